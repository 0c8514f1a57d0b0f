"""Replay and verify: the stored state rebuilt from the journal alone, and every other check
of a state folder.

Replay starts from the ``init`` entry (the model as it was stored) and applies each accepted
event to the model again — with the same code the runtime used, checked by catc again —
comparing the model's hash after each with the one journaled; approvals apply their
proposals; decisions, ``enact-begin`` and ``enact-done`` move the generation and the
deployed composition.  The result must equal the stored state.  Solver answers are not
recomputed (they are what the journal says was decided), but every deployed composition is
replayed by the validator on the model it was deployed for.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from catc.api import text_cache
from catrt.apply import Candidate, Rejection, apply_change, check
from catrt.enact import complete, differing, generation_name
from catrt.events import Event
from catrt.model import ModelState
from catrt.runtime import GENERATIONS, MODEL_FOLDER, model_sha
from catrt.store import Store, Verdict

STATE_KEYS = ("model", "incumbent", "enacting", "generation")


@dataclass
class Replayed:
    state: dict[str, Any] = field(default_factory=dict)
    approvals: dict[str, str] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    entries: int = 0


class _Replay:
    def __init__(self, store: Store, folder: Path) -> None:
        self.store, self.folder = store, folder
        self.out = Replayed()
        self.candidate: Candidate | None = None
        self.sources: dict[str, str] = {}
        self.plans: dict[int, Any] = {}  # decision seq → its plan
        self.proposals: dict[str, Any] = {}
        self.pending_sha: str | None = None
        self.checks = text_cache()  # the sources parsed and checked once: each entry re-checks the problem

    def run(self) -> Replayed:
        st = self.out.state
        for entry in self.store.entries():
            self.out.entries += 1
            handler = getattr(self, "_" + entry["kind"].replace("-", "_"), None)
            if handler is not None:
                handler(entry["seq"], entry["data"], st)
        return self.out

    def problem(self, seq: int, message: str) -> None:
        self.out.problems.append(f"journal entry {seq}: {message}")

    def _check(self, state: ModelState, seq: int) -> None:
        try:
            self.candidate = check(state, self.sources, str(self.folder / MODEL_FOLDER), cache=self.checks)
        except Rejection as exc:
            self.problem(seq, f"the model no longer checks: {exc.text()}")

    def _init(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        self.sources = dict(data["sources"])
        state = ModelState.from_json(data["model"])
        st.update({"model": state.to_json(), "incumbent": None, "enacting": None, "generation": 0})
        self._check(state, seq)

    def _event(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        body = {k: v for k, v in data["event"].items() if k not in ("v", "id")}
        if "approve" in body or "reject" in body:
            self.pending_sha = data["model_sha256"]
            return
        if self.candidate is None:
            return
        state = ModelState.from_json(st["model"])
        try:
            state, _ = apply_change(
                state, self.candidate.instance, self.sources, Event(data["event"]["id"], body, "replay")
            )
        except Rejection as exc:
            self.problem(seq, f"the accepted event no longer applies: {exc.text()}")
            return
        self._moved(seq, state, data["model_sha256"], st)

    def _moved(self, seq: int, state: ModelState, journaled: str, st: dict[str, Any]) -> None:
        if model_sha(state) != journaled:
            self.problem(seq, "the model after this event differs from the one journaled")
        st["model"] = state.to_json()
        self._check(state, seq)

    def _approval_request(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        self.proposals[data["request"]] = data
        self.out.approvals[data["request"]] = Verdict.PENDING

    def _approval(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        request, verdict = data["request"], data["verdict"]
        self.out.approvals[request] = verdict
        if verdict != Verdict.APPROVED or self.candidate is None:
            return
        state = ModelState.from_json(st["model"])
        change = Event(request, {"set": self.proposals[request]["set"]}, "replay")
        try:
            state, _ = apply_change(state, self.candidate.instance, self.sources, change)
        except Rejection as exc:
            self.problem(seq, f"the approved proposal no longer applies: {exc.text()}")
            return
        self._moved(seq, state, self.pending_sha or "", st)

    def _decision(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        self.plans[seq] = data.get("plan")

    def _enact_begin(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        st["generation"] = data["generation"]
        st["enacting"] = {"generation": data["generation"], "decision": data["decision"],
                          "plan": self.plans.get(data["decision"])}  # fmt: skip

    def _enact_done(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        enacting = st.get("enacting")
        if enacting is None or enacting["generation"] != data["generation"]:
            self.problem(seq, f"enact-done for generation {data['generation']} without its enact-begin")
            return
        st["incumbent"] = {"generation": data["generation"], "plan": enacting["plan"]}
        st["enacting"] = None
        if self.candidate is not None and enacting["plan"] is not None:
            self._valid(seq, enacting["plan"])

    def _valid(self, seq: int, plan_doc: Any) -> None:
        from catc.api import read_plan, validate
        from catc.semantics.plan import PlanFormatError

        assert self.candidate is not None
        try:
            plan = read_plan(self.candidate.instance, plan_doc)
        except PlanFormatError as exc:
            self.problem(seq, f"the deployed composition does not read: {exc}")
            return
        if not validate(self.candidate.instance, plan).ok:
            self.problem(seq, "the deployed composition is not valid on the model it was deployed for")

    def _enact_failed(self, seq: int, data: dict[str, Any], st: dict[str, Any]) -> None:
        if "generation" in data:
            st["enacting"] = None


def replay(store: Store, folder: Path) -> Replayed:
    return _Replay(store, folder).run()


def differences(store: Store, replayed: Replayed) -> list[str]:
    """Where the stored state differs from the replayed one."""
    stored = store.state()
    out = [f"state '{k}' differs from the journal's replay" for k in STATE_KEYS
           if json.dumps(stored.get(k), sort_keys=True) != json.dumps(replayed.state.get(k), sort_keys=True)]  # fmt: skip
    approvals = {a["id"]: a["status"] for a in store.approvals()}
    if approvals != replayed.approvals:
        out.append("the approvals differ from the journal's replay")
    return out


def verify(store: Store, folder: Path) -> tuple[list[str], list[str]]:
    """(problems, notes): SQLite's integrity, the journal's numbering, the replay, every
    generation against its manifest, ``current`` pointing at the deployed one."""
    from catrt.store import StoreError

    problems = list(store.integrity())
    try:
        store.check_sources()
    except StoreError as exc:
        problems.append(f"error[{exc.code}]: {exc}")
    if problems:  # a damaged store is not replayed: what it holds cannot be trusted
        return problems, ["the replay was not run: the store failed its integrity check"]
    replayed = replay(store, folder)
    problems += replayed.problems + differences(store, replayed)
    notes: list[str] = []
    root = folder / GENERATIONS
    if root.is_dir():
        for gen in sorted(root.iterdir()):
            if gen.name.startswith(".tmp-"):
                notes.append(f"{gen.name}: an unfinished generation a crash left (removed on the next enactment)")
            elif not complete(gen):
                names = ", ".join(differing(gen)) or "a file"
                problems.append(f"generation {gen.name}: {names} differs from its manifest")
    incumbent = store.get("incumbent")
    if incumbent is not None:
        link = folder / "current"
        target = (root / generation_name(incumbent["generation"])).resolve()
        if (not link.is_symlink() or link.resolve() != target) and store.get("enacting") is None:
            problems.append(f"'current' does not point at the deployed generation {incumbent['generation']}")
    if store.get("enacting") is not None:
        notes.append(f"generation {store.get('enacting')['generation']} was being enacted: the next run finishes it")
    return problems, notes
