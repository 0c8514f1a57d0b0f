"""Hypothesis strategies for *valid* .cat models (issue 15, items 2 and 3).

Mutation fuzzing (tests/test_fuzz.py, benchmarks/fuzz.py) mostly reaches the parser and the
checker; these strategies build domains and problems that check clean, so that the
encoder, the solver, the validator, ``catc fmt`` and the exports are reached on every
example.  A model has resources of every sort — ``bool``, bounded and open ``int``,
``real``, a closed enumeration, an open symbolic sort (whose reserve values the solver may
invent) and a set of it — and one to four morphisms with θ parameters (``int`` and
``real`` with bounds, some ``:fixed``, symbolic), ``:uses`` limits, preconditions over
resources and parameters, and effects of every kind (``assign``, ``increase``,
``decrease``, ``add``, ``remove``) with at most one write per resource and morphism (the
checker's E0501 rule); then initial values within the bounds, a goal and a horizon.

The generator keeps its own record of what it drew (:class:`Model`), so tests can ask,
say, whether the model is grid-expressible for the PDDL export (no ``real`` parameter).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hypothesis import strategies as st

ITEMS = ("c0", "c1", "c2")  # constants of the open sort `item`
MODES = ("m0", "m1", "m2")  # values of the enumeration `mode`


@dataclass(frozen=True)
class Resource:
    name: str
    sort: str  # "bool", "int", "real", "mode", "item", "set"
    bounds: tuple[int, int | None] | None = None  # numeric resources: (lo, hi), hi None = open

    def declaration(self) -> str:
        sort = "(set item)" if self.sort == "set" else self.sort
        bounds = ""
        if self.bounds is not None:
            hi = "*" if self.bounds[1] is None else str(self.bounds[1])
            bounds = f" :bounds ({self.bounds[0]} {hi})"
        return f"({self.name} {sort}{bounds})"


@dataclass(frozen=True)
class Param:
    name: str
    sort: str  # "int", "real", "item"
    fixed: bool = False

    def declaration(self) -> str:
        bounds = {"int": " :bounds (0 3)", "real": " :bounds (0 2)", "item": ""}[self.sort]
        return f"({self.name} {self.sort}{bounds}{' :fixed' if self.fixed else ''})"


@dataclass
class Model:
    """What was drawn, and the text of the file (domain, then problem)."""

    resources: list[Resource]
    morphisms: list[str] = field(default_factory=list)
    params: list[Param] = field(default_factory=list)
    horizon: int = 0
    text: str = ""

    @property
    def has_real_params(self) -> bool:
        return any(p.sort == "real" for p in self.params)

    def __repr__(self) -> str:  # hypothesis prints the falsifying example: show the model
        return f"Model(<<\n{self.text}\n>>)"


# ---------------------------------------------------------------- resources


@st.composite
def resources(draw: st.DrawFn) -> list[Resource]:
    """At least one resource of every sort, a few more of some."""
    out = [
        Resource("b0", "bool"),
        Resource("i0", "int", (0, draw(st.integers(2, 5)))),
        Resource("r0", "real", (0, None)),
        Resource("e0", "mode"),
        Resource("s0", "item"),
        Resource("S0", "set"),
    ]
    for i in range(1, draw(st.integers(1, 3))):
        sort = draw(st.sampled_from(["bool", "int", "real"]))
        bounds = {"bool": None, "int": draw(st.sampled_from([(0, 3), (-2, 2), (0, None)])), "real": (0, 4)}[sort]
        out.append(Resource(f"{sort[0]}{i}", sort, bounds))
    return out


# ---------------------------------------------------------------- terms and literals


def _numeric_term(draw: st.DrawFn, params: list[Param], want: str, depth: int = 0) -> str:
    """A term of sort ``want`` ("int" or "real": ints promote) from constants and parameters,
    now and then compound — ``+``, ``-``, ``*`` by a constant (linear), ``min``, ``max``,
    ``if`` on a bool resource, and ``/`` by a constant for reals."""
    usable = [p.name for p in params if p.sort == "int" or (want == "real" and p.sort == "real")]
    consts = ["1", "2"] if want == "int" else ["1", "2", "0.5", "(/ 1 3)"]
    if depth >= 2 or draw(st.integers(0, 3)) > 0:
        return draw(st.sampled_from(consts + usable))
    ops = ["+", "-", "*", "min", "max", "if"] + (["/"] if want == "real" else [])
    op = draw(st.sampled_from(ops))
    a = _numeric_term(draw, params, want, depth + 1)
    b = _numeric_term(draw, params, want, depth + 1)
    if op == "*":
        return f"(* {draw(st.sampled_from(['2', '-1', '3']))} {a})"
    if op == "/":
        return f"(/ {a} {draw(st.sampled_from(['2', '4']))})"
    if op == "if":
        return f"(if b0 {a} {b})"
    return f"({op} {a} {b})"


def _literal(draw: st.DrawFn, res: list[Resource], params: list[Param]) -> str:
    r = draw(st.sampled_from(res))
    items = [*ITEMS, *(p.name for p in params if p.sort == "item")]
    if r.sort == "bool":
        return draw(st.sampled_from([r.name, f"(not {r.name})"]))
    if r.sort in ("int", "real"):
        op = draw(st.sampled_from([">=", "<=", "<", ">", "="]))
        rhs = (
            _numeric_term(draw, params, r.sort) if draw(st.booleans()) else draw(st.sampled_from(["0", "1", "2", "3"]))
        )
        if r.sort == "int" and any(p.sort == "int" for p in params) and draw(st.booleans()):
            rhs = f"(+ 1 {next(p.name for p in params if p.sort == 'int')})"
        return f"({op} {r.name} {rhs})"
    if r.sort == "mode":
        return f"(= {r.name} {draw(st.sampled_from(MODES))})"
    if r.sort == "item":
        return f"(= {r.name} {draw(st.sampled_from(items))})"
    member = f"(member {draw(st.sampled_from(items))} {r.name})"
    return draw(st.sampled_from([member, f"(not {member})"]))


def _condition(draw: st.DrawFn, res: list[Resource], params: list[Param], n: int) -> str:
    lits = [_literal(draw, res, params) for _ in range(n)]
    if len(lits) >= 2 and draw(st.integers(0, 4)) == 0:  # now and then a disjunction
        lits = [f"(or {lits[0]} {lits[1]})", *lits[2:]]
    return f"(and {' '.join(lits)})"


def _effect(draw: st.DrawFn, r: Resource, params: list[Param]) -> str:
    items = [*ITEMS, *(p.name for p in params if p.sort == "item")]
    if r.sort == "bool":
        return f"(assign {r.name} {draw(st.sampled_from(['true', 'false']))})"
    if r.sort in ("int", "real"):
        kind = draw(st.sampled_from(["increase", "decrease", "assign"]))
        return f"({kind} {r.name} {_numeric_term(draw, params, r.sort)})"
    if r.sort == "mode":
        return f"(assign {r.name} {draw(st.sampled_from(MODES))})"
    if r.sort == "item":
        return f"(assign {r.name} {draw(st.sampled_from(items))})"
    return f"({draw(st.sampled_from(['add', 'remove']))} {r.name} {draw(st.sampled_from(items))})"


# ---------------------------------------------------------------- morphisms and the problem


PARAM_SORTS = ("int", "real", "item")


@st.composite
def morphism(
    draw: st.DrawFn, index: int, res: list[Resource], param_sorts: tuple[str, ...] = PARAM_SORTS
) -> tuple[str, list[Param]]:
    params = []
    sorts = draw(st.lists(st.sampled_from(param_sorts), max_size=2)) if param_sorts else []
    for j, sort in enumerate(sorts):
        params.append(Param(f"p{index}x{j}", sort, fixed=sort != "item" and draw(st.integers(0, 3)) == 0))
    written = draw(st.lists(st.sampled_from(res), min_size=1, max_size=3, unique_by=lambda r: r.name))
    effects = " ".join(_effect(draw, r, params) for r in written)
    parts = [f"(:morphism m{index}"]
    uses = draw(st.sampled_from([None, 1, 2]))
    if uses is not None:
        parts.append(f":uses {uses}")
    if params:
        parts.append(f":parameters ({' '.join(p.declaration() for p in params)})")
    n_pre = draw(st.integers(0, 3))
    if n_pre:
        parts.append(f":precondition {_condition(draw, res, params, n_pre)}")
    parts.append(f":effect (and {effects}))")
    return "  " + " ".join(parts), params


def _initial(draw: st.DrawFn, r: Resource) -> str | None:
    if r.sort == "bool":
        return r.name if draw(st.booleans()) else None
    if r.sort in ("int", "real"):
        lo, hi = r.bounds or (0, None)
        top = hi if hi is not None else lo + 4
        value = draw(st.integers(lo, top))
        if r.sort == "real" and value < top and draw(st.booleans()):
            return f"(= {r.name} {value}.5)"
        return f"(= {r.name} {value})"
    if r.sort == "mode":
        return f"(= {r.name} {draw(st.sampled_from(MODES))})"
    if r.sort == "item":
        return f"(= {r.name} {draw(st.sampled_from(ITEMS))})"
    chosen = draw(st.lists(st.sampled_from(ITEMS), max_size=2, unique=True))
    return f"(= {r.name} {{{' '.join(chosen)}}})"


@st.composite
def models(
    draw: st.DrawFn, max_morphisms: int = 4, max_horizon: int = 3, param_sorts: tuple[str, ...] = PARAM_SORTS
) -> Model:
    """A domain and a problem in one file, which ``catc check`` accepts without errors.
    ``param_sorts``: the sorts θ parameters may have (``("int",)`` for models the PDDL
    export expresses exactly: no grid, no reserve values)."""
    res = draw(resources())
    model = Model(res)
    lines = [
        "(define (domain gen)",
        "  (:requirements :numeric :sets :free-parameters)",
        f"  (:sorts item - symbol mode - (enum {' '.join(MODES)}))",
        f"  (:constants {' '.join(ITEMS)} - item)",
        f"  (:resources {' '.join(r.declaration() for r in res)})",
    ]
    for i in range(draw(st.integers(1, max_morphisms))):
        text, params = draw(morphism(i, res, param_sorts))
        lines.append(text)
        model.morphisms.append(f"m{i}")
        model.params.extend(params)
    lines.append(")")
    init = [x for r in res if (x := _initial(draw, r)) is not None]
    goal = _condition(draw, res, [], draw(st.integers(1, 2)))
    model.horizon = draw(st.integers(0, max_horizon))
    lines += [
        "(define (problem p)",
        "  (:domain gen)",
        f"  (:init {' '.join(init)})",
        f"  (:goal {goal})",
        f"  (:horizon {model.horizon}))",
    ]
    model.text = "\n".join(lines) + "\n"
    return model
