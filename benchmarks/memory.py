"""Peak memory of every example query: each command the golden answers record
(tests/golden/record.py) run as a fresh ``python -m catc`` process, its peak resident set
size read from the kernel when it ends (``os.wait4``: ``ru_maxrss``, the figure
``/usr/bin/time -v`` prints as "Maximum resident set size").

Prints a Markdown table (the largest first), the median and the largest, and the command
that produced it; docs/limits.md quotes the result.

    python benchmarks/memory.py [--only TEXT]... [--top N]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "tests" / "golden")]

import record  # noqa: E402  (tests/golden/record.py: every example's commands)


def peak_mb(argv: list[str], out_dir: Path) -> tuple[float, int]:
    """(peak RSS in MB, exit code) of ``python -m catc ARGV`` in a fresh process."""
    argv = [str(out_dir / "out") if a == "{out}" else a for a in argv]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "compiler"), str(ROOT)])}
    proc = subprocess.Popen(
        [sys.executable, "-m", "catc", *argv],
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return usage.ru_maxrss / 1024, proc.returncode


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", action="append", default=[], help="keep commands whose key contains TEXT")
    ap.add_argument("--top", type=int, default=15, help="rows of the table (the largest)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for key, argv in record.commands():
            if args.only and not any(t in key for t in args.only):
                continue
            mb, code = peak_mb(list(argv), Path(tmp))
            rows.append((mb, key, code))
            print(f"{mb:7.1f} MB  exit {code}  {key}", file=sys.stderr)
    rows.sort(reverse=True)
    print(f"command: python benchmarks/memory.py{''.join(f' --only {t}' for t in args.only)}")
    print()
    print("| peak RSS (MB) | example and query | exit |")
    print("|---:|---|---:|")
    for mb, key, code in rows[: args.top]:
        print(f"| {mb:.0f} | {key} | {code} |")
    sizes = [mb for mb, _, _ in rows]
    print()
    print(
        f"{len(rows)} commands: median {statistics.median(sizes):.0f} MB, largest {max(sizes):.0f} MB "
        f"({rows[0][1]}), smallest {min(sizes):.0f} MB"
    )


if __name__ == "__main__":
    main()
