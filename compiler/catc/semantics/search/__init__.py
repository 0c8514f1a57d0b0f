"""A forward state-space search for shortest sequential compositions: greedy best-first on a
numeric h_add for a first composition, then A* with a numeric h^max to prove it shortest.

The greedy phase (:func:`_greedy`, h_add over the conditions cut into atoms by :class:`_Atoms`,
or over literals on bitmasks; ordered first by the counting bound where the task has numeric
goal conditions) is inadmissible and claims nothing about length; its plan is shortened through
its neighbourhood (:func:`_improve`), and A* below that length (:func:`_astar`) either finds a
shorter composition or proves that there is none. The rest of this docstring is about A*.

For numeric tasks A*'s heuristic is the largest of h^max (below), a goal-achiever bound read
off h^max's layers (:meth:`_Task._achiever_bound`: a goal fact's achiever cannot fire before
its layer, and the achievers of goal facts independent of it are further steps) and an
operator-counting bound (:class:`_Counting`: a linear program over how often each morphism
fires, solved exactly), all read against the bounds every reachable state keeps — declared, or inferred from the
preconditions that guard every change of a number (:func:`infer_bounds`).

For ground instances (morphisms without parameters, as :mod:`catc.frontend.up_import` makes
them) the shortest sequential composition is found by A* over the concrete states (exact
``Fraction`` arithmetic), guided by an admissible and consistent heuristic: the number of
layers of an *interval relaxation* after which the goal can hold (h^max generalised to numbers,
as ENHSP's ``hrmax``). Layer 0 is the state itself, each resource a point (a number an
interval, a Boolean or symbol a set of possible values); layer i+1 joins into layer i the
effects of every morphism whose preconditions can hold in layer i. Every state reachable in i
steps lies within layer i, so the layer where the goal first can hold is a lower bound on the
distance to the goal, and a layer that no longer changes without the goal proves a dead end.

What the search answers, all of it a proof (the validator still replays every composition):

* a composition of L steps — the shortest (A* with an admissible heuristic, unit steps),
  unless ``shortest`` is False (the greedy composition, A* stopped by the time);
* none within the horizon k — every state within k steps was expanded or pruned by the
  heuristic (whose bound is sound);
* none of any length (``final``) — additionally no state was cut by the horizon: the
  reachable state space was exhausted (by A*, dead ends proven by the relaxation; or by the
  greedy phase, which prunes nothing).

Instances with what the search does not model (parameters, sets, holes, use limits, an
effect that assigns and increases one resource, a resource without an initial value) are
answered :attr:`SearchStatus.UNSUPPORTED`, and the caller falls back to the SMT encoding.

The package's parts: :mod:`.common` (the answer, exact numbers, linear forms), :mod:`.terms`
(concrete and relaxed conditions), :mod:`.task` (the ground task, h^max and the achiever
bound), :mod:`.bounds` (inferred bounds), :mod:`.counting` (the operator-counting bound),
:mod:`.atoms` (h_add), :mod:`.strips` (the bitmask fast path) and :mod:`.algorithms` (greedy,
A*, the neighbourhood, :func:`search`).
"""

from catc.semantics.search.algorithms import reachable_states, search
from catc.semantics.search.atoms import _Atoms
from catc.semantics.search.bounds import infer_bounds
from catc.semantics.search.common import SearchResult, SearchStatus, _Unsupported
from catc.semantics.search.counting import _Counting, _Dual, _max_dual
from catc.semantics.search.strips import _Strips
from catc.semantics.search.task import _inline_statics, _Task

__all__ = [
    "SearchResult",
    "SearchStatus",
    "_Atoms",
    "_Counting",
    "_Dual",
    "_Strips",
    "_Task",
    "_Unsupported",
    "_inline_statics",
    "_max_dual",
    "infer_bounds",
    "reachable_states",
    "search",
]
