"""The Python API, at its public address: ``from catc.api import load``.

Everything lives in :mod:`catc.interfaces.api`; this module names what programs may rely on
(docs/api.md).
"""

from catc.interfaces.api import CatError, Model, load, loads
from catgrammar.limits import Limits

__all__ = ["CatError", "Limits", "Model", "load", "loads"]
