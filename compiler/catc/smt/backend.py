"""The backend protocol: what every query may ask of a solver, and nothing more.

A :class:`Backend` is fed the encoder's script (declarations and labelled assertions,
:mod:`catc.smt.script`) and the queries' own :mod:`~catc.smt.terms`; it checks, under
assumptions, inside push/pop scopes; it answers with a :class:`Check`, an unsat core (the
assumed :class:`~catc.smt.script.Symbol` s that conflict), a model's values as exact
``Fraction`` s and ``bool`` s, and — where it can optimise — each objective's :class:`Bound`.
No module outside the backends imports a solver; no value crosses the boundary as text.

Backends are found by name in :data:`BACKENDS` and imported only when opened, so a missing
optional solver is an error naming its package, not an import failure at start-up.  A new
backend is one module implementing :class:`Backend` plus one entry in :data:`BACKENDS`.
"""

from __future__ import annotations

import sys
from abc import ABC, abstractmethod
from collections.abc import Sequence
from contextvars import ContextVar
from enum import Enum
from fractions import Fraction
from typing import Any

from catc.smt.script import Assertion, Symbol
from catc.smt.terms import Term
from catgrammar.record import Record, set_field
from catgrammar.registry import Registry, UnknownName


class Check(str, Enum):
    SAT = "sat"
    UNSAT = "unsat"
    UNKNOWN = "unknown"


class Capability(str, Enum):
    """What a backend can do beyond checking satisfiability."""

    MODELS = "models"  # values after SAT
    CORES = "cores"  # unsat cores over the assumptions
    OPTIMIZE = "optimize"  # minimize / maximize / soft constraints (open with optimize=True)
    LOGIC = "logic"  # a solver configured for a named logic (open with logic=...)


class Bound(Record):
    """An objective's optimum as the solver reports it: ``infinite``·∞ + ``value`` +
    ``epsilon``·ε.  ``infinite`` is −1, 0 or 1; a non-zero ``epsilon`` means the value is a
    supremum or infimum that no model attains."""

    __slots__ = ("infinite", "value", "epsilon")
    infinite: int
    value: Fraction
    epsilon: Fraction

    def __init__(self, infinite: int, value: Fraction, epsilon: Fraction = Fraction(0)) -> None:
        set_field(self, "infinite", infinite)
        set_field(self, "value", value)
        set_field(self, "epsilon", epsilon)

    @property
    def exact(self) -> bool:
        return self.infinite == 0 and self.epsilon == 0


class BackendError(Exception):
    """A backend cannot be opened (its package is missing) or cannot do what was asked."""


class Backend(ABC):
    """One solver instance.  Open one with :func:`open_backend`."""

    name: str = ""
    capabilities: frozenset[Capability] = frozenset()
    #: the most memory (MB) this solver may allocate during a check (0: no limit); set per
    #: backend by :func:`open_backend`
    memory: int = 0

    # ------------------------------------------------------------ input
    @abstractmethod
    def add(self, decls: Sequence[Symbol], asserts: Sequence[Assertion]) -> None:
        """Declare ``decls`` and assert ``asserts`` (label, SMT-LIB text), in one batch."""

    @abstractmethod
    def assert_term(self, term: Term) -> None:
        """Assert one query term."""

    def intern(self, term: Term) -> Term:
        """The same term, prepared once for repeated use (an objective read after every
        check); by default the term itself."""
        return term

    @abstractmethod
    def push(self) -> None: ...

    @abstractmethod
    def pop(self) -> None: ...

    # ------------------------------------------------------------ checking
    @abstractmethod
    def set_timeout(self, seconds: float | None) -> None:
        """A limit for each following check (None: none)."""

    @abstractmethod
    def check(self, assumptions: Sequence[Symbol] = ()) -> Check:
        """Satisfiability of the assertions with the Boolean ``assumptions`` assumed true."""

    @abstractmethod
    def reason_unknown(self) -> str: ...

    def core(self) -> list[Symbol]:
        """After UNSAT under assumptions: a subset of the assumptions that conflicts."""
        raise self.unsupported(Capability.CORES)

    def has_model(self) -> bool:
        """Whether a model can be read (after SAT, or a stopped optimisation's best)."""
        return False

    def value(self, term: Term) -> Fraction | bool:
        """The value of ``term`` in the current model: ``bool``, or an exact ``Fraction``
        (for Int and Real terms alike); unconstrained constants take a default value."""
        raise self.unsupported(Capability.MODELS)

    # ------------------------------------------------------------ optimisation
    def minimize(self, term: Term) -> Any:
        """Add an objective (priority: the order of the calls); returns its handle."""
        raise self.unsupported(Capability.OPTIMIZE)

    def maximize(self, term: Term) -> Any:
        raise self.unsupported(Capability.OPTIMIZE)

    def add_soft(self, term: Term, weight: Fraction, group: str | None = None) -> Any:
        """A soft constraint: its weight is paid when ``term`` is false.  The soft constraints
        of one ``group`` form one objective (the sum paid; priority: where the group was
        first added among the objectives); returns the group's handle for :meth:`bound`."""
        raise self.unsupported(Capability.OPTIMIZE)

    def bound(self, handle: Any) -> Bound:
        """The optimum of an objective after a finished check."""
        raise self.unsupported(Capability.OPTIMIZE)

    def unsupported(self, capability: Capability) -> BackendError:
        return BackendError(f"the {self.name} backend cannot do this: no {capability.value} support")


#: The solver memory (MB, 0: no limit) that :func:`open_backend` gives a backend when the
#: caller names none: a context variable, as the limits in force are
#: (:mod:`catgrammar.limits`), so each thread starts at 0.  Only the ``catc`` executable sets
#: it (``--memory``, docs/limits.md, :func:`limit_solver_memory`); the library leaves it at 0.
_SOLVER_MEMORY: ContextVar[int] = ContextVar("catc_solver_memory", default=0)


def limit_solver_memory(megabytes: int) -> None:
    """The solver memory of the backends opened from now on in this context (the executable's
    ``--memory``).  Z3 applies it during its checks only: when its parser runs out, Z3 ends
    the process."""
    _SOLVER_MEMORY.set(megabytes)


def solver_memory() -> int:
    """The solver memory :func:`open_backend` gives in this context (MB, 0: no limit)."""
    return _SOLVER_MEMORY.get()


#: The solver contexts kept to the end of the process instead of being freed, in this context
#: (None: none are): the executable's, which ends with ``os._exit`` (catc.interfaces.entry.leave)
#: once its answer is printed, so freeing a context it made only costs time — 2–5 ms for Z3's,
#: a few per cent of a small query (Z3: with the first solver made in it, whose freeing costs
#: 1–5 ms more; its memory is then held to the end, as the context's is).  At most
#: :data:`KEEP_AT_MOST`, so a query that makes many contexts still frees all but the first few.
_KEPT: ContextVar[list[object] | None] = ContextVar("catc_kept_contexts", default=None)
KEEP_AT_MOST = 4


def keep_solver_contexts() -> None:
    """Keep the first :data:`KEEP_AT_MOST` solver contexts opened from now on in this context
    until the process ends (the executable's setting, made with its memory limit)."""
    _KEPT.set([])


def kept(context: object) -> None:
    """A backend made ``context``: kept to the process's end when :func:`keep_solver_contexts` says so."""
    found = _KEPT.get()
    if found is not None and len(found) < KEEP_AT_MOST:
        found.append(context)


def kept_mark() -> int:
    """How many solver contexts are kept so far (for :func:`release_kept`)."""
    found = _KEPT.get()
    return 0 if found is None else len(found)


def release_kept(mark: int) -> None:
    """Keep no longer the solver contexts kept since :func:`kept_mark` gave ``mark``: each is
    freed once nothing refers to it, and the next context made reuses its memory (the
    executable's allocator setting, :func:`_reuse_freed_memory`) — Z3 writes ~16 MB into
    every new context, ~11 ms of fresh pages, ~1 ms in memory a freed one leaves."""
    found = _KEPT.get()
    if found is not None:
        del found[mark:]


_REUSING: list[bool] = []  # [True] once :func:`_reuse_freed_memory` has run


def _reuse_freed_memory() -> None:
    """The executable's allocator setting (glibc; elsewhere nothing), made before its first
    solver context: blocks up to 32 MB come from the heap instead of a mapping of their own,
    and up to 256 MB of freed heap stay in the process — so a context freed by
    :func:`release_kept` costs ~0.1 ms instead of 1–5 (no unmapping) and leaves its pages,
    already touched, to the next context."""
    if _REUSING:
        return
    _REUSING.append(True)
    if not sys.platform.startswith("linux"):
        return
    import ctypes  # the Z3 binding has imported it already

    mallopt = getattr(ctypes.CDLL(None), "mallopt", None)
    if mallopt is not None:
        mallopt(_M_MMAP_THRESHOLD, 32 << 20)
        mallopt(_M_TRIM_THRESHOLD, 256 << 20)


_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3  # glibc's <malloc.h>


#: Backend name → "module:class", imported on first use.
BACKENDS: dict[str, str] = {
    "z3": "catc.smt.z3backend:Z3Backend",
    "cvc5": "catc.smt.cvc5backend:Cvc5Backend",
}

DEFAULT_BACKEND = "z3"


_REGISTRY: Registry[type[Backend]] = Registry("backend", BACKENDS)


def backend_class(name: str) -> type[Backend]:
    try:
        return _REGISTRY.get(name)
    except UnknownName as exc:
        raise BackendError(str(exc)) from None


def open_backend(
    name: str = DEFAULT_BACKEND,
    *,
    optimize: bool = False,
    logic: str | None = None,
    share_with: Backend | None = None,
    memory: int | None = None,
) -> Backend:
    """A fresh solver: an optimiser with ``optimize``, configured for ``logic`` when given;
    ``share_with`` another backend of the same kind to share its term store (Z3: its
    context), so that both see the same term identities; ``memory`` the most MB it may
    allocate during a check (0: no limit; default: :func:`solver_memory`)."""
    cls = backend_class(name)
    needed = {Capability.OPTIMIZE} if optimize else set()
    if logic:
        needed.add(Capability.LOGIC)
    missing = needed - cls.capabilities
    if missing:
        what = ", ".join(sorted(c.value for c in missing))
        raise BackendError(f"the {name} backend has no {what} support")
    # the registered backends take these keywords (Backend declares no __init__: an
    # SmtlibWriter is made with others)
    if _KEPT.get() is not None:
        _reuse_freed_memory()
    backend = cls(optimize=optimize, logic=logic, share_with=share_with)  # type: ignore[call-arg]
    backend.memory = solver_memory() if memory is None else memory
    return backend
