"""What the PDDL exports share (:mod:`catc.targets.pddl_exporter` for PDDL 2.1,
:mod:`catc.targets.pddlplus` for PDDL+): the flavours, the export record and its report,
the errors, PDDL names and numbers, and the grids real parameters θ are ground on."""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from fractions import Fraction

from catc import ir
from catc.ir import ArithOp
from catc.ir.fold import FoldError, fold
from catc.ir.numbers import decimal_text, fraction_text, int_text, number_text
from catc.semantics.plan import Activation, Plan


class Flavor(str, Enum):
    """Which PDDL the export writes."""

    ENHSP = "enhsp"  # PDDL 2.1 numeric planning (ENHSP), every real θ on a grid
    SMTPLAN = "smtplan"  # PDDL+ for SMTPlan+: a real θ without a grid step is a dial (a process)


#: Words some PDDL planners (ENHSP, the PyPI parser) reject as names.
RESERVED = frozenset(
    [
        "start",
        "end",
        "over",
        "all",
        "at",
        "number",
        "minimize",
        "maximize",
        "when",
        "forall",
        "exists",
        "increase",
        "decrease",
        "assign",
        "scale-up",
        "scale-down",
        "and",
        "or",
        "not",
        "imply",
        "either",
        "object",
        "total-cost",
        "total-time",
        "define",
        "domain",
        "problem",
        "requirements",
        "types",
        "constants",
        "predicates",
        "functions",
        "action",
        "parameters",
        "precondition",
        "effect",
        "objects",
        "init",
        "goal",
        "metric",
    ]
)


class ExportError(Exception):
    """The instance cannot be exported (e.g. a real θ without bounds or grid step)."""


class Unsupported(Exception):
    """One construct has no PDDL counterpart (the enclosing item is reported)."""


@dataclass
class ExportReport:
    items: list[tuple[str, str]] = field(default_factory=list)  # (category, text)

    def add(self, category: str, text: str) -> None:
        if (category, text) not in self.items:
            self.items.append((category, text))

    def markdown(self, title: str) -> str:
        lines = [f"# catc export pddl: {title}", ""]
        if not self.items:
            lines.append("Everything in the model is expressed in the PDDL files.")
            return "\n".join(lines) + "\n"
        lines.append("Not expressed (or expressed only approximately) in the PDDL files:")
        lines.append("")
        cats: dict[str, list[str]] = {}
        for c, t in self.items:
            cats.setdefault(c, []).append(t)
        for c, ts in cats.items():
            lines.append(f"## {c}")
            lines.append("")
            lines.extend(f"- {t}" for t in ts)
            lines.append("")
        return "\n".join(lines)


@dataclass
class Export:
    domain: str
    problem: str
    report: ExportReport
    actions: dict[str, Activation]  # ground action name → activation
    grid: dict[str, Fraction]  # "morphism.param" → step used
    flavor: Flavor = Flavor.ENHSP
    #: smtplan flavour: real θ expressed as PDDL+ dials (:mod:`catc.targets.pddlplus`), by key
    #: "morphism.param"; their values come from a timed plan, not from the action names.
    dials: dict = field(default_factory=dict)

    def activation(self, name: str) -> Activation:
        return self.actions[name.lower()]

    def plan_from_actions(self, names: list[str]) -> Plan:
        """A sequential catc plan (one activation per step) from ground action names."""
        if self.dials:
            raise ExportError(
                "this export has continuous θ (dials): read the timed plan with "
                "catc.targets.pddlplus.parse_timed_plan instead of action names"
            )
        return Plan(tuple((self.activation(n),) for n in names))


# ---------------------------------------------------------------- names


def sanitize(text: str) -> str:
    s = re.sub(r"[^a-z0-9-]+", "-", text.lower()).strip("-")
    s = re.sub(r"-+", "-", s)
    if not s or not s[0].isalpha():
        s = "x" + s
    return s


def value_suffix(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, Fraction):
        if v.denominator == 1:
            t = int_text(v.numerator)
        else:
            d = decimal_text(v)
            t = d if not d.startswith("≈") else fraction_text(v).replace("/", "over")
        return t.replace("-", "m").replace(".", "p").replace("/", "over")
    return sanitize(str(v))


def number(v: Fraction | int) -> str:
    """A PDDL number: an integer or a decimal of at most 12 places, else ``(/ n d)``."""
    return number_text(Fraction(v), max_places=12)


class Names:
    def __init__(self) -> None:
        self.used: set[str] = set()

    def fresh(self, base: str) -> str:
        name = sanitize(base)
        if name in RESERVED:
            name = "r-" + name
        out, i = name, 2
        while out in self.used:
            out, i = f"{name}-{i}", i + 1
        self.used.add(out)
        return out


# ---------------------------------------------------------------- grids and bounds


def nice_step(least: Fraction) -> Fraction:
    """The smallest of 1, 2, 5 × 10ᵏ that is at least ``least`` (> 0)."""
    power = Fraction(10) ** (len(int_text(int(least))) - 1) if least >= 1 else Fraction(1)
    while power > least:
        power /= 10
    for mantissa in (1, 2, 5, 10):
        if mantissa * power >= least:
            return mantissa * power
    return 10 * power  # pragma: no cover - 10·power ≥ least by the loops above


def grid_values(lower: Fraction, upper: Fraction, step: Fraction) -> list[Fraction]:
    out, v = [], lower
    while v <= upper:
        out.append(v)
        v += step
    if out[-1] != upper:
        out.append(upper)
    return out


def lower_bound(e: ir.Expr, params: Mapping[str, ir.Param]) -> Fraction | None:
    """A lower bound of a θ-only amount over θ's bounds (interval arithmetic), or None."""
    if isinstance(e, ir.Const) and isinstance(e.value, Fraction) and not isinstance(e.value, bool):
        return e.value
    if isinstance(e, ir.ParamRef):
        p = params.get(e.name)
        return None if p is None or p.lower is None else Fraction(p.lower)
    if isinstance(e, ir.Arith) and e.op is ArithOp.ADD:
        known = [x for x in (lower_bound(a, params) for a in e.args) if x is not None]
        return sum(known, Fraction(0)) if len(known) == len(e.args) else None
    if isinstance(e, ir.Arith) and e.op is ArithOp.MUL and len(e.args) == 2:
        a, b = (lower_bound(x, params) for x in e.args)
        if a is not None and a >= 0 and b is not None and b >= 0:
            return a * b
    return None


def nonnegative_constant(cost: ir.Expr) -> bool:
    """Whether a ``:cost`` is a constant ≥ 0 (no θ, no resource; folded), as the
    ``(total-cost)`` metric needs."""
    if ir.params_in(cost) or ir.resources_in(cost):
        return False
    try:
        folded = fold(cost)
    except FoldError:
        return False
    return isinstance(folded, ir.Const) and not isinstance(folded.value, str) and folded.value >= 0
