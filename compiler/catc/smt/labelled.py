"""The composition formula with one indicator literal per source label.

Every source construct's constraints are guarded by the indicator of its label (``pre/m/i``,
``eff/m/i``, ``init/r``, ``goal/i``, ``bound/m/p``, ``bounds/r``, ``uses/m``, ``horizon``),
so the lifelong queries (diagnose, relax) ask questions about subsets of labels: checking
with some indicators assumed true enforces exactly those constructs, and an unsat core over
the assumptions is a set of labels.
"""

from __future__ import annotations

from collections.abc import Iterable

from catc import ir
from catc.semantics.horizon import use_bound
from catc.smt.backend import DEFAULT_BACKEND, Backend, Check, open_backend
from catc.smt.encoder import Encoder
from catc.smt.script import SmtSort, Symbol, and_text, or_text

#: The label of "nothing happens after the horizon" (see :class:`LabelledModel`).
HORIZON = ir.Label.horizon()


class LabelledModel:
    """The composition formula with one indicator per source label.

    ``components`` fixes the set of morphisms used at least once (diagnosis relative to a
    composition).  With ``horizon_label`` the encoding extends past the horizon ``k`` — to
    the use-limit bound, or to 2k — and "nothing happens after step k" becomes the label
    ``horizon``, so a core can say that more steps would help.  ``slack`` (label → slack
    term over ``slack_decls``) weakens relaxable requirements (``catc relax``)."""

    def __init__(
        self,
        inst: ir.Instance,
        horizon: int,
        *,
        sequential: bool = False,
        components: Iterable[str] | None = None,
        horizon_label: bool = True,
        slack: dict[str, str] | None = None,
        slack_decls: Iterable[Symbol] = (),
        optimize: bool = False,
        share_with: LabelledModel | None = None,
        backend: str = DEFAULT_BACKEND,
    ):
        self.inst = inst
        self.k = horizon
        self.components = None if components is None else tuple(components)
        self.extended = extended = _extended_horizon(inst, horizon, components) if horizon_label else horizon
        self.enc = enc = Encoder(inst, extended, sequential=sequential, track=True, slack=slack)
        enc.unroll(extended)
        for t in range(horizon, extended):
            enc.add(HORIZON, f"(not {or_text(list(enc.act[t].values()))})")
        if components is not None:
            fixed = set(components)
            for m in enc.morphisms:
                used = or_text([enc.act[t][m.name] for t in range(extended)])
                enc.add(None, used if m.name in fixed else f"(not {used})")
        # Indicators: assert (=> |L:label| group) for each label.
        groups: dict[str, list[str]] = {}
        structural: list[str] = []
        for label, text in enc.script.asserts:
            (structural if label is None else groups.setdefault(label, [])).append(text)
        self.labels = list(dict.fromkeys(list(groups) + list(enc.indicators)))
        self.indicator: dict[str, Symbol] = {
            label: enc.indicators.get(label) or Symbol(f"L:{label}", SmtSort.BOOL) for label in self.labels
        }
        self._label_of = {symbol: label for label, symbol in self.indicator.items()}
        decls = [
            *slack_decls,
            *enc.script.decls,
            *(s for label, s in self.indicator.items() if label not in enc.indicators),
        ]
        asserts: list[tuple[str | None, str]] = [(None, t) for t in structural]
        asserts += [(label, f"(=> {self.indicator[label]} {and_text(parts)})") for label, parts in groups.items()]
        # the solver is opened, and the formula handed to it, on first use: a diagnosis whose
        # every test the relaxation and the validator settle never needs it
        self._pending: tuple[list[Symbol], list[tuple[str | None, str]]] | None = (decls, asserts)
        self._formula = (decls, asserts)
        self._open = (backend, optimize, share_with)
        self._backend: Backend | None = None
        self.checks = 0

    @property
    def backend(self) -> Backend:
        if self._backend is None:
            name, optimize, share_with = self._open
            self._backend = open_backend(
                name, optimize=optimize, share_with=None if share_with is None else share_with.backend
            )
            assert self._pending is not None
            self._backend.add(*self._pending)
            self._pending = None
        return self._backend

    def formula(self) -> tuple[list[Symbol], list[tuple[str | None, str]]]:
        """The declarations and assertions the solver is given (a certificate's text,
        :mod:`catc.queries.certify`); :attr:`indicator` names each label's literal."""
        return self._formula

    def check(self, labels: Iterable[str], timeout: float | None = None) -> tuple[Check, list[str]]:
        """Check with exactly ``labels`` enforced; on UNSAT also return a core (labels, in
        the order given)."""
        wanted = list(labels)
        if timeout is not None:
            self.backend.set_timeout(timeout)
        self.checks += 1
        r = self.backend.check([self.indicator[label] for label in wanted])
        if r is Check.UNSAT:
            core = {self._label_of[s] for s in self.backend.core() if s in self._label_of}
            return r, [label for label in wanted if label in core]
        return r, []

    def enforce_all(self) -> None:
        """Assert every indicator: all constructs hold (weakened only by slack)."""
        for label in self.labels:
            self.backend.assert_term(self.indicator[label])


def _extended_horizon(inst: ir.Instance, horizon: int, components: Iterable[str] | None = None) -> int:
    """Past the horizon: to the use-limit bound when it is larger, or to twice the horizon
    when some morphism is unlimited.  Relative to a composition only its components fire, so
    only their use limits count."""
    bound = use_bound(inst, None if components is None else frozenset(components))
    if bound is None:
        return max(2 * horizon, horizon)
    return max(bound, horizon)
