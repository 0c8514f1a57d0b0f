"""``catalog`` and ``health``, applied together: morphisms added (``(:morphism ...)`` text) and
removed, morphisms failed and recovered — each name checked against the catalogue as it
stands, the event's own removals and additions included."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from catc import ir
from catgrammar.diagnostics import did_you_mean
from catrt.changes.base import Change, Rejection, balanced
from catrt.model import ModelState, morphisms_in_sources


def apply(
    state: ModelState, inst: ir.Instance, sources: Mapping[str, str], body: Mapping[str, Any], origins: dict[str, str]
) -> ModelState:
    catalog, health = body.get("catalog") or {}, body.get("health") or {}
    if not catalog and not health:
        return state
    known = set(morphisms_in_sources(sources)) | state.catalog_names
    known -= set(state.removed)
    for name in catalog.get("remove", []):
        if name not in known:
            raise Rejection(f"catalog.remove: no morphism named '{name}'{did_you_mean(name, sorted(known))}")
    for key in ("failed", "recovered"):
        for name in health.get(key, []):
            if name not in known:
                raise Rejection(f"health.{key}: no morphism named '{name}'{did_you_mean(name, sorted(known))}")
    for name in health.get("recovered", []):
        if name not in state.failed:
            raise Rejection(f"health.recovered: '{name}' is not failed")
    added = _morphisms(catalog["add"]) if "add" in catalog else []
    for name, _, _ in added:  # replacing is explicit: remove it in the same event
        if name in known and name not in catalog.get("remove", []):
            raise Rejection(
                f"catalog.add: '{name}' is already in the catalogue; to replace it, remove it in the same event "
                f'({{"catalog": {{"remove": ["{name}"], "add": ...}}}})'
            )
    for name, _, start in added:  # catalog.add@LINES:COLUMNS: how far into the field its text starts
        before = catalog["add"][:start]
        origins[f"catalog.{name}"] = f"catalog.add@{before.count(chr(10))}:{len(before) - before.rfind(chr(10)) - 1}"
    return state.with_catalog(
        add=[(name, text) for name, text, _ in added],
        remove=catalog.get("remove", []),
        failed=health.get("failed", []),
        recovered=health.get("recovered", []),
        sources=sources,
    )


def _morphisms(text: str) -> list[tuple[str, str, int]]:
    """``(:morphism NAME ...) ...`` → [(NAME, its text, where it starts)], else Rejection."""
    found = balanced(text, "catalog.add")
    out: list[tuple[str, str, int]] = []
    i = 0
    while i < len(found):
        tok = found[i]
        if not tok.opens or i + 2 >= len(found) or found[i + 1].text != ":morphism":
            raise Rejection(
                f"catalog.add: only (:morphism NAME ...) declarations, found '{tok.text}' at {tok.line}:{tok.column}"
            )
        name = found[i + 2].text
        depth, j = 0, i
        while True:
            depth += found[j].opens - found[j].closes
            if depth == 0:
                break
            j += 1
        out.append((name, text[tok.start : found[j].end], tok.start))
        i = j + 1
    return out


CHANGE = Change(("catalog", "health"), apply)
