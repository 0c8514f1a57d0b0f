"""The categorical IR: the checked, typed, immutable model every later stage consumes.

:mod:`catc.ir.nodes` holds the node classes (re-exported here, so ``from catc import ir``
and ``ir.Morphism`` read naturally); beside them live the functions every stage shares over
the IR: :mod:`~catc.ir.views` (views as functors), :mod:`~catc.ir.fold` (constant folding),
:mod:`~catc.ir.text` (IR back to ``.cat`` text), :mod:`~catc.ir.numbers` (exact numbers as
text) and :mod:`~catc.ir.labels` (labelled constraints back to their source).
"""

from catc.ir.nodes import *  # noqa: F403
from catc.ir.nodes import __all__  # noqa: F401
