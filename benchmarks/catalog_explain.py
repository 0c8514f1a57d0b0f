"""Issue 24, diagnose and relax: the UNSAT solve, diagnose and relax on
benchmarks/catalog_gen.py's global-infeasibility variants, for two source trees side by side
in one run (each cell one ``catc`` process; the trees alternate per point, so both see the
same load).

    python benchmarks/catalog_explain.py --tree main=/work/main --tree branch=. \\
        [--variants budget,power,ram,missing] [--sizes 25,100,400] [--depths 6,12,24] \\
        [--timeout 60] [--timeout-of main=20] [--seed 24]

A cell is the wall time in seconds, ``unknown`` (exit 3), ``timeout`` (killed 15 s past the
limit) or ``WRONG`` (a core without the constructed members, a relaxation other than the
constructed least, or not proven; the script then exits 1).  ``×`` is diagnose over the
UNSAT solve of the same tree.

The variant ``coupled`` (not in the default list) is the ``sat`` problem with the RAM cut to
7 GB (``--coupled-ram``; to half the seeded sum where that is 7 or less), ``coupled2`` the
same with the GPU memory cut to 5 GB too (``--coupled-gpu``): several resources may need
raising at once and alternatives trade one for another, so there is no constructed least;
the relax cell counts when it is proven least (the totals are printed after the table), and
``coupled``'s cores must contain ``init/ram`` (with the RAM free, the seeded selection fits
every other sum exactly).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import catalog_gen as gen  # noqa: E402
from catalog_scale import _doc  # noqa: E402


def _run(tree: Path, args: list[str], timeout: float, cwd: Path) -> tuple[float | str, int, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(str(tree / p) for p in ("compiler", "runtime", "."))
    start = time.perf_counter()
    try:
        p = subprocess.run(
            [sys.executable, "-m", "catc", *args],
            cwd=cwd,
            capture_output=True,
            text=True,
            timeout=timeout + 15,
            env=env,
        )
    except subprocess.TimeoutExpired:
        return "timeout", 3, ""
    return time.perf_counter() - start, p.returncode, p.stdout


def measure(tree: Path, variant: str, expect: dict, timeout: float, tmp: Path) -> dict[str, object]:
    dom = "missing-domain.cat" if variant == "missing" else "domain.cat"
    t = ["--timeout", str(timeout)]
    row: dict[str, object] = {}
    totals: dict[str, object] = {}

    def cell(name: str, args: list[str], ok) -> None:
        wall, rc, out = _run(tree, args, timeout, tmp)
        if wall == "timeout" or rc == 3:
            row[name] = "timeout" if wall == "timeout" else "unknown"
            return
        row[name] = wall if ok(_doc(out)) else "WRONG"

    def unsat_ok(j: dict) -> bool:
        return j.get("status") == "unsat" and j.get("unsat", {}).get("final") is True

    def core_ok(j: dict) -> bool:
        cores = j.get("cores") or []
        labels = {x.get("label") for x in cores[0]} if cores else set()
        return j.get("status") == "unsat" and set(expect["core_contains"]) <= labels

    def relax_ok(j: dict) -> bool:
        if expect["relax"] == "proven":  # the coupled cut: any proven least, its total kept
            totals[variant] = f"{j.get('cost')} ({expect['cut']})"
            return j.get("status") == "relaxed" and j.get("proven") is True
        if expect["relax"] is None:
            return j.get("status") == "unsat"
        got = {r["label"]: str(r["delta"]) for r in j.get("relaxations", [])}
        want = {k: str(v) for k, v in expect["relax"].items()}
        return j.get("status") == "relaxed" and j.get("proven") is True and got == want

    cell("UNSAT solve", ["solve", dom, f"{variant}.cat", "--json", *t], unsat_ok)
    cell("diagnose", ["diagnose", dom, f"{variant}.cat", "--json", *t], core_ok)
    cell("relax", ["relax", dom, f"{variant}.cat", "--json", *t], relax_ok)
    u, dg = row.get("UNSAT solve"), row.get("diagnose")
    row["×"] = dg / u if isinstance(u, float) and isinstance(dg, float) else "—"
    if variant in totals:
        row["total"] = totals[variant]
    return row


def coupled(tmp: Path, variant: str, cuts: dict[str, int]) -> dict:
    """The ``sat`` problem with the RAM (``coupled``), or the RAM and the GPU memory
    (``coupled2``), cut as ``cuts`` say — to half the seeded value where that is no more
    (see the module docstring)."""
    text = (tmp / "sat.cat").read_text()
    done = []
    for r in ["ram", "gpu"] if variant == "coupled2" else ["ram"]:
        seeded = int(re.search(rf"\(= {r} ([0-9]+)\)", text).group(1))  # type: ignore[union-attr]
        cut = cuts[r] if seeded > cuts[r] else seeded // 2
        text = re.sub(rf"\(= {r} [0-9]+\)", f"(= {r} {cut})", text, count=1)
        done.append(f"{r} {seeded} → {cut}")
    (tmp / f"{variant}.cat").write_text(text.replace("(problem sat)", f"(problem {variant})"))
    return {"core_contains": ["init/ram"] if variant == "coupled" else [], "relax": "proven", "cut": ", ".join(done)}


def _cell(v: object) -> str:
    return f"{v:.1f}" if isinstance(v, float) else str(v)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tree", action="append", required=True, help="NAME=PATH of a source tree (repeat)")
    ap.add_argument("--variants", default="budget,power,ram,missing")
    ap.add_argument("--sizes", default="25,100,400")
    ap.add_argument("--depths", default="6,12,24")
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--timeout-of", action="append", default=[], help="NAME=SECONDS: another limit for one tree")
    ap.add_argument("--seed", type=int, default=24)
    ap.add_argument("--coupled-ram", type=int, default=7, help="the RAM of the coupled variants (GB)")
    ap.add_argument("--coupled-gpu", type=int, default=5, help="the GPU memory of the coupled2 variant (GB)")
    args = ap.parse_args(argv)
    shown = sys.argv[1:] if argv is None else argv
    trees = [(name, Path(path).resolve()) for name, _, path in (t.partition("=") for t in args.tree)]
    limit = {name: float(s) for name, _, s in (t.partition("=") for t in args.timeout_of)}
    queries = ["UNSAT solve", "diagnose", "relax", "×"]
    rows = []
    for variant in args.variants.split(","):
        for d in (int(x) for x in args.depths.split(",")):
            for n in (int(x) for x in args.sizes.split(",")):
                if n < d:
                    continue
                cat = gen.build(n, d, args.seed)
                with tempfile.TemporaryDirectory() as tmp:
                    expects = gen.write(cat, Path(tmp))
                    cuts = {"ram": args.coupled_ram, "gpu": args.coupled_gpu}
                    couples = variant.startswith("coupled")
                    expect = coupled(Path(tmp), variant, cuts) if couples else expects[variant]
                    for name, tree in trees:
                        row = measure(tree, variant, expect, limit.get(name, args.timeout), Path(tmp))
                        row["load"] = os.getloadavg()[0]
                        rows.append((variant, n, d, name, row))
                        cells = ", ".join(f"{k} {_cell(v)}" for k, v in row.items())
                        print(f"  {variant} n={n} d={d} {name}: {cells}", file=sys.stderr, flush=True)
    print(f"`python benchmarks/catalog_explain.py {' '.join(shown)}` — seconds per process\n")
    print("| variant | n | d | tree | " + " | ".join(queries) + " | load (1 min) |")
    print("|---|---:|---:|---|" + "---:|" * len(queries) + "---:|")
    for variant, n, d, name, row in rows:
        cells = " | ".join(_cell(row.get(q, "")) for q in queries)
        print(f"| {variant} | {n} | {d} | {name} | {cells} | {row['load']:.1f} |")
    totals = [(v, n, d, name, row["total"]) for v, n, d, name, row in rows if "total" in row]
    if totals:
        print(
            "\nProven least totals of the coupled cut: "
            + ", ".join(f"n = {n}, d = {d} {name}: {t}" for _, n, d, name, t in totals)
        )
    wrong = [(v, n, d, name, q) for v, n, d, name, row in rows for q, x in row.items() if x == "WRONG"]
    if wrong:
        print(f"\nWRONG answers: {wrong}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
