"""The machine the figures were measured on: processor, cores, Python, Java and ENHSP."""

from __future__ import annotations

import os
import platform
import shutil
import subprocess


def cpu_text() -> str:
    """The processor model, the core count and the Python version (also used by the scripts
    in benchmarks/)."""
    model = platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            model = next(l.split(":", 1)[1].strip() for l in fh if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{model}, {os.cpu_count()} cores, Python {platform.python_version()}"


def machine() -> str:
    java = "?"
    exe = shutil.which("java")
    if exe:
        try:
            out = subprocess.run([exe, "-version"], capture_output=True, text=True, timeout=30)
            java = (out.stderr or out.stdout).splitlines()[0]
        except (OSError, subprocess.SubprocessError, IndexError):
            pass
    try:
        from importlib.metadata import version

        enhsp = f"up-enhsp {version('up-enhsp')}"
    except Exception:
        enhsp = "up-enhsp ?"
    return f"{cpu_text()}, {java}, {enhsp}"
