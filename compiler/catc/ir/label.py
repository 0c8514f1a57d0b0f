"""Labels as data: every constraint the encoder files under a label (``pre/m/i``,
``eff/m/i``, ``init/r``, ``goal/i``, ``soft/i``, ``bound/m/p``, ``bounds/r``, ``uses/m``,
``horizon``) is a :class:`Label`: a :class:`LabelKind` and its parts.  A label *is* its text
(``Label`` is a ``str``), so it reads, hashes, compares and prints exactly as the string it
always was in JSON, text reports and SMT-LIB2 ``:named`` attributes; building one goes
through the kind, so no stage spells the format out.  (:mod:`catc.ir.labels` maps labels
back to source; this module imports nothing of the IR, so the IR's records can use it.)
"""

from __future__ import annotations

from enum import Enum
from typing import Any


class LabelKind(str, Enum):
    """What a labelled construct is; the value is the label's first part."""

    PRE = "pre"  # pre/<morphism>/<i>: the i-th conjunct of a precondition
    EFF = "eff"  # eff/<morphism>/<i>: the i-th effect
    INIT = "init"  # init/<resource>: a resource's initial value
    GOAL = "goal"  # goal/<i>: the i-th conjunct of the goal
    SOFT = "soft"  # soft/<i>: the i-th soft constraint
    BOUND = "bound"  # bound/<morphism>/<param>: a parameter's bounds
    BOUNDS = "bounds"  # bounds/<resource>: a resource's bounds
    USES = "uses"  # uses/<morphism>: a use limit
    HORIZON = "horizon"  # horizon: nothing happens after the horizon

    @property
    def arity(self) -> int:
        """How many parts follow the kind."""
        return _ARITY[self]


_ARITY = {
    LabelKind.PRE: 2,
    LabelKind.EFF: 2,
    LabelKind.INIT: 1,
    LabelKind.GOAL: 1,
    LabelKind.SOFT: 1,
    LabelKind.BOUND: 2,
    LabelKind.BOUNDS: 1,
    LabelKind.USES: 1,
    LabelKind.HORIZON: 0,
}


class Label(str):
    """A constraint's label: ``Label(LabelKind.BOUND, "drive", "speed")`` is ``bound/drive/speed``.

    A ``str`` (its text), so labels stay byte-identical wherever they are written and are
    found in sets and dicts keyed by their text; :attr:`kind` and :attr:`parts` read it back."""

    __slots__ = ()

    def __new__(cls, kind: LabelKind, *parts: str | int) -> Label:
        if len(parts) != kind.arity:
            raise ValueError(f"a {kind.value} label has {kind.arity} part(s), not {len(parts)}: {parts!r}")
        texts = tuple(str(p) for p in parts)
        if any(not t or "/" in t for t in texts):
            raise ValueError(f"label parts must be non-empty and without '/': {texts!r}")
        return super().__new__(cls, "/".join((kind.value, *texts)))

    @classmethod
    def parse(cls, text: str) -> Label:
        """The label written ``text`` (``ValueError`` if it is not one)."""
        head, *parts = text.split("/")
        return cls(LabelKind(head), *parts)

    @property
    def kind(self) -> LabelKind:
        return LabelKind(self.split("/", 1)[0])

    @property
    def parts(self) -> tuple[str, ...]:
        return tuple(self.split("/")[1:])

    @property
    def text(self) -> str:
        """The label as a plain string (as written in JSON, reports and SMT-LIB2)."""
        return str.__str__(self)

    def __reduce__(self) -> tuple[Any, ...]:
        return (Label.parse, (self.text,))

    # One constructor per kind, named as the label reads.
    @classmethod
    def pre(cls, morphism: str, i: int) -> Label:
        return cls(LabelKind.PRE, morphism, i)

    @classmethod
    def eff(cls, morphism: str, i: int) -> Label:
        return cls(LabelKind.EFF, morphism, i)

    @classmethod
    def init(cls, resource: str) -> Label:
        return cls(LabelKind.INIT, resource)

    @classmethod
    def goal(cls, i: int) -> Label:
        return cls(LabelKind.GOAL, i)

    @classmethod
    def soft(cls, i: int) -> Label:
        return cls(LabelKind.SOFT, i)

    @classmethod
    def bound(cls, morphism: str, param: str) -> Label:
        return cls(LabelKind.BOUND, morphism, param)

    @classmethod
    def bounds(cls, resource: str) -> Label:
        return cls(LabelKind.BOUNDS, resource)

    @classmethod
    def uses(cls, morphism: str) -> Label:
        return cls(LabelKind.USES, morphism)

    @classmethod
    def horizon(cls) -> Label:
        return cls(LabelKind.HORIZON)


#: The label of "nothing happens after the horizon".
HORIZON = Label.horizon()
