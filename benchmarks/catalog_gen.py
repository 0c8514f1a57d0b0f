"""Seeded catalogs with competing alternatives and global infeasibility (issue 24).

    python benchmarks/catalog_gen.py OUT_DIR [--n 100] [--d 12] [--seed 24]

writes ``OUT_DIR/domain.cat`` (the catalog), ``OUT_DIR/missing-domain.cat`` (the same catalog
with one capability level's providers taken out) and one problem per variant —
``sat.cat``, ``budget.cat``, ``power.cat``, ``ram.cat``, ``missing.cat``, ``recompose.cat``
(a deployed composition and a one-value event) — plus ``expect.json``, what each must answer,
derived by construction (below).

The shape (issue 24): a chain of ``d`` capability levels ``cap1 … capd`` (the goal is ``capd``)
cycling hardware / software / behaviour; every level has ``⌈0.6 n / d⌉`` alternatives, each
needing the level below (its first precondition) and competing for the numeric resources:

* hardware alternatives cost ``budget`` (USD, in [1000, 1900)) and draw ``power`` (W);
* software alternatives use ``ram`` and ``gpu`` (GB) and publish the level's topic ``t<i>``;
* behaviour alternatives subscribe to the topic of the software level below and draw ``power``
  at a θ-parameterised speed ``speed ∈ [lo, hi]`` (they draw ``speed`` W).

Every numeric resource has bounds ``(0 *)`` and only decreases.  The rest of the ``n``
components are distractors: spare hardware (costs budget, gives nothing the goal needs),
loggers with an open-sort θ topic (use a little RAM), monitors (draw power), shortcuts from
``cap(s-1)`` to ``cap(s+1)`` that need more RAM than there is by ``≥ 1000`` GB, and consumers
of the topic ``ghost`` that nothing publishes.

What each variant must answer, by construction (no deployment, so the queries are about the
whole catalog).  A composition reaches ``capd`` only through one alternative per level (a
shortcut needs ``ram ≥ R + 1000`` with ``ram`` starting at ``R`` and only decreasing; a ghost
consumer's topic is never published), so a mission is feasible exactly when some *selection*
(one alternative per level, behaviour speeds at their ``lo``) fits every initial value;
distractors and second alternatives only consume more.

* ``sat``: the initial values are the sums of a seeded selection ``S`` (speeds at ``lo``):
  feasible.
* ``budget``: ``budget = Σ_hardware levels min price − Δ``, everything else generous (the
  sums of the per-level maxima).  Infeasible; from two hardware levels on (d ≥ 4) every
  single alternative stays affordable (prices lie in [1000, 1900), so the least sum of two
  exceeds any one price by more than Δ ≤ 100).  Least relaxation: ``init/budget`` by ``+Δ`` and nothing
  else: no eligible requirement but an initial value makes the purchases cost less (the
  bounds ``(0 *)`` are not relaxable and the purchases decrease the budget whatever their
  preconditions say), and a shortcut would need ``≥ 1000 > Δ`` more RAM.  Any core contains
  ``init/budget`` (without it the budget is free and the selection of cheapest hardware fits).
* ``power``: the same with ``power = Σ min power − Δ`` over hardware draws and behaviour ``lo``
  (cost-free choices: the two kinds draw independently per level).  Least: ``init/power +Δ``.
* ``ram``: ``ram = Σ_software min ram − Δ``.  Least: ``init/ram +Δ``.
* ``missing``: level ``L`` has no provider (``missing-domain.cat``) and no shortcut skips it;
  generous resources.  No relaxation of numeric requirements helps (relax: ``unsat``); every
  core contains the first precondition (``cap L``) of every alternative at level ``L+1``
  (dropping one lets that alternative fire without ``cap L``, and the rest of the chain is
  affordable).
* ``recompose``: ``sat``'s initial values with ``ram`` one less, and ``S`` deployed.  Level ``i0``
  (a software level) has an alternative ``lean`` that needs one GB less RAM than ``S``'s and
  the same GPU memory.  ``S`` no longer fits; stability first the least churn is 2 (remove
  ``S[i0]``, add ``lean``): churn 1 either removes a level's only user (the chain breaks) or
  adds a component to a composition that already does not fit.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import sys
from dataclasses import dataclass, field
from fractions import Fraction
from itertools import product
from pathlib import Path

KINDS = ("hardware", "software", "behavior")
#: a shortcut needs this much RAM more than the catalog starts with
SHORTCUT_EXCESS = 1000


def level_kind(level: int) -> str:
    return KINDS[(level - 1) % 3]


@dataclass(frozen=True)
class Alt:
    name: str
    level: int
    kind: str
    price: int = 0  # hardware: USD
    power: int = 0  # hardware: W drawn; behaviour: lo of the speed θ
    speed_hi: int = 0  # behaviour: hi of the speed θ
    ram: int = 0  # software: GB
    gpu: int = 0  # software: GB

    def need(self) -> dict[str, int]:
        return {"budget": self.price, "power": self.power, "ram": self.ram, "gpu": self.gpu}


@dataclass
class Catalog:
    n: int
    d: int
    seed: int
    levels: list[list[Alt]]
    selection: list[Alt]  # S: one alternative per level (sat and recompose)
    lean: Alt  # recompose: the alternative needing one GB less than S's at level i0
    missing: int  # the level taken out of missing-domain.cat
    shortcuts: list[int]  # s: cap(s-1) → cap(s+1)
    distractors: list[str] = field(default_factory=list)  # their text
    components: int = 0


RESOURCES = ("budget", "power", "ram", "gpu")


def build(n: int, d: int, seed: int = 24) -> Catalog:
    """The catalog's data (the text comes from :func:`domain_text` and :func:`problem_text`)."""
    if d < 3 or n < d:
        raise ValueError("need d ≥ 3 and n ≥ d")
    rng = random.Random(f"catalog-gen/{seed}/{n}/{d}")
    per = max(1, math.ceil(0.6 * n / d))
    levels: list[list[Alt]] = []
    for level in range(1, d + 1):
        kind = level_kind(level)
        alts = []
        for j in range(per):
            name = f"{kind[:2]}{level}-{j}"
            if kind == "hardware":
                alts.append(Alt(name, level, kind, price=rng.randrange(1000, 1900), power=rng.randrange(20, 36)))
            elif kind == "software":
                alts.append(Alt(name, level, kind, ram=rng.randrange(4, 8), gpu=rng.randrange(0, 9)))
            else:
                lo = rng.randrange(20, 36)
                alts.append(Alt(name, level, kind, power=lo, speed_hi=lo + rng.randrange(1, 20)))
        levels.append(alts)
    selection = [rng.choice(alts) for alts in levels]
    software = [lv for lv in range(1, d + 1) if level_kind(lv) == "software"]
    i0 = rng.choice(software)
    s0 = selection[i0 - 1]
    # lean: one GB less RAM than S's software at i0 (S's needs at least 2 so lean's is ≥ 1)
    if s0.ram < 2:
        s0 = Alt(s0.name, s0.level, s0.kind, ram=2, gpu=s0.gpu)
        levels[i0 - 1] = [s0 if a.name == s0.name else a for a in levels[i0 - 1]]
        selection[i0 - 1] = s0
    lean = Alt(f"so{i0}-lean", i0, "software", ram=s0.ram - 1, gpu=s0.gpu)
    levels[i0 - 1].append(lean)
    missing = rng.randrange(2, d)  # never the goal's level nor the first
    cat = Catalog(n, d, seed, levels, selection, lean, missing, [])
    used = sum(len(a) for a in levels)
    extra = max(4, n - used)
    cat.components = used + extra
    for k in range(extra):
        role = k % 5
        if role == 0:
            cat.distractors.append(
                f"  (:morphism spare-{k} :kind hardware :uses 1\n"
                f"    :precondition (>= budget {rng.randrange(10, 500)})\n"
                f"    :effect (and (assign spare-{k}-on true) (decrease budget {rng.randrange(10, 500)})))"
            )
        elif role == 1:
            cat.distractors.append(
                f"  (:morphism logger-{k} :kind software :uses 1\n"
                "    :parameters ((t topic))\n"
                "    :precondition (and (member t topics) (>= ram 1))\n"
                f"    :effect (and (assign logged-{k} true) (decrease ram 1)))"
            )
        elif role == 2:
            below = rng.randrange(1, d + 1)
            cat.distractors.append(
                f"  (:morphism monitor-{k} :kind behavior :uses 1\n"
                f"    :precondition (and cap{below} (>= power {rng.randrange(1, 20)}))\n"
                f"    :effect (and (assign monitored-{k} true) (decrease power 1)))"
            )
        elif role == 3:
            # s = missing skips the missing level, s = missing - 1 gives it: neither
            choices = [s for s in range(2, d) if s not in (missing - 1, missing)]
            s = rng.choice(choices) if choices else 0
            if not choices:  # a short chain: a ghost consumer instead
                role = 4
            else:
                cat.shortcuts.append(s)
                cat.distractors.append(
                    f"  (:morphism shortcut-{k} :kind software :uses 1\n"
                    f"    :precondition (and cap{s - 1} (>= ram RAM-BIG-{k}))\n"
                    f"    :effect (and (assign cap{s + 1} true) (decrease ram RAM-BIG-{k})))"
                )
        if role == 4:
            gives = rng.randrange(1, d + 1)
            cat.distractors.append(
                f"  (:morphism ghost-reader-{k} :kind software :uses 1\n"
                "    :precondition (member ghost topics)\n"
                f"    :effect (assign cap{gives} true))"
            )
    return cat


def _morphism(a: Alt) -> str:
    below = [f"cap{a.level - 1}"] if a.level > 1 else []
    if a.kind == "hardware":
        pre = [*below, f"(>= budget {a.price})", f"(>= power {a.power})"]
        eff = [f"(assign cap{a.level} true)", f"(decrease budget {a.price})", f"(decrease power {a.power})"]
        params = ""
    elif a.kind == "software":
        pre = [*below, f"(>= ram {a.ram})", f"(>= gpu {a.gpu})"]
        eff = [f"(assign cap{a.level} true)", f"(add topics t{a.level})", f"(decrease ram {a.ram})"]
        eff.append(f"(decrease gpu {a.gpu})")
        params = ""
    else:
        pre = [*below, f"(member t{a.level - 1} topics)", "(>= power speed)"]
        eff = [f"(assign cap{a.level} true)", "(decrease power speed)"]
        params = f"\n    :parameters ((speed real :unit W :bounds ({a.power} {a.speed_hi})))"
    return (
        f"  (:morphism {a.name} :kind {a.kind} :uses 1{params}\n"
        f"    :precondition (and {' '.join(pre)})\n"
        f"    :effect (and {' '.join(eff)}))"
    )


def generous(cat: Catalog) -> dict[str, int]:
    """Initial values no selection can exceed: the sums of per-level maxima."""
    return {r: sum(max(a.need()[r] for a in alts) for alts in cat.levels) + 1 for r in RESOURCES}


def least_sums(cat: Catalog) -> dict[str, int]:
    """Per resource, the least any selection needs (the resources are chosen independently:
    each level's alternatives draw on disjoint resources but power, which hardware and
    behaviour levels draw at different levels)."""
    return {r: sum(min(a.need()[r] for a in alts) for alts in cat.levels) for r in RESOURCES}


def sums(selection: list[Alt]) -> dict[str, int]:
    return {r: sum(a.need()[r] for a in selection) for r in RESOURCES}


def domain_text(cat: Catalog, missing: bool = False) -> str:
    big = generous(cat)["ram"] + SHORTCUT_EXCESS
    name = f"catalog-{cat.n}-{cat.d}" + ("-missing" if missing else "")
    lines = [
        f"; issue 24 catalog: n = {cat.n}, d = {cat.d}, seed {cat.seed} (benchmarks/catalog_gen.py)",
        f"(define (domain {name})",
        "  (:requirements :numeric :sets :free-parameters :optimization :recomposition)",
        "  (:sorts topic - symbol)",
        "  (:constants " + " ".join(f"t{i}" for i in range(1, cat.d + 1)) + " ghost - topic)",
        "  (:resources",
        "    (budget real :unit USD :bounds (0 *))",
        "    (power real :unit W :bounds (0 *))",
        "    (ram real :unit GB :bounds (0 *))",
        "    (gpu real :unit GB :bounds (0 *))",
        "    (topics (set topic))",
        "    " + " ".join(f"(cap{i} bool)" for i in range(1, cat.d + 1)),
    ]
    flags = []
    for text in cat.distractors:
        head = text.split()[1]
        if head.startswith("spare-"):
            flags.append(f"{head}-on")
        elif head.startswith("logger-"):
            flags.append("logged-" + head.split("-")[1])
        elif head.startswith("monitor-"):
            flags.append("monitored-" + head.split("-")[1])
    if flags:
        lines.append("    " + " ".join(f"({f} bool)" for f in flags))
    lines[-1] += ")"
    for level, alts in enumerate(cat.levels, 1):
        if missing and level == cat.missing:
            continue
        lines += [_morphism(a) for a in alts]
    for text in cat.distractors:
        for k in range(len(cat.distractors) + 5):
            text = text.replace(f"RAM-BIG-{k})", f"{big + k})")  # noqa: PLW2901
        lines.append(text)
    lines.append(")")
    return "\n".join(lines) + "\n"


def problem_text(cat: Catalog, variant: str, delta: int = 1) -> tuple[str, dict]:
    """One problem of the catalog and what it must answer (see the module's docstring)."""
    init = generous(cat)
    least = least_sums(cat)
    expect: dict = {"variant": variant}
    deployed: list[str] = []
    metric = ""
    domain = f"catalog-{cat.n}-{cat.d}"
    if variant == "sat":
        init = sums(cat.selection)
        expect["status"] = "sat"
    elif variant in ("budget", "power", "ram"):
        init[variant] = least[variant] - delta
        expect.update(status="unsat", relax={f"init/{variant}": delta}, core_contains=[f"init/{variant}"])
    elif variant == "missing":
        domain += "-missing"
        above = [a.name for a in cat.levels[cat.missing]]  # level missing + 1
        expect.update(
            status="unsat",
            relax=None,
            missing_level=cat.missing,
            core_contains=[f"pre/{name}/1" for name in above],
        )
    elif variant == "recompose":
        init = sums(cat.selection)
        init["ram"] -= 1
        deployed = [a.name for a in cat.selection]
        metric = "  (:metric maximize budget)\n"
        expect.update(status="sat", churn=2, lean=cat.lean.name, deployed=deployed)
    else:
        raise ValueError(f"variant {variant!r}")
    lines = [
        f"(define (problem {variant}) (:domain {domain})",
        "  (:init " + " ".join(f"(= {r} {init[r]})" for r in RESOURCES) + ")",
        f"  (:goal cap{cat.d})",
        f"  (:horizon {cat.d + 2})",
    ]
    if deployed:
        lines.append(metric.rstrip("\n"))
        lines.append(f"  (:deployed {' '.join(deployed)})")
    lines[-1] += ")"
    return "\n".join(lines) + "\n", expect


VARIANTS = ("sat", "budget", "power", "ram", "missing", "recompose")


def write(cat: Catalog, out: Path, delta: int = 1) -> dict[str, dict]:
    out.mkdir(parents=True, exist_ok=True)
    (out / "domain.cat").write_text(domain_text(cat))
    (out / "missing-domain.cat").write_text(domain_text(cat, missing=True))
    expects = {}
    for v in VARIANTS:
        text, expect = problem_text(cat, v, delta)
        (out / f"{v}.cat").write_text(text)
        expects[v] = expect
    (out / "expect.json").write_text(json.dumps(expects, indent=1, default=str) + "\n")
    return expects


# ------------------------------------------------------- brute force (tiny catalogs)


def feasible_selections(cat: Catalog, init: dict[str, int], missing: bool = False) -> list[tuple[Alt, ...]]:
    """Every selection (one alternative per level) that fits ``init`` (speeds at ``lo``)."""
    levels = [[] if missing and lv == cat.missing else alts for lv, alts in enumerate(cat.levels, 1)]
    out = []
    for sel in product(*levels):
        s = sums(list(sel))
        if all(s[r] <= init[r] for r in RESOURCES):
            out.append(sel)
    return out


def least_restoration(cat: Catalog, init: dict[str, int], eligible: tuple[str, ...] = RESOURCES) -> Fraction:
    """By brute force: the least Σ of initial-value increases making some selection fit."""
    best = None
    for sel in product(*cat.levels):
        s = sums(list(sel))
        cost = sum(max(0, s[r] - init[r]) for r in eligible)
        if all(s[r] <= init[r] for r in RESOURCES if r not in eligible):
            best = cost if best is None else min(best, cost)
    return Fraction(best if best is not None else -1)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--d", type=int, default=12)
    ap.add_argument("--seed", type=int, default=24)
    ap.add_argument("--delta", type=int, default=1)
    args = ap.parse_args(argv)
    cat = build(args.n, args.d, args.seed)
    write(cat, args.out, args.delta)
    print(f"{cat.components} components, d = {cat.d}: {args.out}/domain.cat and {len(VARIANTS)} problems")
    return 0


if __name__ == "__main__":
    sys.exit(main())
