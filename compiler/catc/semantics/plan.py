"""Compositions (plans): what a solve returns and what the validator replays.

A :class:`Plan` is a sequence of steps; each step is a set of activations that run in
parallel (⊗), and steps compose serially (∘).  Values are exact: ``Fraction`` for numbers,
``bool``, and ``str`` for symbols.  A symbol that is not a constant of the model is a *fresh*
(reserve) value of the sort recorded in ``Plan.fresh`` (finite grounding, Proposition 1).

The JSON form (schema ``catc.plan/1``, docs/cli.md) writes numbers as strings of exact
rationals (``"17/4"``) or integers, so nothing is ever a float.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from fractions import Fraction
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, TypeAlias

from catc.ir.numbers import fraction_text
from catgrammar.record import Record, set_field

if TYPE_CHECKING:  # pragma: no cover
    from catc import ir

Value: TypeAlias = Fraction | bool | str
SetValue: TypeAlias = frozenset[str]  # of symbol names
StateValue: TypeAlias = Value | SetValue
State: TypeAlias = Mapping[str, StateValue]

PLAN_SCHEMA = "catc.plan/1"
#: The ``--json`` answers whose ``steps`` and ``fresh`` are a plan too: ``catc validate`` reads
#: them as it reads a ``catc.plan/1`` document (their other fields are ignored).
ANSWER_SCHEMAS = ("catc.solve/1", "catc.optimize/1", "catc.recompose/1")
#: A grounding's manifest (``catc ground``, a runtime generation) carries its composition under "plan".
MANIFEST_SCHEMA = "catc.ground/1"


def fresh_name(sort: str, n: int) -> str:
    """Reserve values are shown as ``topic#1``: '#' cannot occur in a name of the language."""
    return f"{sort}#{n}"


class Activation(Record):
    """One use of a morphism, with the values of its parameters θ."""

    __slots__ = ("morphism", "params")
    morphism: str
    params: Mapping[str, Value]

    def __init__(self, morphism: str, params: Mapping[str, Value] | None = None) -> None:
        set_field(self, "morphism", morphism)
        set_field(self, "params", MappingProxyType(dict(params or {})))

    def __hash__(self) -> int:  # params is a mapping: unhashable, as the dataclass was
        raise TypeError(f"unhashable type: {type(self).__name__!r}")


class Plan(Record):
    """Steps of parallel activations, and the sorts of the reserve (fresh) values used."""

    __slots__ = ("steps", "fresh")
    steps: tuple[tuple[Activation, ...], ...]
    fresh: Mapping[str, str]  # value → sort

    def __init__(self, steps: Iterable[Iterable[Activation]], fresh: Mapping[str, str] | None = None) -> None:
        set_field(self, "steps", tuple(tuple(s) for s in steps))
        set_field(self, "fresh", MappingProxyType(dict(fresh or {})))

    def __hash__(self) -> int:
        raise TypeError(f"unhashable type: {type(self).__name__!r}")

    @property
    def activations(self) -> list[tuple[int, Activation]]:
        return [(i, a) for i, step in enumerate(self.steps) for a in step]

    @property
    def components(self) -> frozenset[str]:
        """A_b: the morphisms used at least once (for churn)."""
        return frozenset(a.morphism for _, a in self.activations)

    def __len__(self) -> int:
        return len(self.steps)


# ---------------------------------------------------------------- exact values in JSON


def value_to_json(v: StateValue) -> Any:
    if isinstance(v, bool):
        return v
    if isinstance(v, Fraction):
        # an integer is a JSON integer, but for one of more digits than JSON readers take
        # (Python's: 4,300): that one is a string of digits, as other rationals are strings
        if v.denominator == 1 and abs(v.numerator) < _JSON_INTEGERS:
            return int(v)
        return fraction_text(v)
    if isinstance(v, frozenset):
        return sorted(v)
    return v


_JSON_INTEGERS = 10**4000


class PlanFormatError(ValueError):
    """A plan file that does not follow ``catc.plan/1``."""


def _number_from_json(x: Any, where: str) -> Fraction:
    if isinstance(x, bool):
        raise PlanFormatError(f"{where}: expected a number, got {x!r}")
    if isinstance(x, int):
        return Fraction(x)
    if isinstance(x, str):
        try:
            return Fraction(x)
        except (ValueError, ZeroDivisionError):
            raise PlanFormatError(f'{where}: {x!r} is not an exact number such as "17/4" or "0.1"') from None
    if isinstance(x, float):
        raise PlanFormatError(f'{where}: floats are not exact; write {x!r} as a string such as "{x}"')
    raise PlanFormatError(f"{where}: expected a number, got {x!r}")


def plan_to_json(plan: Plan) -> dict[str, Any]:
    return {
        "schema": PLAN_SCHEMA,
        "steps": [
            [{"morphism": a.morphism, "params": {k: value_to_json(v) for k, v in a.params.items()}} for a in step]
            for step in plan.steps
        ],
        "fresh": dict(plan.fresh),
    }


def param_sorts(inst: ir.Instance) -> dict[str, dict[str, str]]:
    """How to read each parameter of a ``catc.plan/1`` document: 'bool', 'int', 'real' or 'symbol'."""
    return {
        m.name: {p.name: (p.sort.kind.value if not p.sort.is_symbolic else "symbol") for p in m.params}
        for m in inst.morphisms.values()
    }


def read_plan(inst: ir.Instance, doc: Any) -> Plan:
    """A plan document (``catc.plan/1``, or an answer holding one) read against the checked
    instance ``inst``, each parameter by its sort; :class:`PlanFormatError` when malformed."""
    return plan_from_json(doc, param_sorts(inst))


def plan_from_json(doc: Any, param_sorts: Mapping[str, Mapping[str, str]]) -> Plan:
    """Read a plan; ``param_sorts[morphism][param]`` is 'bool', 'int', 'real' or 'symbol'
    (decides how each JSON value is read).  Unknown morphisms/params are kept as given so
    the validator can report them."""
    if not isinstance(doc, dict):
        raise PlanFormatError('a plan is a JSON object with a "steps" list')
    if doc.get("schema") == MANIFEST_SCHEMA:  # a grounding's manifest: the composition it grounded
        doc = doc.get("plan")
        if not isinstance(doc, dict):
            raise PlanFormatError('this catc.ground/1 manifest holds no composition ("plan")')
    schema = doc.get("schema", PLAN_SCHEMA)
    if schema != PLAN_SCHEMA and schema not in ANSWER_SCHEMAS:
        accepted = ", ".join(repr(s) for s in (PLAN_SCHEMA, *ANSWER_SCHEMAS, MANIFEST_SCHEMA))
        raise PlanFormatError(f"unsupported plan schema {schema!r}; expected one of {accepted}")
    steps_doc = doc.get("steps")
    if schema in ANSWER_SCHEMAS and steps_doc is None:
        status = doc.get("status")
        raise PlanFormatError(f"this {schema} answer holds no composition (status {status!r})")
    if not isinstance(steps_doc, list):
        raise PlanFormatError('"steps" must be a list of steps, each a list of activations')
    steps = []
    for i, step in enumerate(steps_doc):
        if not isinstance(step, list):
            raise PlanFormatError(f"step {i}: expected a list of activations")
        acts = []
        for j, act in enumerate(step):
            where = f"step {i}, activation {j}"
            if not isinstance(act, dict) or not isinstance(act.get("morphism"), str):
                raise PlanFormatError(f'{where}: expected {{"morphism": NAME, "params": {{...}}}}')
            params_doc = act.get("params", {})
            if not isinstance(params_doc, dict):
                raise PlanFormatError(f'{where}: "params" must be an object')
            sorts = param_sorts.get(act["morphism"], {})
            params: dict[str, Value] = {}
            for name, raw in params_doc.items():
                kind = sorts.get(name)
                if kind in ("int", "real"):
                    params[name] = _number_from_json(raw, f"{where}, parameter {name}")
                elif kind == "bool":
                    if not isinstance(raw, bool):
                        raise PlanFormatError(f"{where}, parameter {name}: expected true or false")
                    params[name] = raw
                elif isinstance(raw, (str, bool)):
                    params[name] = raw
                else:
                    params[name] = _number_from_json(raw, f"{where}, parameter {name}")
            acts.append(Activation(act["morphism"], params))
        steps.append(tuple(acts))
    fresh = doc.get("fresh", {})
    if not isinstance(fresh, dict) or not all(isinstance(k, str) and isinstance(v, str) for k, v in fresh.items()):
        raise PlanFormatError('"fresh" must map fresh symbol values to their sort names')
    return Plan(tuple(steps), fresh)
