"""What approving a request would deploy: the request's restoration applied to the model in
memory, decided as the loop decides (:func:`catrt.decide.decide`), grounded, and compared with
the deployed generation.  Nothing is written to the store; the answer is what the loop would
do if nothing else happens before the approval."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from catrt.store import Store


def preview(store: Store, folder: Path, request: str) -> tuple[str, str | None]:
    """(the decision's reason, the diff's text or None when it would deploy nothing)."""
    from catc.api import deployment, diff_artifacts, read_grounding, read_plan, write_files
    from catrt.apply import apply_change, check
    from catrt.config import load_config
    from catrt.decide import Limits, RelaxPolicy, decide
    from catrt.events import Event
    from catrt.model import ModelState
    from catrt.runtime import MODEL_FOLDER
    from catrt.views import diff_text, generation_folder

    approval = next(a for a in store.approvals() if a["id"] == request)
    sources, state = store.sources(), ModelState.from_json(store.get("model"))
    current = check(state, sources, str(folder / MODEL_FOLDER))
    change = Event(f"preview-{request}", {"set": approval["proposal"].get("set", {})}, "console", False)
    state, origins = apply_change(state, current.instance, sources, change)
    candidate = check(state, sources, str(folder / MODEL_FOLDER), origins)
    incumbent: dict[str, Any] | None = store.get("incumbent")
    config = load_config(folder)
    limits = {"compose": 120.0, "diagnose": 30.0, "relax": 30.0, **config.limits}  # as the loop's
    decision = decide(candidate.model, incumbent["plan"] if incumbent else None,
                      Limits(limits["compose"], limits["diagnose"], limits["relax"], limits.get("decision")),
                      policy=RelaxPolicy(dict(config.relax_weights), config.relax_fixed))  # fmt: skip
    if not decision.action.deploys or decision.plan is None:
        return str(decision.reason), None
    plan = read_plan(candidate.instance, decision.to_json()["plan"])
    files, manifest = deployment(candidate.instance, plan, "preview")
    with tempfile.TemporaryDirectory(prefix="catrt-preview-") as tmp:
        write_files(Path(tmp), files, manifest)
        new = read_grounding(tmp)
    old_generation = incumbent["generation"] if incumbent else 0
    old = read_grounding(str(generation_folder(folder, old_generation))) if incumbent else {}
    return str(decision.reason), diff_text(diff_artifacts(old, new), old_generation, old_generation + 1)
