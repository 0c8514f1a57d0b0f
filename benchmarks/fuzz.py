"""Coverage-guided fuzzing of the whole pipeline with atheris (issue 15, item 2).

Parse → check → fmt → encode → solve → validate → export, on inputs that libFuzzer's
coverage-guided mutations make from every ``.cat`` file of the repository (and, for a
problem whose domain lives in another file of its folder, the two files joined, so that
mutants reach the solver).  What each input must satisfy is :mod:`fuzz_oracle`; a
dictionary of the language's keywords and operators (from :mod:`catgrammar.symbols`) steers
the mutations towards the grammar.

    python benchmarks/fuzz.py [--inputs 100000] [--seconds S] [--timeout 2] [--jobs 1] [--seed N]
                              [--state DIR] [--allow-known]
    python benchmarks/fuzz.py --summarize --state DIR

Mutations are libFuzzer's three times in ten and structural (:func:`structural_mutation`)
seven times in ten.  Each input's solve runs with ``timeout`` as ``catc solve --timeout``
(a deadline over every horizon); the oracle's watchdog stops any stage at ``timeout + 1 + 2``
s, and libFuzzer's own ``-timeout`` and ``-rss_limit_mb`` stop a worker stuck in C code or out
of memory, which this script then records (with the input libFuzzer saved) and restarts.
``--jobs`` workers run side by side on one corpus.  At the end every hang is replayed in an
uninstrumented process (atheris's instrumentation slows Python many times) and counts only if
it recurs; findings in the classes issue 15 hands to the limits branch are labelled.  The
Markdown summary gives the command, the inputs, one row per category (every one must be 0)
and each distinct finding with the file holding its input; the exit code is 1 when a finding
is listed (with ``--allow-known``: one outside the labelled classes).  ``--state`` keeps the
corpus, the findings and the worker logs.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import os
import random
import re
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(ROOT), str(ROOT / "compiler"), str(HERE)]

SKIP_PARTS = {"node_modules", ".git", "build", "dist", ".pytest_cache", "mutants", ".venv"}
_DEFINES = re.compile(r"\(\s*define\s*\(\s*(domain|problem)\b")


# ---------------------------------------------------------------- seeds and dictionary


def seeds() -> dict[str, bytes]:
    """name → text: every .cat file of the repository, and each problem file joined after
    the domain files of its folder (a mutant of that reaches the solver on its own)."""
    out: dict[str, bytes] = {}
    files = [p for p in sorted(ROOT.rglob("*.cat")) if not SKIP_PARTS & set(p.relative_to(ROOT).parts)]
    for p in files:
        out[str(p.relative_to(ROOT))] = p.read_bytes()
    for p in files:
        kinds = set(_DEFINES.findall(p.read_text(errors="replace")))
        if kinds != {"problem"}:
            continue
        domains = [q for q in files if q.parent == p.parent and "domain" in _DEFINES.findall(q.read_text())]
        if domains:
            name = f"{p.relative_to(ROOT)}+domains"
            out[name] = b"\n".join(q.read_bytes() for q in domains) + b"\n" + p.read_bytes()
    return out


def dictionary() -> list[str]:
    """libFuzzer dictionary entries: the language's words, keywords and operators."""
    from catgrammar import symbols

    words = {"(", ")", "{", "}", "(define", "(domain", "(problem", "1e99", "1e-9", "0.5", "-1", "*", '"', " - "}
    for group in symbols.all_keywords().values():
        words.update(group)
        words.update(f"({w}" for w in group if not w.startswith(":"))
    return sorted(words)


def _dict_file(words: list[str]) -> str:
    return "".join(f'"{w.replace(chr(92), chr(92) * 2).replace(chr(34), chr(92) + chr(34))}"\n' for w in words)


# ---------------------------------------------------------------- the worker (atheris)


def worker(state: Path, timeout: float, libfuzzer_args: list[str]) -> None:
    """The fuzzing process: atheris over catc's instrumented code, writing its counts to
    ``state/stats.json`` after each input and its findings to ``state/findings.jsonl``."""
    import atheris

    with atheris.instrument_imports(include=["catc", "catgrammar"]):
        import fuzz_oracle

        _import_everything()
    from catc.interfaces.entry import configure_process

    configure_process()
    stats_path, findings_path = state / "stats.json", state / "findings.jsonl"
    stats = json.loads(stats_path.read_text()) if stats_path.exists() else {"inputs": 0}
    work = Path(tempfile.mkdtemp(prefix="catc-fuzz-"))

    def one_input(data: bytes) -> None:
        reached: list[str] = []
        flavors = (("enhsp",), ("smtplan",))[zlib.crc32(data) % 2]  # one export a input: half the cost
        findings = fuzz_oracle.examine(data, work, timeout=timeout, reached=reached, flavors=flavors)
        stats["inputs"] += 1
        for what in reached:
            stats.setdefault("reached", {})[what] = stats.get("reached", {}).get(what, 0) + 1
        for f in findings:
            stats[f.category] = stats.get(f.category, 0) + 1
            _record(state, findings_path, f.category, f.stage, f.detail, data)
        tmp = stats_path.with_suffix(".tmp")
        tmp.write_text(json.dumps(stats))
        os.replace(tmp, stats_path)

    def mutate(data: bytes, max_size: int, seed: int) -> bytes:
        rng = random.Random(seed)
        if rng.random() < 0.3:
            return atheris.Mutate(data, max_size)
        return structural_mutation(data, rng)[:max_size]

    atheris.Setup([sys.argv[0], *libfuzzer_args], one_input, custom_mutator=mutate)
    atheris.Fuzz()


# ---------------------------------------------------------------- structural mutations

_TOKEN = re.compile(rb'\(|\)|"(?:[^"\\]|\\.)*"|;[^\n]*|[^\s()";]+')
_NUMBER = re.compile(rb"-?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
#: Operators swapped for one of their own family (a mutant that still parses and often checks).
_FAMILIES = [
    [b">=", b"<=", b"<", b">", b"="],
    [b"increase", b"decrease", b"assign"],
    [b"add", b"remove"],
    [b"and", b"or"],
    [b"+", b"-", b"*", b"min", b"max"],
    [b"minimize", b"maximize"],
    [b"int", b"real", b"bool"],
]
_NUMBERS = [b"0", b"1", b"-1", b"2", b"3", b"0.5", b"100", b"(/ 1 3)", b"1e-9", b"1e9", b"1e99", b"-0", b"*"]


def structural_mutation(data: bytes, rng: random.Random) -> bytes:
    """One mutation at the level of tokens and balanced parentheses, which keeps many
    inputs parseable (libFuzzer's byte mutations rarely do): a number or an operator
    replaced by a sibling of its kind, a name by another name of the file, a balanced
    expression deleted or duplicated, a comparison wrapped in ``(not ...)``."""
    toks = [(m.start(), m.end()) for m in _TOKEN.finditer(data) if data[m.start()] not in b';"']
    op = rng.randrange(6)
    if op == 0:
        picks = [i for i, (a, b) in enumerate(toks) if _NUMBER.fullmatch(data[a:b])]
    elif op == 1:
        picks = [i for i, (a, b) in enumerate(toks) if any(data[a:b] in f for f in _FAMILIES)]
    elif op == 2:
        picks = [i for i, (a, b) in enumerate(toks) if re.fullmatch(rb"[a-zA-Z_][\w-]*", data[a:b])]
    else:  # an expression: "(" not opening a section or a definition
        picks = [i for i, (a, b) in enumerate(toks[:-1]) if data[a:b] == b"(" and data[toks[i + 1][0]] not in b":("]
    if not picks:
        return data
    i = rng.choice(picks)
    a, b = toks[i]
    if op == 0:
        return data[:a] + rng.choice(_NUMBERS) + data[b:]
    if op == 1:
        return data[:a] + rng.choice(next(f for f in _FAMILIES if data[a:b] in f)) + data[b:]
    if op == 2:
        x, y = toks[rng.choice(picks)]
        return data[:a] + data[x:y] + data[b:]
    start, end = _balanced(data, toks, i)
    if op == 3:
        return data[:start] + data[end:]
    if op == 4:
        return data[:end] + b" " + data[start:end] + data[end:]
    return data[:start] + b"(not " + data[start:end] + b")" + data[end:]


def _balanced(data: bytes, toks: list[tuple[int, int]], i: int) -> tuple[int, int]:
    """The byte range of the balanced expression starting at token ``i`` (the token alone
    when it is not an opening parenthesis)."""
    a, b = toks[i]
    if data[a:b] != b"(":
        return a, b
    depth = 0
    for x, y in toks[i:]:
        depth += {b"(": 1, b")": -1}.get(data[x:y], 0)
        if depth == 0:
            return a, y
    return a, len(data)


def _import_everything() -> None:
    """Import catc's and catgrammar's modules now, so that atheris instruments the ones
    the pipeline imports lazily (the exporters, the queries)."""
    import importlib
    import pkgutil

    import catc
    import catgrammar

    for package in (catc, catgrammar):
        for mod in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            if mod.name.startswith(("catc.bench", "catc.interfaces.lsp")) or mod.name.endswith("__main__"):
                continue
            with contextlib.suppress(ImportError):  # an optional extra that is not installed
                importlib.import_module(mod.name)


def _record(state: Path, log: Path, category: str, stage: str, detail: str, data: bytes) -> None:
    digest = hashlib.sha1(data).hexdigest()[:12]
    keep = state / "findings" / f"{digest}.cat"
    keep.parent.mkdir(exist_ok=True)
    keep.write_bytes(data)
    entry = {"category": category, "stage": stage, "detail": detail, "input": str(keep)}
    with log.open("a") as fh:
        fh.write(json.dumps(entry) + "\n")


# ---------------------------------------------------------------- the orchestrator


def _prepare(state: Path) -> tuple[Path, Path, Path]:
    seed_dir, corpus, dict_path = state / "seeds", state / "corpus", state / "cat.dict"
    seed_dir.mkdir(parents=True, exist_ok=True)
    corpus.mkdir(exist_ok=True)
    for name, data in seeds().items():
        (seed_dir / name.replace("/", "__")).write_bytes(data)
    dict_path.write_text(_dict_file(dictionary()))
    return seed_dir, corpus, dict_path


def _libfuzzer_args(
    args: argparse.Namespace,
    job: Path,
    seed_dir: Path,
    corpus: Path,
    dict_path: Path,
    runs: int,
    left: float,
    seed: int | None,
) -> list[str]:
    max_len = max(len(p.read_bytes()) for p in seed_dir.iterdir()) + 1024
    per_input = int(6 * (args.timeout + 3)) + 10  # every stage at its watchdog, and the start
    out = [
        f"-runs={runs}",
        f"-max_len={max_len}",
        f"-timeout={per_input}",
        f"-rss_limit_mb={args.memory}",
        f"-dict={dict_path}",
        f"-artifact_prefix={job}/artifacts/",
        "-print_final_stats=1",
        str(corpus),
        str(seed_dir),
    ]
    if left < float("inf"):
        out.insert(1, f"-max_total_time={max(1, int(left))}")
    if seed is not None:
        out.insert(1, f"-seed={seed}")
    return out


def _run_worker(args: argparse.Namespace, state: Path, lf_args: list[str], log: Path) -> int:
    cmd = [sys.executable, __file__, "--worker", "--state", str(state), "--timeout", str(args.timeout), "--", *lf_args]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "compiler"), str(HERE)])}
    with log.open("ab") as fh:
        return subprocess.run(cmd, stdout=fh, stderr=subprocess.STDOUT, env=env).returncode


def _died(state: Path, log: Path, rc: int) -> None:
    """Record a worker that libFuzzer stopped (timeout, out of memory) or that crashed."""
    text = log.read_text(errors="replace")[-20000:]
    artifacts = re.findall(r"Test unit written to (\S+)", text)
    reason = re.findall(r"==\d+== ERROR: libFuzzer: ([^\n]+)", text)
    detail = f"exit {rc}: {reason[-1] if reason else 'no libFuzzer report'}"
    data = Path(artifacts[-1]).read_bytes() if artifacts and Path(artifacts[-1]).exists() else b""
    from fuzz_oracle import DIED

    _record(state, state / "findings.jsonl", DIED, "process", detail, data)
    stats_path = state / "stats.json"
    stats = json.loads(stats_path.read_text()) if stats_path.exists() else {"inputs": 0}
    stats[DIED] = stats.get(DIED, 0) + 1
    stats_path.write_text(json.dumps(stats))


def _fuzz_job(
    args: argparse.Namespace, job: Path, shared: tuple[Path, Path, Path], inputs: int, seed: int | None
) -> None:
    """One worker after another in ``job`` until it has run ``inputs`` inputs (a worker that
    dies is recorded and replaced)."""
    seed_dir, corpus, dict_path = shared
    (job / "artifacts").mkdir(parents=True, exist_ok=True)
    start, restarts, before = time.monotonic(), 0, -1
    stats_path = job / "stats.json"
    while True:
        done = json.loads(stats_path.read_text())["inputs"] if stats_path.exists() else 0
        left = args.seconds - (time.monotonic() - start)
        if done >= inputs or left <= 0 or restarts > args.max_restarts or done == before:
            break  # (done == before: the last worker died without running an input)
        before = done
        lf_args = _libfuzzer_args(args, job, seed_dir, corpus, dict_path, inputs - done, left, seed)
        rc = _run_worker(args, job, lf_args, job / "worker.log")
        if rc == 0:
            break
        _died(job, job / "worker.log", rc)
        restarts += 1


def fuzz(args: argparse.Namespace) -> dict:
    """Run ``args.jobs`` workers side by side (one corpus) until ``args.inputs`` inputs in all
    or ``args.seconds`` have gone by; their counts and findings are gathered in ``state``."""
    import threading

    state = Path(args.state)
    shared = _prepare(state)
    start = time.monotonic()
    share = -(-args.inputs // args.jobs)
    threads = [
        threading.Thread(
            target=_fuzz_job,
            args=(args, state / f"job-{j}", shared, share, None if args.seed is None else args.seed + j),
        )
        for j in range(args.jobs)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    stats = gather(state)
    stats["seconds"] = time.monotonic() - start
    (state / "stats.json").write_text(json.dumps(stats))
    return stats


def gather(state: Path) -> dict:
    """The counts of every job of ``state`` added up; their findings in ``state/findings.jsonl``
    (a state without jobs, from a run of one worker, is left as it is)."""
    if not any(state.glob("job-*")):
        kept = state / "stats.json"
        return json.loads(kept.read_text()) if kept.exists() else {"inputs": 0}
    total: dict = {"inputs": 0, "reached": {}}
    lines: list[str] = []
    for job in sorted(state.glob("job-*")):
        if (job / "stats.json").exists():
            for key, value in json.loads((job / "stats.json").read_text()).items():
                if key == "reached":
                    for what, n in value.items():
                        total["reached"][what] = total["reached"].get(what, 0) + n
                else:
                    total[key] = total.get(key, 0) + value
        if (job / "findings.jsonl").exists():
            lines += (job / "findings.jsonl").read_text().splitlines()
    (state / "findings.jsonl").write_text("".join(line + "\n" for line in lines))
    return total


#: A horizon past this in a hanging input is issue 15's "unbounded horizons" (Found #4), which
#: the limits work (a checked maximum horizon) closes: labelled, still counted.
HUGE_HORIZON = 10**6
_HORIZON = re.compile(rb"\(\s*:horizon\s+([-+0-9.eE]+)")


def known_class(finding: dict) -> str | None:
    """The issue-15 class of a finding, when it is one handed to the limits branch."""
    detail, stage = finding["detail"], finding["stage"]
    if "Exceeds the limit" in detail:
        return "issue 15 Found #1: a number past Python's int/str digit limit (wt-limits)"
    if stage.startswith("export") and "_theta_values" in detail:
        return "issue 15 Found #6: no cap on ground actions in the export (wt-limits)"
    if finding["category"] == fuzz_oracle_hang() and "validate.py" in detail:
        return "issue 15 Found #5: validation outside the timeout (wt-limits)"
    if finding["input"] and _horizon(Path(finding["input"]).read_bytes()) >= HUGE_HORIZON:
        return "issue 15 Found #4: unbounded horizon (wt-limits)"
    return None


def fuzz_oracle_hang() -> str:
    from fuzz_oracle import HANG

    return HANG


def _horizon(data: bytes) -> float:
    """The largest horizon of the input's problems: a ``(:horizon k)`` as written, or the
    horizon catc derives (the sum of the ``:uses`` limits) when the input checks."""
    best = 0.0
    for text in _HORIZON.findall(data):
        with contextlib.suppress(ValueError, OverflowError):
            best = max(best, float(text))
    with tempfile.TemporaryDirectory() as work:
        from catc.frontend.session import check_files
        from catc.semantics.horizon import default_horizon
        from catgrammar.diagnostics import Diagnostics

        path = Path(work) / "input.cat"
        path.write_bytes(data)
        with contextlib.suppress(Exception):
            _, instances = check_files([str(path)], Diagnostics())
            for inst in instances.values():
                best = max(best, float(default_horizon(inst)))
    return best


def findings_of(state: Path) -> list[dict]:
    """The findings recorded in ``state``, each input's path found again when the state
    folder was moved since."""
    log = state / "findings.jsonl"
    entries = [json.loads(line) for line in log.read_text().splitlines()] if log.exists() else []
    for f in entries:
        if f["input"] and not Path(f["input"]).exists():
            found = sorted(state.rglob(Path(f["input"]).name))
            f["input"] = str(found[0]) if found else ""
    return entries


def confirm(state: Path, timeout: float) -> dict[str, dict]:
    """Replay every input with a hang in an uninstrumented process (atheris's instrumentation
    slows Python code down many times): input → {"confirmed": bool, "known": label}.  A hang
    in a class handed to the limits branch is counted without a replay (its reproducers,
    docs/benchmarks.md, hang outside the fuzzer too)."""
    from fuzz_oracle import HANG

    entries = findings_of(state)
    out: dict[str, dict] = {}
    for f in entries:
        if f["category"] != HANG or f["input"] in out:
            continue
        label = known_class(f)
        if label is not None:
            out[f["input"]] = {"confirmed": True, "known": label}
            continue
        cmd = [sys.executable, str(HERE / "fuzz_oracle.py"), f["input"], "--timeout", str(timeout)]
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), str(ROOT / "compiler"), str(HERE)])}
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
        replay = [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]
        out[f["input"]] = {"confirmed": any(r["category"] == HANG for r in replay), "known": None}
    return out


def summary(args: argparse.Namespace, stats: dict, command: str) -> str:
    from fuzz_oracle import CATEGORIES, HANG
    from solve_bench import machine

    state = Path(args.state)
    replays = confirm(state, args.timeout)
    entries = findings_of(state)
    kept = [f for f in entries if f["category"] != HANG or replays[f["input"]]["confirmed"]]
    counts = {c: sum(1 for f in kept if f["category"] == c) for c in CATEGORIES}
    slow_only = len({f["input"] for f in entries if f["category"] == HANG and not replays[f["input"]]["confirmed"]})
    known = {f["input"] for f in kept if known_class(f)}
    lines = [f"command: {command}", f"machine: {machine()}", ""]
    lines += ["| what | count |", "|---|---:|"]
    lines.append(f"| inputs (atheris {_atheris_version()}, {stats.get('seconds', 0):.0f} s) | {stats['inputs']:,} |")
    lines += [f"| {c} | {counts[c]} |" for c in CATEGORIES]
    reached = stats.get("reached", {})
    if reached:
        lines += ["", "Reached: " + ", ".join(f"{what} {n:,}" for what, n in sorted(reached.items()))]
    lines.append(
        f"Hangs that did not recur in an uninstrumented replay (atheris's instrumentation only): {slow_only} inputs"
    )
    lines.append(f"Inputs with findings in a class issue 15 hands to another branch: {len(known)}")
    seen: set[tuple[str, str, str]] = set()
    if kept:
        lines += ["", "Findings (category, stage, detail, input):"]
    for f in kept:
        key = (f["category"], f["stage"], re.sub(r"\d+(\.\d+)?", "N", f["detail"]))
        if key not in seen:
            seen.add(key)
            label = known_class(f)
            lines.append(
                f"- {f['category']} in {f['stage']}: {f['detail']} — {f['input']}" + (f" [{label}]" if label else "")
            )
    return "\n".join(lines)


def _atheris_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("atheris")
    except PackageNotFoundError:
        return "not installed"


def replay_solve(state: Path, timeout: float, jobs: int) -> int:
    """``catc solve --timeout`` on every corpus input, each a fresh uninstrumented process, ``jobs``
    at a time: a table of exit codes, the slowest walls, and the inputs over ``timeout + 1`` s."""
    from concurrent.futures import ThreadPoolExecutor

    files = sorted(p for p in (state / "corpus").iterdir() if p.is_file())

    def one(path: Path) -> tuple[float, int, Path]:
        with tempfile.TemporaryDirectory() as tmp:
            cat = Path(tmp) / "input.cat"
            cat.write_bytes(path.read_bytes())
            start = time.perf_counter()
            proc = subprocess.run(
                [sys.executable, "-m", "catc", "solve", str(cat), "--timeout", str(timeout)],
                capture_output=True,
                timeout=timeout * 20 + 60,
            )
            return time.perf_counter() - start, proc.returncode, path

    with ThreadPoolExecutor(jobs) as pool:
        results = list(pool.map(one, files))
    codes: dict[int, int] = {}
    for _, code, _ in results:
        codes[code] = codes.get(code, 0) + 1
    slow = [r for r in results if r[0] > timeout + 1]
    walls = sorted(r[0] for r in results)
    print(f"`python benchmarks/fuzz.py --replay-solve {timeout:g} --jobs {jobs} --state DIR`: {len(files):,} inputs\n")
    print("| exit code | inputs |\n|---:|---:|")
    for code in sorted(codes):
        print(f"| {code} | {codes[code]:,} |")
    print(
        f"\nwall: median {walls[len(walls) // 2]:.2f} s, slowest {walls[-1]:.2f} s; over {timeout + 1:g} s: {len(slow)}"
    )
    for wall, code, path in sorted(slow, reverse=True)[:20]:
        print(f"- {path.name}: {wall:.2f} s (exit {code})")
    return 1 if slow or 70 in codes else 0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--inputs", type=int, default=100_000, help="stop after this many inputs")
    ap.add_argument("--seconds", type=float, default=float("inf"), help="stop after this many seconds")
    ap.add_argument("--timeout", type=float, default=2.0, help="catc's --timeout for each input's solve")
    ap.add_argument("--memory", type=int, default=3072, help="libFuzzer's -rss_limit_mb")
    ap.add_argument("--state", help="folder for the corpus, findings and logs (default: a new temporary one)")
    ap.add_argument("--seed", type=int, help="libFuzzer's random seed (job j: seed + j)")
    ap.add_argument("--jobs", type=int, default=1, help="workers side by side, sharing one corpus")
    ap.add_argument("--max-restarts", type=int, default=50, help="give up after this many dead workers")
    ap.add_argument("--summarize", action="store_true", help="print the summary of the run kept in --state")
    ap.add_argument(
        "--allow-known",
        action="store_true",
        help="exit 0 when every finding is in a class issue 15 hands to another branch (labelled in the summary)",
    )
    ap.add_argument(
        "--replay-solve",
        type=float,
        metavar="SECONDS",
        help="run `catc solve --timeout SECONDS` as a process on every input of --state's corpus and "
        "report the slowest (issue 15's bar: within SECONDS + 1)",
    )
    ap.add_argument(
        "--numerals",
        type=int,
        metavar="N",
        help="parse N mutants with other scripts' digits, "
        "numerals and confusable letters (fuzz_unicode_lsp.py; issue 28); exit 1 on a finding",
    )
    ap.add_argument(
        "--lsp-framing",
        type=int,
        metavar="N",
        help="send N random frames to one catc lsp, "
        "a probe after each (fuzz_unicode_lsp.py; issue 28); exit 1 on a finding",
    )
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("libfuzzer", nargs="*", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.numerals is not None or args.lsp_framing is not None:
        import fuzz_unicode_lsp as more

        failed = 0
        if args.numerals is not None:
            failed |= more.report("numerals", more.numerals(args.numerals, args.seed or 0))
        if args.lsp_framing is not None:
            failed |= more.report("lsp-framing", more.lsp_framing(args.lsp_framing, args.seed or 0))
        sys.exit(failed)
    if args.replay_solve is not None:
        sys.exit(replay_solve(Path(args.state), args.replay_solve, max(1, args.jobs)))
    if args.worker:
        worker(Path(args.state), args.timeout, args.libfuzzer)
        return
    if args.summarize:
        kept = Path(args.state) / "stats.json"
        stats = {**(json.loads(kept.read_text()) if kept.exists() else {}), **gather(Path(args.state))}
        command = (
            (Path(args.state) / "command.txt").read_text().strip()
            if (Path(args.state) / "command.txt").exists()
            else "?"
        )
    else:
        args.state = args.state or tempfile.mkdtemp(prefix="catc-fuzz-state-")
        shown = [a for a, prev in zip(sys.argv[1:], ["", *sys.argv[1:]]) if "--state" not in (a.split("=")[0], prev)]
        command = "python benchmarks/fuzz.py " + " ".join(shown)
        Path(args.state).mkdir(parents=True, exist_ok=True)
        (Path(args.state) / "command.txt").write_text(command)
        stats = fuzz(args)
    text = summary(args, stats, command)
    print(text)
    listed = [line for line in text.splitlines() if line.startswith("- ")]
    unexplained = [line for line in listed if not (args.allow_known and line.endswith("(wt-limits)]"))]
    sys.exit(1 if unexplained else 0)


if __name__ == "__main__":
    main()
