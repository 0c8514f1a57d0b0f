"""Frozen slotted records without ``@dataclass``'s start-up cost.

Generating a dataclass compiles six functions per class (``exec`` of generated source),
about 0.6 ms each class; with the AST's and the IR's ~70 classes that was ~40 ms of every
``catc`` start.  A :class:`Record` subclass lists ``__slots__`` and spells out its
``__init__``; this base supplies the rest with the behaviour of
``@dataclass(frozen=True, slots=True)``: immutable (:class:`dataclasses.FrozenInstanceError`),
equality and hash over the compared fields in order (``_compared``, default: all — the
equivalent of ``field(compare=False)`` for the others, which are also left out of the repr),
private caches in ``__slots__`` that are not fields (``_fields`` lists the fields when some
slots are not),
``ClassName(field=value, ...)`` repr, ``__match_args__``, pickling, and
``__dataclass_fields__``, so ``dataclasses.fields``/``replace``/``asdict`` work.
:mod:`dataclasses` itself is imported only when one of those is used: importing it costs
~7 ms of start-up (it imports :mod:`inspect`), so ``__dataclass_fields__`` is built on first
access and :func:`replace` here does what ``dataclasses.replace`` does.
``tests/test_generated_parser.py`` and ``tests/test_ir.py`` check all of it against real
dataclasses.
"""

from __future__ import annotations

from collections.abc import Callable
from operator import attrgetter
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, TypeVar

if TYPE_CHECKING:
    from dataclasses import Field

set_field = object.__setattr__  # for the hand-written ``__init__`` of frozen records

R = TypeVar("R", bound="Record")


class _Getter(Protocol):
    """The compared fields of a record, as a tuple (a protocol rather than a ``Callable`` so
    that mypy does not take the class attribute holding it for a method bound to ``self``)."""

    def __call__(self, obj: Any, /) -> tuple[Any, ...]: ...


def _getter(names: tuple[str, ...]) -> Callable[[Any], tuple[Any, ...]]:
    """A function returning the named attributes as a tuple (also for one name)."""
    if len(names) == 1:
        one = attrgetter(names[0])
        return lambda obj: (one(obj),)
    return attrgetter(*names)


class _DataclassFields:
    """``Record.__dataclass_fields__``: the ``dataclasses.Field`` objects ``@dataclass`` would
    have made, built on first access and then stored on the class in its place."""

    def __get__(self, obj: object, cls: type[Record]) -> dict[str, Field[Any]]:
        import dataclasses

        fields: dict[str, Field[Any]] = {}
        for name in cls._fields:
            f: Field[Any] = dataclasses.field(compare=name in cls._compared, repr=name in cls._compared)
            f.name, f.type, f.kw_only = name, cls.__annotations__[name], False
            f._field_type = dataclasses._FIELD  # type: ignore[attr-defined]  # private: as @dataclass sets it
            fields[name] = f
        type.__setattr__(cls, "__dataclass_fields__", fields)
        return fields


_DATACLASS_FIELDS = _DataclassFields()


def replace(obj: R, /, **changes: Any) -> R:
    """A copy of the record ``obj`` with ``changes``, as ``dataclasses.replace`` makes it."""
    for name in obj._fields:
        if name not in changes:
            changes[name] = getattr(obj, name)
    return obj.__class__(**changes)


class Record:
    """Base of frozen slotted records; see the module docstring."""

    __slots__ = ()
    __match_args__: ClassVar[tuple[str, ...]] = ()
    _fields: ClassVar[tuple[str, ...]]  # the fields, in order (default: every slot)
    _compared: ClassVar[tuple[str, ...]]  # the fields taking part in ==, hash and repr
    _values: ClassVar[_Getter]  # getter of the compared fields, in order
    # what ``dataclasses.fields``/``replace`` look for (set per class, built on first access)
    __dataclass_fields__: ClassVar[dict[str, Field[Any]]]

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        names: tuple[str, ...] = cls.__dict__.get("_fields", cls.__slots__)
        compared = cls.__dict__.get("_compared", names)
        cls._fields = names
        cls.__match_args__ = names  # type: ignore[misc]  # each record class matches on its own fields
        cls._compared = compared
        # a staticmethod: the one-field getter is a lambda, which would otherwise bind ``self``
        cls._values = staticmethod(_getter(compared))
        # every class gets its own, so a subclass never sees its base's fields
        type.__setattr__(cls, "__dataclass_fields__", _DATACLASS_FIELDS)

    def __setattr__(self, name: str, value: Any) -> None:
        from dataclasses import FrozenInstanceError

        raise FrozenInstanceError(f"cannot assign to field {name!r}")

    def __delattr__(self, name: str) -> None:
        from dataclasses import FrozenInstanceError

        raise FrozenInstanceError(f"cannot delete field {name!r}")

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return self._values(self) == self._values(other)
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self._values(self))

    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={getattr(self, name)!r}" for name in self._compared)
        return f"{type(self).__qualname__}({fields})"

    def __getstate__(self) -> list[Any]:
        return [getattr(self, name) for name in self._fields]

    def __setstate__(self, state: list[Any]) -> None:
        self.__init__(*state)  # type: ignore[misc]  # each record's own __init__; also rebuilds private caches
