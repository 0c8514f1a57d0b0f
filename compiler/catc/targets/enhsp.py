"""Run the ENHSP numeric planner (shipped as ``enhsp.jar`` by the PyPI package ``up-enhsp``)
on exported PDDL and read its plan back as ground action names.

Needs Java (17 or newer) on PATH and the ``baselines`` extra
(``pip install 'catc-lang[baselines]'``).  ENHSP's own ``-timeout`` does nothing, so the
process is wrapped in a subprocess timeout.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

from catc.targets import BASELINES_HINT


def lift_memory_limit() -> None:
    """In a planner's process (``preexec_fn``): lift the soft address-space limit the catc
    process put on itself (``--memory``): a Java virtual machine reserves far more address
    space than it uses, and the planner's memory is its own option (``-Xmx``)."""
    try:
        import resource

        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        resource.setrlimit(resource.RLIMIT_AS, (hard, hard))
    except (ImportError, ValueError, OSError):  # pragma: no cover - not POSIX, or nothing to lift
        pass


JAVA_HINT = "install Java 17 (e.g. apt-get install -y openjdk-17-jre-headless)"


class BaselineMissing(RuntimeError):
    """Java or the ENHSP jar is not installed; the message says what to install."""


def enhsp_jar() -> Path:
    try:
        import up_enhsp
    except ImportError:
        raise BaselineMissing(f"ENHSP is not installed (package up-enhsp); {BASELINES_HINT}") from None
    jar = Path(up_enhsp.__file__).parent / "ENHSP" / "enhsp.jar"
    if not jar.is_file():
        raise BaselineMissing(f"enhsp.jar not found at {jar}; {BASELINES_HINT}")
    return jar


def java() -> str:
    exe = shutil.which("java")
    if exe is None:
        raise BaselineMissing(f"java is not on PATH; {JAVA_HINT}")
    return exe


def available() -> str | None:
    """None when ENHSP can run, else the reason (naming what to install)."""
    try:
        java()
        enhsp_jar()
    except BaselineMissing as exc:
        return str(exc)
    return None


@dataclass
class EnhspResult:
    status: str  # "sat", "unsat", "timeout", "error"
    actions: list[str] = field(default_factory=list)
    metric: float | None = None
    planning_ms: int | None = None
    wall: float = 0.0
    output: str = ""


_PLAN_LINE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*:\s*\(([^()]*)\)")


def parse_output(text: str) -> EnhspResult:
    actions = []
    for line in text.splitlines():
        m = _PLAN_LINE.match(line)
        if m:
            actions.append(m.group(2).strip().split()[0].lower())
    if "Problem Solved" in text:
        status = "sat"
    elif "FileNotFoundException" in text or "ParseException" in text:  # it says "Unsolvable" after these too
        status = "error"
    elif "Problem unsolvable" in text or "Unsolvable Problem" in text or "Problem Detected as Unsolvable" in text:
        status = "unsat"
    else:
        status = "error"
    metric = None
    m = re.search(r"Metric \(Search\):\s*([-0-9.eE]+)", text)
    if m:
        metric = float(m.group(1))
    ms = re.search(r"Planning Time \(msec\):\s*(\d+)", text)
    return EnhspResult(
        status, actions if status == "sat" else [], metric, int(ms.group(1)) if ms else None, output=text
    )


def run_enhsp(
    domain: str | Path, problem: str | Path, *, planner: str = "sat-hadd", timeout: float = 60.0, memory: str = "2g"
) -> EnhspResult:
    """Run ENHSP in place (its ``libs/`` folder sits beside the jar)."""
    exe = java()  # Java first: it is the prerequisite of the jar
    jar = enhsp_jar()
    # absolute paths: ENHSP runs in the jar's folder
    cmd = [
        exe,
        f"-Xmx{memory}",
        "-jar",
        str(jar),
        "-o",
        str(Path(domain).resolve()),
        "-f",
        str(Path(problem).resolve()),
        "-planner",
        planner,
    ]
    start = time.perf_counter()
    try:
        proc = subprocess.run(
            cmd, capture_output=True, text=True, timeout=timeout, cwd=jar.parent, preexec_fn=lift_memory_limit
        )
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        return EnhspResult("timeout", wall=time.perf_counter() - start, output=out)
    res = parse_output(proc.stdout + "\n" + proc.stderr)
    res.wall = time.perf_counter() - start
    return res
