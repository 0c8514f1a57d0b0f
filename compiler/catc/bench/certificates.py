"""The certificates table of ``catc bench`` (issue 31): every final UNSAT of the examples
(examples/*/expect.toml), the wall time of ``catc solve --certificate`` (the answer, with
its certificate written) beside that of ``catc certify`` (both checkers on every
obligation, one process per checker), each a process of its own, median of the bench's
runs; whether it was certified, and by what."""

from __future__ import annotations

import json
import statistics
import subprocess
import time
import tomllib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from catc.bench.runners import CATC


def no_answers(examples: Path) -> Iterator[tuple[str, str | None]]:
    """(file relative to ``examples``, problem) of every case expect.toml records as a final UNSAT."""
    for expect in sorted(examples.glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            if case.get("status") == "unsat" and case.get("final_unsat"):
                yield f"{expect.parent.name}/{case['file']}", case.get("problem")


def _timed(cmd: list[str], timeout: float) -> tuple[float, subprocess.CompletedProcess[str] | None]:
    start = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return time.perf_counter() - start, None
    return time.perf_counter() - start, proc


def certificate_row(
    examples: Path, file: str, problem: str | None, runs: int, timeout: float, work: Path
) -> dict[str, Any]:
    """One no-answer: answer and certification walls (interleaved trials), the method and status."""
    path = str(examples / file)
    chosen = ["--problem", problem] if problem else []
    cert = work / (file.replace("/", "-") + (f"-{problem}" if problem else "") + ".certificate.json")
    answer: list[float] = []
    certify: list[float] = []
    doc: dict[str, Any] = {}
    for _ in range(runs):
        wall, proc = _timed([*CATC, "solve", path, *chosen, "--certificate", str(cert)], timeout)
        answer.append(wall)
        if proc is None or not cert.exists():
            return {"problem": file, "name": problem, "status": "no certificate", "answer": answer, "certify": []}
        wall, proc = _timed([*CATC, "certify", path, *chosen, str(cert), "--json"], timeout)
        certify.append(wall)
        try:
            doc = json.loads(proc.stdout) if proc is not None else {"status": "timeout"}
        except json.JSONDecodeError:
            doc = {"status": "error"}
    return {
        "problem": file,
        "name": problem,
        "status": doc.get("status", "error"),
        "method": doc.get("method"),
        "producer": doc.get("producer"),
        "obligations": len(doc.get("obligations", [])),
        "checked_by": sorted({c for o in doc.get("obligations", []) for c in o.get("proved_by", [])}),
        "answer": answer,
        "certify": certify,
    }


def certificate_rows(
    examples: Path, runs: int, timeout: float, work: Path, log: Callable[[str], None], keep: tuple[str, ...] = ("",)
) -> list[dict]:
    """The rows of the no-answers whose path contains one of ``keep``."""
    rows = []
    for file, problem in no_answers(examples):
        if not any(k in file for k in keep):
            continue
        log(f"certificates: {file}{' ' + problem if problem else ''}")
        rows.append(certificate_row(examples, file, problem, runs, timeout, work))
    return rows


def certificate_table(rows: list[dict[str, Any]], runs: int) -> list[str]:
    out = [
        "### Certificates of the no-answers",
        "",
        f"Every final UNSAT of the examples: `catc solve --certificate` (the answer and its certificate) and "
        f"`catc certify` (z3 and cvc5 on every obligation: in catc's process for a small certificate, else one process per checker), wall seconds "
        f"of each process, median of {runs} interleaved trial(s); the ratio is certify over answer (target ≤ 2).",
        "",
        "| problem | method (producer) | obligations | status | proved by | answer wall (s) | certify wall (s) | ratio |",
        "|---|---|---:|---|---|---:|---:|---:|",
    ]
    for r in rows:
        a = statistics.median(r["answer"]) if r["answer"] else None
        c = statistics.median(r["certify"]) if r["certify"] else None
        ratio = f"{c / a:.1f}×" if a and c else "—"
        name = r["problem"] + (f" ({r['name']})" if r["name"] else "")
        out.append(
            f"| {name} | {r.get('method') or '—'} ({r.get('producer') or '—'}) | {r.get('obligations', 0)} | "
            f"{r['status']} | {', '.join(r.get('checked_by', [])) or '—'} | "
            f"{'—' if a is None else f'{a:.2f}'} | {'—' if c is None else f'{c:.2f}'} | {ratio} |"
        )
    return [*out, ""]
