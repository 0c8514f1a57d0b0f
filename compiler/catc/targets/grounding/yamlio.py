"""YAML as robots read it: written with PyYAML, never from text templates.

The dumper differs from ``yaml.safe_dump`` where ROS 2 and Compose would misread its output:

* no anchors or aliases, ever (PyYAML writes ``&id001`` for an object that appears twice;
  ROS 2's parameter parser refuses aliases);
* a real is always written as a float (``50.0``, ``4.25``): rclcpp refuses an integer for a
  double parameter.  A terminating decimal is written exactly; another rational has no
  exact float, and is written as the nearest double (shortest round-tripping digits);
* a string is quoted whenever a reader could take it for something else: YAML 1.1's
  Booleans and numbers (``yes``, ``on``, ``010``), and everything ROS 2's parser types
  itself — ``y``/``n``/``Y``/``N`` are Booleans there, ``0x1F`` an integer, ``1e3``,
  ``inf`` and ``nan`` doubles (rcl's ``get_value``).
"""

from __future__ import annotations

import math
import re
from fractions import Fraction
from typing import Any

from catc.ir.numbers import exact_decimal
from catc.targets.grounding.resolve import Key, Real

try:
    import yaml
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError("grounding needs the 'grounding' extra: pip install 'catc-lang[grounding]'") from exc

_RCL_BOOLS = {
    "Y", "y", "yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON",
    "N", "n", "no", "No", "NO", "false", "False", "FALSE", "off", "Off", "OFF",
}  # fmt: skip
_C_INT = re.compile(r"\s*[+-]?(0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)")
_C_FLOAT = re.compile(
    r"\s*[+-]?(\d+\.?\d*([eE][+-]?\d+)?|\.\d+([eE][+-]?\d+)?|0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)([pP][+-]?\d+)?"
    r"|inf(inity)?|nan(\(\w*\))?)",
    re.IGNORECASE,
)
_YAML_SPECIAL = {".nan", ".NaN", ".NAN", ".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF", "-.inf", "-.Inf", "-.INF"}


def typed_as_non_string(text: str) -> bool:
    """Would a plain scalar ``text`` be read as something other than a string, by ROS 2's
    parameter parser or by a YAML 1.1 reader?"""
    if text in _RCL_BOOLS or text in _YAML_SPECIAL or text in ("~", "null", "Null", "NULL", ""):
        return True
    return bool(_C_INT.fullmatch(text) or _C_FLOAT.fullmatch(text))


def float_text(v: Fraction) -> str:
    """A real as a YAML float: exact when its decimal terminates, always with a point."""
    exact = exact_decimal(v)
    if exact is not None:
        return exact if "." in exact else f"{exact}.0"
    f = float(v)
    if math.isinf(f):  # beyond a double: no float can carry it
        raise ValueError(f"{v} does not fit a floating-point parameter")
    return repr(f)


class Dumper(yaml.SafeDumper):
    """SafeDumper without aliases, with exact reals as floats and careful strings."""

    def ignore_aliases(self, data: Any) -> bool:
        return True


def _represent_real(dumper: Dumper, v: Real) -> Any:
    return dumper.represent_scalar("tag:yaml.org,2002:float", float_text(v))


def _represent_fraction(dumper: Dumper, v: Fraction) -> Any:
    if v.denominator == 1:
        return dumper.represent_int(int(v))
    return _represent_real(dumper, Real(v))


def _represent_str(dumper: Dumper, text: str) -> Any:
    style = "'" if typed_as_non_string(text) else None
    return dumper.represent_scalar("tag:yaml.org,2002:str", str(text), style=style)


Dumper.add_representer(Real, _represent_real)
Dumper.add_representer(Fraction, _represent_fraction)
Dumper.add_representer(str, _represent_str)
Dumper.add_representer(Key, lambda d, k: _represent_str(d, "{" + k + "}"))


def dump(data: Any) -> str:
    """``data`` as YAML: block style, keys in the order given, no aliases."""
    return yaml.dump(data, Dumper=Dumper, sort_keys=False, default_flow_style=False, allow_unicode=True, width=100)
