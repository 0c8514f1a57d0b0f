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
* ``compose`` — ``docker compose -p PROJECT -f GEN/compose.yaml up -d --remove-orphans``,
  then ``up -d --no-deps --force-recreate`` for the services whose image, node, parameters
  or remappings changed (Compose does not restart a container when only a mounted file
  changed).  Hardware steps are for a person: they are listed, never run.
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


class Enactor:
    name: ClassVar[str]
    #: Runs commands that change the robot.
    acts: ClassVar[bool] = False

    def __init__(self, options: Mapping[str, Any] | None = None) -> None:
        self.options = dict(options or {})

    def plan(self, project: str, folder: Path, diff: GroundDiff | None) -> Enacted:
        """The commands that bring the robot to ``folder``'s generation."""
        compose = str(folder.resolve() / "compose.yaml")  # absolute: the commands run inside the folder
        base = [self.options.get("docker", "docker"), "compose", "-p", project, "-f", compose]
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
        for argv in done.commands:
            out = _run(argv, folder, timeout)
            done.outputs.append(out)
            if out["exit"] != 0:
                raise EnactError(f"{' '.join(argv)} failed (exit {out['exit']}): {out['stderr'][-500:]}")
        done.ran = True
        return done


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
