"""Enacting a composition: its artifacts as a generation folder, then an enactor.

A generation is ``STATE/generations/NNNNNN/``: what ``catc ground`` writes (instructions,
Compose file, ROS 2 parameters, behaviour tree, manifest) plus ``decision.json``.  It is
written into a temporary folder beside it, every file and the folder synced to disk, then
renamed into place and the parent folder synced: a generation folder is complete or absent,
never half-written.  Writing a generation that exists already checks it against its
manifest and leaves it alone (enacting again after a crash is idempotent).
``STATE/current`` is a symbolic link to the deployed generation, swapped atomically.

Enactors (a registry: one class each):

* ``dry`` — runs nothing; says what would be run.  The default.
* ``compose`` — ``docker compose -p PROJECT -f GEN/compose.yaml --profile P... up -d
  --remove-orphans`` (every profile the generation's services are in: a service in a profile
  that is not active is not started, and Compose says "no service selected" and exits 0),
  then ``up -d --no-deps --force-recreate`` for the services whose image, node, parameters
  or remappings changed (Compose does not restart a container when only a mounted file
  changed).  Then it asks ``ps --all --format json`` until every service of the generation
  is running (or has exited 0, a one-shot service) — ``ready`` seconds at most, 60 by
  default; otherwise the enactment fails (E1011) and the deployed generation stays.  A
  missing Compose plugin is said as such (``docker compose version`` is asked first).
  Hardware steps are for a person: they are listed, never run.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from catc.api import diff_artifacts, write_files

if TYPE_CHECKING:  # pragma: no cover
    from catc.api import GroundDiff

MANIFEST = "manifest.json"


class EnactError(RuntimeError):
    pass


def generation_name(generation: int) -> str:
    return f"{generation:06d}"


def _fsync_dir(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def complete(folder: Path) -> bool:
    """Every file the manifest names is there with its hash."""
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        return all(
            hashlib.sha256((folder / name).read_bytes()).hexdigest() == entry["sha256"]
            for name, entry in manifest["artifacts"].items()
        )
    except (OSError, ValueError, KeyError, TypeError):
        return False


def differing(folder: Path) -> list[str]:
    """The files of a generation that differ from its manifest or are missing (the manifest
    itself when it cannot be read)."""
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        artifacts = manifest["artifacts"].items()
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return [MANIFEST]
    out = []
    for name, entry in artifacts:
        try:
            same = hashlib.sha256((folder / name).read_bytes()).hexdigest() == entry["sha256"]
        except (OSError, KeyError, TypeError):
            same = False
        if not same:
            out.append(name)
    return out


def write_generation(
    root: Path, generation: int, files: Mapping[str, bytes], manifest: Mapping[str, Any], extra: Mapping[str, Any],
    crash: Any = None,
) -> Path:  # fmt: skip
    """The generation folder, written atomically (see the module's description)."""
    root.mkdir(parents=True, exist_ok=True)
    final = root / generation_name(generation)
    if final.exists():
        if complete(final):
            return final
        shutil.rmtree(final)  # cannot happen through rename; a hand-made folder is replaced
    for stale in root.glob(f".tmp-{generation_name(generation)}-*"):
        shutil.rmtree(stale, ignore_errors=True)
    tmp = root / f".tmp-{generation_name(generation)}-{os.getpid()}"
    tmp.mkdir()
    names = list(files)
    write_files(tmp, {n: files[n] for n in names[: len(names) // 2]}, dict(manifest), durable=True)
    if crash is not None:
        crash("mid-artifacts")
    write_files(tmp, dict(files), dict(manifest), durable=True)
    (tmp / "decision.json").write_text(json.dumps(extra, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    with open(tmp / "decision.json", "rb") as fh:
        os.fsync(fh.fileno())
    _fsync_dir(tmp)
    os.rename(tmp, final)
    _fsync_dir(root)
    return final


def point_current(state: Path, folder: Path) -> None:
    """``STATE/current`` → ``folder``, swapped atomically."""
    link = state / "current"
    tmp = state / f".current-{os.getpid()}"
    if tmp.is_symlink() or tmp.exists():
        tmp.unlink()
    os.symlink(os.path.relpath(folder, state), tmp)
    os.replace(tmp, link)
    _fsync_dir(state)


def read_files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}


def diff_generations(old: Path | None, new: Path) -> GroundDiff | None:
    if old is None or not complete(old):
        return None
    return diff_artifacts(read_files(old), read_files(new))


# ---------------------------------------------------------------- enactors


@dataclass
class Enacted:
    commands: list[list[str]] = field(default_factory=list)
    ran: bool = False
    outputs: list[dict[str, Any]] = field(default_factory=list)
    hardware: dict[str, list[str]] = field(default_factory=dict)
    diff: dict[str, Any] | None = None

    def to_json(self) -> dict[str, Any]:
        return {"commands": self.commands, "ran": self.ran, "outputs": self.outputs, "hardware": self.hardware,
                "diff": self.diff}  # fmt: skip


def compose_services(folder: Path) -> tuple[list[str], list[str]]:
    """(the services of the generation's compose.yaml, the profiles they are in)."""
    import yaml

    doc = yaml.safe_load((folder / "compose.yaml").read_text(encoding="utf-8")) or {}
    services = doc.get("services") or {}
    profiles = sorted({p for s in services.values() for p in (s.get("profiles") or [])})
    return list(services), profiles


class Enactor:
    name: ClassVar[str]
    #: Runs commands that change the robot.
    acts: ClassVar[bool] = False

    def __init__(self, options: Mapping[str, Any] | None = None) -> None:
        self.options = dict(options or {})

    def compose(self) -> list[str]:
        """The Compose command: ``enactor.compose`` (e.g. ``["docker-compose"]``), else
        ``DOCKER compose``."""
        given = self.options.get("compose")
        if given:
            return [given] if isinstance(given, str) else list(given)
        return [self.options.get("docker", "docker"), "compose"]

    def base(self, project: str, folder: Path) -> list[str]:
        compose = str(folder.resolve() / "compose.yaml")  # absolute: the commands run inside the folder
        _, profiles = compose_services(folder)
        return [*self.compose(), "-p", project, "-f", compose, *(a for p in profiles for a in ("--profile", p))]

    def plan(self, project: str, folder: Path, diff: GroundDiff | None) -> Enacted:
        """The commands that bring the robot to ``folder``'s generation."""
        base = self.base(project, folder)
        commands = [[*base, "up", "-d", "--remove-orphans"]]
        if diff is not None and diff.recreate:
            commands.append([*base, "up", "-d", "--no-deps", "--force-recreate", *diff.recreate])
        hardware = {"unmount": list(diff.unmount), "mount": list(diff.mount)} if diff is not None else {}
        as_json: dict[str, Any] | None = None
        if diff is not None:
            as_json = {k: list(getattr(diff, k)) for k in ("added", "removed", "unmount", "mount", "stop", "start",
                                                          "recreate")}  # fmt: skip
            as_json["tree_changed"] = diff.tree_changed
        return Enacted(commands, False, [], hardware, as_json)

    def enact(self, project: str, folder: Path, diff: GroundDiff | None) -> Enacted:
        raise NotImplementedError


class DryEnactor(Enactor):
    name = "dry"

    def enact(self, project: str, folder: Path, diff: GroundDiff | None) -> Enacted:
        return self.plan(project, folder, diff)


class ComposeEnactor(Enactor):
    name = "compose"
    acts = True

    def enact(self, project: str, folder: Path, diff: GroundDiff | None) -> Enacted:
        done = self.plan(project, folder, diff)
        timeout = float(self.options.get("timeout", 600))
        self._check_plugin(folder, timeout)
        for argv in done.commands:
            out = _run(argv, folder, timeout)
            done.outputs.append(out)
            if out["exit"] != 0:
                raise EnactError(f"{' '.join(argv)} failed (exit {out['exit']}): {out['stderr'][-500:]}")
        done.outputs.append(self._wait_running(project, folder, timeout))
        done.ran = True
        return done

    def _check_plugin(self, folder: Path, timeout: float) -> None:
        argv = [*self.compose(), "version"]
        out = _run(argv, folder, timeout)
        if out["exit"] != 0:
            raise EnactError(
                f"Docker Compose v2 is not available: `{' '.join(argv)}` failed (exit {out['exit']}: "
                f"{(out['stderr'] or out['stdout']).strip()[-300:]}); install the compose plugin (Debian: "
                'docker-compose-plugin) or name a Compose binary in config.toml: [enactor] compose = "docker-compose"'
            )

    def _wait_running(self, project: str, folder: Path, timeout: float) -> dict[str, Any]:
        """Ask ``ps`` until every service runs (or exited 0), ``ready`` seconds at most."""
        import time

        expected, _ = compose_services(folder)
        ready = float(self.options.get("ready", 60))
        argv = [*self.base(project, folder), "ps", "--all", "--format", "json"]
        start = time.monotonic()
        while True:
            out = _run(argv, folder, timeout)
            if out["exit"] != 0:
                raise EnactError(f"{' '.join(argv)} failed (exit {out['exit']}): {out['stderr'][-500:]}")
            states = ps_states(out["stdout"])
            bad = not_running(expected, states)
            if not bad:
                return out
            if time.monotonic() - start >= ready:
                raise EnactError(f"after {ready:g} s not every service runs: {'; '.join(bad)}")
            time.sleep(min(1.0, ready / 10))


def ps_states(text: str) -> dict[str, dict[str, Any]]:
    """``docker compose ps --format json`` by service: one JSON array (Compose before 2.21)
    or one object a line (since)."""
    text = text.strip()
    if not text:
        return {}
    try:
        doc = json.loads(text)
        rows = doc if isinstance(doc, list) else [doc]
    except ValueError:
        rows = [json.loads(line) for line in text.splitlines() if line.strip()]
    return {str(r.get("Service")): r for r in rows if isinstance(r, dict)}


def not_running(expected: Sequence[str], states: Mapping[str, Mapping[str, Any]]) -> list[str]:
    """Each expected service that is neither running nor exited 0, said why."""
    bad = []
    for name in expected:
        row = states.get(name)
        if row is None:
            bad.append(f"{name}: not created")
            continue
        state = str(row.get("State", "")).lower()
        if state == "running" or (state == "exited" and row.get("ExitCode") == 0):
            continue
        bad.append(f"{name}: {state or 'unknown'}" + (f" (exit {row.get('ExitCode')})" if state == "exited" else ""))
    return bad


def _run(argv: Sequence[str], cwd: Path, timeout: float) -> dict[str, Any]:
    try:
        proc = subprocess.run(list(argv), cwd=cwd, capture_output=True, timeout=timeout, stdin=subprocess.DEVNULL)
    except FileNotFoundError:
        return {"argv": list(argv), "exit": 127, "stdout": "", "stderr": f"{argv[0]}: not found"}
    except subprocess.TimeoutExpired:
        return {"argv": list(argv), "exit": -1, "stdout": "", "stderr": f"timed out after {timeout:g} s"}
    return {
        "argv": list(argv),
        "exit": proc.returncode,
        "stdout": proc.stdout.decode("utf-8", "replace")[-2000:],
        "stderr": proc.stderr.decode("utf-8", "replace")[-2000:],
    }


#: Enactors by name: a new one is a class here and an entry in this table.
ENACTORS: dict[str, type[Enactor]] = {cls.name: cls for cls in (DryEnactor, ComposeEnactor)}
