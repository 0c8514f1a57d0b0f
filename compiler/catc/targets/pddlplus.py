"""The ``smtplan`` flavour of ``catc export pddl``: PDDL+ for SMTPlan+ (DESIGN §6).

SMTPlan+ (Cashmore et al. 2016) compiles PDDL+ to SMT and binds continuous quantities
exactly, so a real θ needs no grid here.  It is expressed the standard PDDL+ way, with time:
a **dial** per real θ ``p`` of morphism ``m`` (see docs/export.md for the full encoding)::

    (:functions (theta-m-p))             ; initialised to p's lower bound
    (:predicates (adjusting-m-p))
    (:action start-adjust-m-p :precondition (not (adjusting-m-p)) :effect (adjusting-m-p))
    (:action stop-adjust-m-p  :precondition (and (adjusting-m-p) (<= (theta-m-p) UPPER))
                              :effect (not (adjusting-m-p)))
    (:process adjust-m-p :precondition (adjusting-m-p)
                         :effect (increase (theta-m-p) (* #t 1)))

The ground actions of ``m`` read ``(theta-m-p)`` wherever ``p`` occurs, require the dial to
be stopped and within bounds, and then either lock the dial (a ``:fixed`` θ, or a morphism
used at most once: the value stays readable by the metric) or reset it to the lower bound (a
per-activation θ of a morphism that may fire again: each activation gets its own value, set
by its own dial run).  So θ = lower + the total time the dial ran since the last reset.

Int, bool and symbolic θ are enumerated as in the PDDL 2.1 flavour, and a real θ given a
``--grid`` step is still discretised (so a grid is optional, never required).

:func:`parse_timed_plan` reads a timed plan in SMTPlan+'s format (``TIME: (ACTION) [DUR]``)
back into a catc :class:`~catc.semantics.plan.Plan` with exact θ, for :func:`catc.semantics.validate.validate`.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction

from catc import ir
from catc.ir import SortKind
from catc.ir.numbers import decimal_text
from catc.semantics.plan import Activation, Plan
from catc.targets.enhsp import lift_memory_limit
from catc.targets.pddl_base import Export, ExportError, Flavor, Unsupported, number
from catc.targets.pddl_exporter import Exporter

#: SMTPlan+'s encoder separates consecutive happenings by at least this much time
#: (``duration_vars[h] >= 1/10`` in its EncoderHappening.cpp).
SMTPLAN_EPSILON = Fraction(1, 10)

SMTPLAN_HINT = (
    "SMTPlan+ is not on PATH (no 'SMTPlan' executable); build it from "
    "https://github.com/KCL-Planning/SMTPlan (needs Z3) and put it on PATH"
)


@dataclass(frozen=True)
class Dial:
    """How one real θ is expressed in the PDDL+ export."""

    morphism: str
    param: str
    lower: Fraction
    upper: Fraction | None
    fluent: str  # the function holding θ
    running: str  # the predicate "the dial is turning"
    start: str  # instantaneous action starting the process
    stop: str  # instantaneous action stopping it
    process: str
    lock: str | None  # predicate set by the activation (θ fixed / morphism used at most once)
    reset: bool  # the activation resets the fluent to ``lower`` (per-activation θ, repeatable)

    @property
    def key(self) -> str:
        return f"{self.morphism}.{self.param}"


class PlusExporter(Exporter):
    """The PDDL 2.1 exporter plus dials for the real θ that have no grid step."""

    def __init__(self, inst: ir.Instance, grid: Mapping[str, Fraction], horizon: int | None, flavor: Flavor) -> None:
        super().__init__(inst, grid, horizon, flavor)
        self.dials: dict[str, Dial] = {}
        self._cur: ir.Morphism | None = None

    # ---- which θ become dials
    def _step(self, m: ir.Morphism, p: ir.Param) -> Fraction | None:
        return self.grid_in.get(f"{m.name}.{p.name}", self.grid_in.get(p.name))

    def is_dial(self, m: ir.Morphism, p: ir.Param) -> bool:
        return f"{m.name}.{p.name}" in self.dials

    def declare(self) -> None:
        super().declare()
        for m in self.inst.domain.morphisms.values():
            for p in m.params:
                if p.sort.kind is not SortKind.REAL or self._step(m, p) is not None:
                    continue
                key = f"{m.name}.{p.name}"
                if p.lower is None:
                    raise ExportError(
                        f"real parameter {key} has no finite lower bound; the PDDL+ dial starts at the "
                        f"lower bound and only rises: give it :bounds (lo hi) or (lo *)"
                    )
                if p.upper is not None and p.upper < p.lower:
                    raise ExportError(
                        f"real parameter {key} has empty bounds ({decimal_text(p.lower)} {decimal_text(p.upper)})"
                    )
                repeat = m.uses is None or m.uses > 1
                reset = repeat and not p.fixed
                if p.fixed:
                    lock = self.names.fresh(f"fixed-{m.name}-{p.name}")
                    self.pred[("fixed", m.name, p.name)] = lock  # the flag the PDDL 2.1 flavour also uses
                elif not reset:
                    lock = self.names.fresh(f"theta-set-{m.name}-{p.name}")
                    self.pred[("dial-lock", key)] = lock
                else:
                    lock = None
                fluent = self.names.fresh(f"theta-{m.name}-{p.name}")
                self.func[("dial", key)] = fluent
                running = self.names.fresh(f"adjusting-{m.name}-{p.name}")
                self.pred[("dial", key)] = running
                d = Dial(
                    m.name,
                    p.name,
                    p.lower,
                    p.upper,
                    fluent,
                    running,
                    self.names.fresh(f"start-adjust-{m.name}-{p.name}"),
                    self.names.fresh(f"stop-adjust-{m.name}-{p.name}"),
                    self.names.fresh(f"adjust-{m.name}-{p.name}"),
                    lock,
                    reset,
                )
                self.dials[key] = d
                self.requirements.update({":time", ":numeric-fluents", ":negative-preconditions"})
                hi = "*" if p.upper is None else decimal_text(p.upper)
                how = (
                    "fixed: one value for the whole plan, the dial is locked by the first activation"
                    if p.fixed
                    else "per activation, and the morphism is used at most once: the dial is locked by the activation"
                    if not reset
                    else "per activation, and the morphism may fire again: each activation resets the dial to the lower "
                    "bound, so every activation gets its own value from its own dial run"
                )
                self.report.add(
                    "continuous parameters (exact, as PDDL+ dials)",
                    f"{key} ∈ [{decimal_text(p.lower)}, {hi}] is exact, no grid: fluent ({fluent}) starts at "
                    f"{decimal_text(p.lower)} and rises at rate 1 while process ({d.process}) runs, between "
                    f"actions ({d.start}) and ({d.stop}); θ = lower bound + time the dial ran ({how})",
                )
                if p.upper is None:
                    self.report.add(
                        "continuous parameters (exact, as PDDL+ dials)",
                        f"{key} has no upper bound: the dial is unbounded above",
                    )

    def _theta_values(self, m: ir.Morphism) -> list[list[object]] | None:
        # dial θ stay symbolic: a single placeholder value, stripped in action_text
        out: list[list[object]] = []
        for p in m.params:
            if self.is_dial(m, p):
                out.append([_DIAL])
            else:
                values = super()._theta_values(_only(m, p))
                assert values is not None  # the PDDL 2.1 export enumerates every parameter it can
                out.append(values[0])
        return out

    # ---- the ground morphism actions read the dials
    def param_term(self, e: ir.ParamRef | ir.ParamValue) -> str:
        if isinstance(e, ir.ParamRef) and self._cur is not None:
            d = self.dials.get(f"{self._cur.name}.{e.name}")
            if d is not None:
                return f"({d.fluent})"
        if isinstance(e, ir.ParamValue):
            d = self.dials.get(f"{e.morphism}.{e.param}")
            if d is not None and d.lock is not None:
                return f"({d.fluent})"
        return super().param_term(e)

    def action_text(self, m: ir.Morphism, theta: dict[str, object], objective_cost: bool) -> str | None:
        self._cur = m
        try:
            return super().action_text(m, {k: v for k, v in theta.items() if v is not _DIAL}, objective_cost)
        finally:
            self._cur = None

    def extra_conditions(self, m: ir.Morphism, theta: Mapping[str, object], pre: list[str], effs: list[str]) -> None:
        for p in m.params:
            d = self.dials.get(f"{m.name}.{p.name}")
            if d is None:
                continue
            pre.append(f"(not ({d.running}))")
            if d.upper is not None:
                pre.append(f"(<= ({d.fluent}) {number(d.upper)})")
            if d.lock is not None:
                effs.append(f"({d.lock})")
            if d.reset:
                effs.append(f"(assign ({d.fluent}) {number(d.lower)})")

    def extra_domain_text(self) -> str:
        out, procs = [], []  # unified-planning's reader wants every :action before the :process blocks
        for d in self.dials.values():
            start_pre = [f"(not ({d.running}))"] + ([f"(not ({d.lock}))"] if d.lock else [])
            stop_pre = [f"({d.running})"] + ([f"(<= ({d.fluent}) {number(d.upper)})"] if d.upper is not None else [])
            out.append(
                f"  (:action {d.start}\n    :parameters ()\n    :precondition (and {' '.join(start_pre)})\n"
                f"    :effect (and ({d.running})))\n"
            )
            out.append(
                f"  (:action {d.stop}\n    :parameters ()\n    :precondition (and {' '.join(stop_pre)})\n"
                f"    :effect (and (not ({d.running}))))\n"
            )
            procs.append(
                f"  (:process {d.process}\n    :parameters ()\n    :precondition (and ({d.running}))\n"
                f"    :effect (and (increase ({d.fluent}) (* #t 1))))\n"
            )
        return "".join(out + procs)

    def _init(self) -> list[str]:
        out = super()._init()
        start = {f"(= ({d.fluent}) 0)": f"(= ({d.fluent}) {number(d.lower)})" for d in self.dials.values()}
        return [start.get(line, line) for line in out]

    # ---- the metric: written (PDDL+ has maximize), though SMTPlan+ ignores it
    def metric(self) -> tuple[str | None, bool]:
        met = self.inst.problem.metric
        if met is None:
            return None, False
        ignored = (
            "the metric is written, but SMTPlan+ ignores optimisation metrics (it is satisficing): "
            "its plan need not be optimal — compare with `catc optimize`"
        )
        if met.mode is not ir.MetricMode.SINGLE or len(met.objectives) != 1:
            return super().metric()
        obj = met.objectives[0]
        if isinstance(obj.term, ir.TotalCost):
            text, with_cost = super().metric()
            if text:
                self.report.add("objective", ignored)
            return text, with_cost
        sense = "maximize" if obj.sense is ir.Sense.MAXIMIZE else "minimize"
        try:
            if any(not isinstance(x, (ir.Const, ir.ResourceRef, ir.Arith, ir.ParamValue)) for x in ir.walk(obj.term)):
                raise Unsupported("objective term")
            text = f"(:metric {sense} {self.num(obj.term)})"
        except Unsupported as exc:
            self.report.add("objective", f"objective not exported ({exc})")
            return None, False
        self.report.add("objective", ignored)
        return text, False

    def run(self) -> Export:
        out = super().run()
        out.dials = dict(self.dials)
        if self.dials:
            self.report.add(
                "SMTPlan+",
                f"SMTPlan+ separates consecutive happenings by at least {decimal_text(SMTPLAN_EPSILON)} time "
                f"units, so a dial that runs at all moves θ by at least {decimal_text(SMTPLAN_EPSILON)}: values strictly "
                f"between a lower bound and lower + {decimal_text(SMTPLAN_EPSILON)} are out of SMTPlan+'s reach (the PDDL+ "
                "semantics itself allows them)",
            )
        self.report.add(
            "semantics",
            "PDDL+ plans are timed: SMTPlan+ may put several actions in one happening; "
            "catc replays the morphism actions in time order, one per step (sequential)",
        )
        return out


class _DialMarker:
    def __repr__(self) -> str:
        return "<dial>"


_DIAL = _DialMarker()


def _only(m: ir.Morphism, p: ir.Param) -> ir.Morphism:
    """A view of ``m`` with the single parameter ``p`` (to reuse the enumeration of one θ)."""
    import dataclasses

    return dataclasses.replace(m, params=(p,))


# ---------------------------------------------------------------- timed plans


class PlanReadError(ValueError):
    """A timed plan that cannot be read back (unknown action, dial misuse, inexact time)."""


@dataclass(frozen=True)
class TimedAction:
    time: Fraction
    name: str
    duration: Fraction | None = None


_TIMED = re.compile(
    r"^\s*(?P<t>[-+]?[0-9]+(?:\.[0-9]*)?(?:/[0-9]+)?\??)\s*:\s*\(\s*(?P<name>[^()\s]+)(?P<args>[^()]*)\)"
    r"\s*(?:\[\s*(?P<d>[^\]]*?)\s*\])?"
)


def _exact(text: str, what: str, line: str) -> Fraction:
    if text.endswith("?"):
        raise PlanReadError(
            f"{what} {text!r} is a truncated decimal (Z3's pp.decimal marks it with '?'); "
            f"catc needs exact values: {line.strip()!r}"
        )
    try:
        return Fraction(text)
    except (ValueError, ZeroDivisionError):
        raise PlanReadError(f"{what} {text!r} is not a number: {line.strip()!r}") from None


def read_timed_actions(text: str) -> list[TimedAction]:
    """The ``TIME: (ACTION) [DURATION]`` lines of a planner's output, in order (other lines ignored)."""
    out = []
    for line in text.splitlines():
        m = _TIMED.match(line)
        if not m:
            continue
        if m.group("args").strip():
            raise PlanReadError(f"action with arguments (catc exports ground 0-ary actions): {line.strip()!r}")
        t = _exact(m.group("t"), "time", line)
        if t < 0:
            raise PlanReadError(f"negative time: {line.strip()!r}")
        d = m.group("d")
        out.append(TimedAction(t, m.group("name").lower(), None if d is None else _exact(d, "duration", line)))
    return out


def parse_timed_plan(export: Export, text: str) -> Plan:
    """A sequential catc plan from a timed PDDL+ plan (SMTPlan+'s output format).

    Morphism actions become activations in time order (lines with equal times keep their
    order); the value of a dial θ at an activation is its lower bound plus the time between
    each ``start-adjust``/``stop-adjust`` pair since the dial was last reset — exact
    ``Fraction`` arithmetic on the printed decimals.  Structural misuse (a dial started twice,
    stopped while idle, started when locked, or running at an activation) is a
    :class:`PlanReadError`; bounds and everything else are left to catc's validator.
    """
    starts = {d.start: d for d in export.dials.values()}
    stops = {d.stop: d for d in export.dials.values()}
    value = {k: d.lower for k, d in export.dials.items()}
    since: dict[str, Fraction] = {}
    locked: set[str] = set()
    steps: list[tuple[Activation, ...]] = []
    timed = sorted(enumerate(read_timed_actions(text)), key=lambda x: (x[1].time, x[0]))
    if not timed:
        raise PlanReadError("no timed actions ('TIME: (ACTION) [DURATION]' lines) in the plan text")
    for _, ta in timed:
        if ta.name in starts:
            d = starts[ta.name]
            if d.key in since:
                raise PlanReadError(f"{ta.name} at {decimal_text(ta.time)}: the dial of {d.key} is already turning")
            if d.key in locked:
                raise PlanReadError(f"{ta.name} at {decimal_text(ta.time)}: {d.key} is already set by an activation")
            since[d.key] = ta.time
        elif ta.name in stops:
            d = stops[ta.name]
            if d.key not in since:
                raise PlanReadError(f"{ta.name} at {decimal_text(ta.time)}: the dial of {d.key} is not turning")
            value[d.key] += ta.time - since.pop(d.key)
        elif ta.name in export.actions:
            act = export.actions[ta.name]
            params = dict(act.params)
            for d in export.dials.values():
                if d.morphism != act.morphism:
                    continue
                if d.key in since:
                    raise PlanReadError(f"{ta.name} at {decimal_text(ta.time)}: the dial of {d.key} is still turning")
                params[d.param] = value[d.key]
                if d.reset:
                    value[d.key] = d.lower
                if d.lock is not None:
                    locked.add(d.key)
            steps.append((Activation(act.morphism, params),))
        else:
            raise PlanReadError(f"unknown action {ta.name!r} at {decimal_text(ta.time)} (not in this export)")
    return Plan(tuple(steps))


def timed_plan_text(
    export: Export, activations: list[tuple[str, Mapping[str, Fraction]]], *, gap: Fraction = SMTPLAN_EPSILON
) -> str:
    """The timed plan SMTPlan+ would print for ground action names and dial values:
    for each activation, start each dial that must move, wait value − current, stop it, then
    the action; happenings ``gap`` apart.  (Used by tests; values exact.)"""
    t = Fraction(0)
    cur = {k: d.lower for k, d in export.dials.items()}
    lines = []

    def emit(name: str) -> None:
        lines.append(f"{decimal_text(t, 12)}:\t({name}) [0.0]")

    for name, values in activations:
        act = export.actions[name]
        for d in export.dials.values():
            if d.morphism != act.morphism or d.param not in values:
                continue
            delta = Fraction(values[d.param]) - cur[d.key]
            if delta < 0:
                raise ValueError(
                    f"{d.key} = {values[d.param]} is below the dial's current value {cur[d.key]}: a dial only rises"
                )
            if delta:
                emit(d.start)
                t += delta  # the dial runs for exactly value − current value
                emit(d.stop)
                t += gap
                cur[d.key] += delta
        emit(name)
        t += gap
        for d in export.dials.values():
            if d.morphism == act.morphism and d.reset:
                cur[d.key] = d.lower
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- running SMTPlan+


@dataclass
class SmtplanResult:
    status: str  # "sat", "nosolution", "timeout", "error"
    plan_text: str = ""
    wall: float = 0.0
    output: str = ""
    actions: list[TimedAction] = field(default_factory=list)


def smtplan_binary() -> str | None:
    return shutil.which("SMTPlan")


def run_smtplan(domain, problem, *, timeout: float = 60.0) -> SmtplanResult:
    """Run an ``SMTPlan`` executable found on PATH (there is no package of it); the caller
    checks :func:`smtplan_binary` first."""
    exe = smtplan_binary()
    if exe is None:
        raise FileNotFoundError(SMTPLAN_HINT)
    start = time.perf_counter()
    try:
        proc = subprocess.run(
            [exe, str(domain), str(problem)],
            capture_output=True,
            text=True,
            timeout=timeout,
            check=False,
            preexec_fn=lift_memory_limit,
        )
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        return SmtplanResult("timeout", wall=time.perf_counter() - start, output=out)
    wall = time.perf_counter() - start
    text = proc.stdout + "\n" + proc.stderr
    try:
        acts = read_timed_actions(proc.stdout)
    except PlanReadError:
        acts = []
        status = "error"
    else:
        status = "sat" if acts else ("error" if proc.returncode else "nosolution")
    return SmtplanResult(status, proc.stdout, wall, text, acts)
