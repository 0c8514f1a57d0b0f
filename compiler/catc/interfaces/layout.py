"""A target's artifact as every interface hands it out: made by the target's ``run``, then,
for a target that writes ``.cat`` text (:attr:`catc.targets.base.Target.layout`), laid out
by ``catc fmt``'s formatter — which the targets may not import (past the front end, no
tokenizer), so the interfaces pass it in here, in one place."""

from __future__ import annotations

from typing import Any

from catc import ir
from catc.targets.base import Target


def laid_out(target: Target, artifact: Any) -> Any:
    """``artifact`` with the target's layout applied (itself when the target has none)."""
    if target.layout is None:
        return artifact
    from catc.frontend.formatter import format_text

    return target.layout(artifact, format_text)


def export(target: Target, inst: ir.Instance, options: dict[str, Any]) -> Any:
    """Run ``target`` on ``inst`` with its run ``options``, laid out."""
    return laid_out(target, target.run(inst, **options))


__all__ = ["export", "laid_out"]
