"""IR expressions back to .cat text (for objectives in reports and synthesised skeletons).

``to_text(parse(x)) `` reads back as the same IR; numbers print exactly (``0.08``,
``(/ 1 3)``), so a printed skeleton loses nothing.
"""

from __future__ import annotations

from collections.abc import Callable

from catc import ir
from catc.ir.numbers import number_text


def _const(e: ir.Const) -> str:
    if isinstance(e.value, bool):
        return "true" if e.value else "false"
    if isinstance(e.value, str):
        return e.value
    return number_text(e.value)


def _call(head: str, args) -> str:
    return f"({head}{''.join(' ' + to_text(a) for a in args)})"


_PRINT: dict[type, Callable[[object], str]] = {
    ir.Const: _const,
    ir.ResourceRef: lambda e: e.name,
    ir.ParamRef: lambda e: e.name,
    ir.SetLit: lambda e: "{" + " ".join(to_text(x) for x in e.elements) + "}",
    ir.Arith: lambda e: _call(e.op.value, e.args),
    ir.Compare: lambda e: _call(e.op.value, (e.left, e.right)),
    ir.BoolOp: lambda e: _call(e.op.value, e.args),
    ir.Ite: lambda e: _call("if", (e.cond, e.then, e.orelse)),
    ir.Member: lambda e: _call("member", (e.element, e.set)),
    ir.TotalChurn: lambda e: "(total-churn)",
    ir.TotalCost: lambda e: "(total-cost)",
    ir.Uses: lambda e: f"(uses {e.morphism})",
    ir.ParamValue: lambda e: f"(param {e.morphism} {e.param})",
}


def to_text(e: ir.Expr) -> str:
    return _PRINT[type(e)](e)


def effect_text(e: ir.Effect) -> str:
    return f"({e.kind.value} {e.resource} {to_text(e.value)})"
