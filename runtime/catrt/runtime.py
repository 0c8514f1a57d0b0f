"""The lifelong loop: one process that holds the model, takes events, decides, asks where it
must, and enacts — one step of paper Algorithm 1 per event, each step one transaction.

For a change event: apply it to the model and check the result (a rejected event changes
nothing and is journaled with its reason); decide (:mod:`catrt.decide`); then, in one
transaction, journal the event, the new model, the decision and — when the robot must
change — ``enact-begin`` for a new generation.  Enacting writes the generation's artifacts
and runs the enactor; a second transaction journals ``enact-done`` and makes the new
composition A₀.  A crash between the two leaves ``enact-begin`` without its ``enact-done``:
the next start reports it and enacts that generation again (idempotent).

A decision that needs a person — the least restoration of the world's initial values when no
composition exists — becomes a pending approval: approved by an ``approve`` event, at once
with ``--approve auto``, on the terminal with ``--approve ask``, or never.
"""

from __future__ import annotations

import hashlib
import os
import signal
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import Any

from catc import ir
from catc.api import text_cache, warm_start
from catc.ir.grounding import Value, ValueKind
from catc.semantics.plan import Plan, plan_to_json
from catrt.apply import Candidate, Rejection, apply_change, check, check_values
from catrt.config import Config
from catrt.decide import Action, Decision, Limits, RelaxPolicy, decide, kept
from catrt.enact import (
    ENACTORS,
    EnactError,
    Enactor,
    complete,
    diff_generations,
    generation_name,
    point_current,
    write_generation,
)
from catrt.events import Event, EventError, parse_event
from catrt.model import PROBLEM_FILE, ModelState, problem_file, stored_value
from catrt.store import Store, Verdict, dumps

MODEL_FOLDER = "model"
#: Seconds between two writes of the model files while a loop defers them (a burst of values).
MODEL_EVERY = 1.0
#: Groundings of kept compositions remembered at most (by the values they read).
GROUNDINGS_KEPT = 256
GENERATIONS = "generations"


class Approve(StrEnum):
    """Who approves a proposal (``--approve``)."""

    AUTO = "auto"  # the runtime itself, at once
    NEVER = "never"  # nobody here: requests wait for an approve event
    ASK = "ask"  # the person at the terminal


#: Called with the name of each point where a crash must lose nothing (``after-journal``,
#: ``mid-artifacts``, ``before-enact-done``): the crash tests kill the process there.
CrashHook = Callable[[str], None]


def no_crash(point: str) -> None:
    """The crash hook of a runtime nobody tests: nothing happens."""


class Crash:
    """Fault injection for the crash tests: ``Crash("POINT[:N]")`` kills the process
    (SIGKILL, no clean-up) the N-th time (default 1st) it reaches POINT.  The command line
    makes one of ``CATRT_CRASH_AT``; the runtime's core reads no environment."""

    def __init__(self, spec: str) -> None:
        point, _, n = spec.partition(":")
        self.point, self.n, self.hits = point, int(n or 1), 0

    def __call__(self, point: str) -> None:
        if point == self.point:
            self.hits += 1
            if self.hits == self.n:
                os.kill(os.getpid(), signal.SIGKILL)


class Status(StrEnum):
    """What became of an event."""

    ACCEPTED = "accepted"
    REJECTED = "rejected"
    DUPLICATE = "duplicate"


@dataclass
class Outcome:
    """What became of one event (for the person watching, and the API)."""

    status: Status
    event_id: str
    where: str
    message: str = ""
    decision: Decision | None = None
    generation: int | None = None
    seq: int | None = None
    timings: dict[str, float] = field(default_factory=dict)
    #: A failed enactment of the decision (E1011), reported after it.
    enactment: Outcome | None = None


def grounding_reads(inst: ir.Instance, plan: Plan) -> tuple[str, ...]:
    """The resources whose values the grounding of ``plan``'s components reads (a template's
    resource value, in the state before its step), sorted."""
    found: set[str] = set()

    def walk(node: Any) -> None:
        if isinstance(node, Value):
            if node.kind is ValueKind.RESOURCE and node.name:
                found.add(node.name)
        elif hasattr(type(node), "_fields") and not isinstance(node, tuple):  # an IR record
            for name in type(node)._fields:
                walk(getattr(node, name))
        elif isinstance(node, tuple | list | frozenset):
            for item in node:
                walk(item)
        elif isinstance(node, Mapping):
            for item in node.values():
                walk(item)

    for name in sorted({a.morphism for step in plan.steps for a in step}):
        walk(inst.morphisms[name].grounding)
    return tuple(sorted(found))


#: Seconds of unchanged sensor answers summed up in one ``sensor-repeats`` entry.
REPEATS_EVERY = 60.0


@dataclass
class _Sensed:
    """A sensor's last journaled answer and how often it was read again since."""

    resource: str
    value: Any
    error: str | None
    since: float  # time.monotonic() of the last entry
    repeats: int = 0
    init: Any = None  # the resource's value once the answer was handled


def model_sha(state: ModelState) -> str:
    return hashlib.sha256(dumps(state.to_json()).encode()).hexdigest()


class Runtime:
    def __init__(
        self,
        folder: Path,
        store: Store,
        config: Config,
        *,
        enactor: str | None = None,
        approve: str = Approve.NEVER,
        say: Callable[[Outcome], None] | None = None,
        ask: Callable[[dict[str, Any]], bool] | None = None,
        crash: CrashHook = no_crash,
    ) -> None:
        self.folder, self.store, self.config = folder, store, config
        # solve's encoding, from one decision to the next; sensed values start behind literals
        self.warm = warm_start(s.resource for s in config.sensors)
        limits = {**{"compose": 120.0, "diagnose": 30.0, "relax": 30.0}, **config.limits}
        self.policy = RelaxPolicy(dict(config.relax_weights), config.relax_fixed)
        self.limits = Limits(limits["compose"], limits["diagnose"], limits["relax"], limits.get("decision"))
        kind = enactor or config.enactor.get("kind", "dry")
        self.enactor: Enactor = ENACTORS[kind](config.enactor)
        self.approve, self.say, self.ask = approve, say or (lambda outcome: None), ask
        self.crash = crash
        store.check_sources()  # E1013: never decide on a source changed outside catrt
        self.sources = store.sources()
        self.state = ModelState.from_json(store.get("model"))
        self._checks = text_cache()  # the sources parsed and checked once: a step re-checks the problem
        self.current: Candidate = check(self.state, self.sources, str(folder / MODEL_FOLDER), cache=self._checks)
        self._written: dict[str, bytes] = {}  # the model files as last written by this runtime
        self._written_at = 0.0
        self._unwritten: Candidate | None = None
        #: The loop sets it: during a burst of events that change only values, the model files
        #: are written at most every MODEL_EVERY seconds (each call of the API writes them).
        self.defer_model = False
        self._sensed: dict[str, _Sensed] = {}  # each sensor's last journaled answer
        #: groundings of kept compositions, by (plan, the values the grounding reads), and by
        #: plan the resources it reads; cleared when the model changes beyond initial values
        self._grounded: dict[Any, Any] = {}
        self.write_model(self.current)

    # ------------------------------------------------------------ the model on disk
    def write_model(self, candidate: Candidate, *, values_only: bool = False) -> None:
        """``STATE/model/``: the model as files a person can read and give to catc.  A model
        that changed only in initial values, in a loop that defers (:attr:`defer_model`), is
        written at most every :data:`MODEL_EVERY` seconds and whenever the loop waits, enacts
        or stops (:meth:`flush_model`); the store is the model, these files show it."""
        if values_only and self.defer_model and time.monotonic() - self._written_at < MODEL_EVERY:
            self._unwritten = candidate
            return
        self._unwritten = None
        self._written_at = time.monotonic()
        from catc.api import write_files

        folder = self.folder / MODEL_FOLDER
        names = {Path(p).name: t.encode("utf-8") for p, t in candidate.files.items()}
        names[PROBLEM_FILE] = problem_file(candidate.instance).encode("utf-8")  # catc's writer, catc fmt's layout
        changed = {n: data for n, data in names.items() if self._written.get(n) != data}  # the rest are on disk
        write_files(folder, changed, {"schema": "catrt.model-files/1", "model_sha256": model_sha(candidate.state)})
        self._written = names

    def flush_model(self) -> None:
        """Write the model files a deferring loop has not written yet."""
        if self._unwritten is not None:
            self.write_model(self._unwritten)

    @property
    def incumbent(self) -> dict[str, Any] | None:
        return self.store.get("incumbent")

    # ------------------------------------------------------------ start
    def resume(self) -> list[Outcome]:
        """Finish an enactment a crash (or a full disk) interrupted."""
        enacting = self.store.get("enacting")
        if enacting is None:
            return []
        with self.store.transaction():
            self.store.journal("recovery", {"generation": enacting["generation"],
                                            "note": "enact-begin without enact-done: enacting again"})  # fmt: skip
        outcome = self.enact()
        self.say(outcome)
        return [outcome]

    def start(self) -> list[Outcome]:
        """Finish an enactment a crash interrupted; decide when nothing is deployed yet."""
        out: list[Outcome] = self.resume()
        if self.incumbent is None and not self.store.approvals(Verdict.PENDING):
            outcome = self._decide_and_commit(Event("start", {}, "start", False), self.current, kind="start")
            self.say(outcome)
            out.append(outcome)
            if outcome.decision is not None and outcome.decision.action is Action.RESTORE:
                self._maybe_approve(outcome)
        return out

    # ------------------------------------------------------------ events
    def handle_line(self, line: str, where: str) -> Outcome:
        try:
            event = parse_event(line, where)
        except EventError as exc:
            # a byte that is not UTF-8 (read with surrogateescape) kept as the text \udcff: SQLite takes UTF-8 only
            text = line[:2000].encode("utf-8", "backslashreplace").decode()
            with self.store.transaction():
                seq = self.store.journal("rejected", {"where": exc.where, "code": "E1001", "message": exc.message,
                                                      "line": text})  # fmt: skip
            outcome = Outcome(Status.REJECTED, exc.event_id, exc.where, f"error[E1001]: {exc.message}", seq=seq)
            self.say(outcome)
            return outcome
        return self.handle(event)

    def handle(self, event: Event) -> Outcome:
        if self.store.accepted(event.id):
            outcome = Outcome(Status.DUPLICATE, event.id, event.where, "already accepted: nothing to do")
        elif event.is_approval:
            outcome = self._approval(event)
        else:
            outcome = self._change(event)
        self.say(outcome)
        if outcome.decision is not None and outcome.decision.action is Action.RESTORE:
            self._maybe_approve(outcome)
        return outcome

    def _reject(self, event: Event, code: str, rejection: Rejection) -> Outcome:
        with self.store.transaction():
            seq = self.store.journal("rejected", {"where": event.where, "event": event.to_json(), "code": code,
                                                  **rejection.to_json()}, event.id)  # fmt: skip
        return Outcome(Status.REJECTED, event.id, event.where, f"error[{code}]: {rejection.text()}", seq=seq)

    def _change(self, event: Event) -> Outcome:
        t = time.perf_counter()
        try:
            state, origins = apply_change(self.state, self.current.instance, self.sources, event)
            quick = check_values(self.current, state, event.body)  # only what changed: values
            candidate = quick or check(state, self.sources, str(self.folder / MODEL_FOLDER), origins, self._checks)
        except Rejection as rejection:
            return self._reject(event, "E1002" if rejection.details else "E1001", rejection)
        checked = time.perf_counter() - t
        outcome = self._decide_and_commit(event, candidate, quick=quick is not None)
        outcome.timings = {"apply": checked, **outcome.timings}
        return outcome

    def _approval(self, event: Event) -> Outcome:
        request = str(event.body.get("approve") or event.body.get("reject"))
        pending = {a["id"]: a for a in self.store.approvals(Verdict.PENDING)}
        if request not in pending:
            known = {a["id"]: a["status"] for a in self.store.approvals()}
            why = f"'{request}' is {known[request]}" if request in known else f"no request '{request}'"
            return self._reject(event, "E1010", Rejection(f"{why}; pending: {', '.join(pending) or 'none'}"))
        if "reject" in event.body:
            with self.store.transaction():
                seq = self.store.journal("event", {"where": event.where, "event": event.to_json(),
                                                   "model_sha256": model_sha(self.state)}, event.id)  # fmt: skip
                self.store.journal("approval", {"request": request, "verdict": Verdict.REJECTED, "event": seq})
                self.store.settle_approval(request, Verdict.REJECTED)
            return Outcome(Status.ACCEPTED, event.id, event.where, f"request {request} rejected", seq=seq)
        proposal = pending[request]["proposal"]
        change = Event(event.id, {"set": proposal["set"]}, event.where, event.given_id)
        try:
            state, origins = apply_change(self.state, self.current.instance, self.sources, change)
            candidate = check(state, self.sources, str(self.folder / MODEL_FOLDER), origins, self._checks)
        except Rejection as rejection:  # the model moved on since the request
            return self._reject(event, "E1002", rejection)
        return self._decide_and_commit(event, candidate, approval=request)

    # ------------------------------------------------------------ decide, commit, enact
    def _decide_and_commit(self, event: Event, candidate: Candidate, kind: str = "event",
                           approval: str | None = None, quick: bool = False) -> Outcome:  # fmt: skip
        incumbent = self.incumbent
        decision = kept(candidate.model, incumbent["plan"] if incumbent else None) if quick else None
        if decision is None:
            if quick:  # a solver query follows: on the model checked whole, so that what the
                # queries report (cores, restorations) points into the files as catc reads them
                candidate, quick = (
                    check(candidate.state, self.sources, str(self.folder / MODEL_FOLDER), cache=self._checks),
                    False,
                )
            decision = decide(candidate.model, incumbent["plan"] if incumbent else None, self.limits, self.warm,
                              self.policy)  # fmt: skip
        if not quick:  # the model changed beyond initial values: ground afresh
            self._grounded.clear()
        plan = decision.plan if decision.action.deploys else None
        artifacts, why_not = self._artifacts(candidate, plan, decision.states) if plan is not None else (None, None)
        enact = artifacts is not None and (decision.action is not Action.KEEP or not self._deployed_as(artifacts[0]))
        request: str | None = None
        with self.store.transaction():
            cause = self._journal_cause(event, candidate, kind, approval)
            if approval is not None:
                self.store.settle_approval(approval, Verdict.APPROVED)
            self.store.put("model", candidate.state.to_json())
            seq = self.store.journal("decision", {"cause": cause, **decision.to_json()})
            generation = None
            superseded = [a["id"] for a in self.store.approvals(Verdict.PENDING)] if approval is None else []
            for old in superseded:  # the world moved on: a new decision replaces the request
                self.store.settle_approval(old, Verdict.SUPERSEDED)
                self.store.journal("approval", {"request": old, "verdict": Verdict.SUPERSEDED, "decision": seq})
            if decision.action is Action.RESTORE:
                request = f"r{len(self.store.approvals()) + 1}"  # r1, r2, ...: an events file can name them
                self.store.add_approval(request, seq, decision.proposal or {})
                self.store.journal(
                    "approval-request", {"request": request, "decision": seq, **(decision.proposal or {})}
                )
            if why_not is not None:
                self.store.journal("enact-failed", {"decision": seq, "code": "E1011", "message": why_not})
            elif enact:
                generation = int(self.store.get("generation", 0)) + 1
                self.store.put("generation", generation)
                self.store.put("enacting", {"generation": generation, "decision": seq,
                                            "plan": decision.to_json()["plan"]})  # fmt: skip
                self.store.journal("enact-begin", {"generation": generation, "decision": seq})
        self.crash("after-journal")
        self.state, self.current = candidate.state, candidate
        self.write_model(candidate, values_only=quick and generation is None)
        message = decision.reason + (
            f"; request {request} waits for approval: catrt approve {self.folder} {request}" if request else ""
        )
        outcome = Outcome(Status.ACCEPTED, event.id, event.where, message, decision, generation, cause,
                          dict(decision.timings))  # fmt: skip
        if generation is not None:
            done = self.enact(artifacts)
            if done.status is Status.REJECTED:  # the decision stands; enacting it failed (E1011)
                outcome.message += f"; generation {generation} not enacted (below)"
                outcome.enactment = done
            else:
                outcome.message += f"; {done.message}"
            outcome.generation = done.generation
        return outcome

    def _journal_cause(self, event: Event, candidate: Candidate, kind: str, approval: str | None) -> int:
        data = {"where": event.where, "event": event.to_json(), "model_sha256": model_sha(candidate.state)}
        if kind == "start":
            return self.store.journal("start", {"model_sha256": data["model_sha256"]})
        seq = self.store.journal("event", data, event.id)
        if approval is not None:
            self.store.journal("approval", {"request": approval, "verdict": Verdict.APPROVED, "event": seq})
        return seq

    def _artifacts(self, candidate: Candidate, plan: Any, states: Any = None) -> tuple[Any, str | None]:
        """(files, manifest) of ``plan`` grounded in the candidate model, or (None, why not).
        With the validator's ``states`` (a kept composition), the grounding is reused while
        nothing it reads changed: the same plan, the same values of the resources its
        templates name, in a model that changed only in initial values since it was made."""
        from catc.api import deployment

        digest = hashlib.sha256("\n".join(sorted(hashlib.sha256(t.encode()).hexdigest()
                                                 for t in candidate.files.values())).encode()).hexdigest()  # fmt: skip
        key = None
        if states is not None:
            text = dumps(plan_to_json(plan))
            reads = self._grounded.get(text)
            if reads is None:
                reads = self._grounded[text] = grounding_reads(candidate.instance, plan)
            key = (text, tuple(stored_value(s.get(r)) for s in states for r in reads))
            if key in self._grounded:
                files, manifest = self._grounded[key]
                return (files, {**manifest, "model": {**manifest["model"], "sha256": digest}}), None
        try:
            made = deployment(candidate.instance, plan, digest)
        except ValueError as exc:  # GroundingConflict, a real no artifact can carry
            return None, f"the composition cannot be grounded: {exc}"
        if key is not None:
            if len(self._grounded) > GROUNDINGS_KEPT:  # values that keep changing: start again
                self._grounded.clear()
            self._grounded[key] = made
        return made, None

    def _deployed_as(self, files: dict[str, bytes]) -> bool:
        """The deployed generation has exactly these artifacts."""
        incumbent = self.incumbent
        if incumbent is None:
            return False
        folder = self.folder / GENERATIONS / generation_name(incumbent["generation"])
        return complete(folder) and all((folder / n).read_bytes() == data for n, data in files.items())

    def enact(self, artifacts: Any = None) -> Outcome:
        """Enact the generation in ``enacting`` (after a crash: again)."""
        enacting = self.store.get("enacting")
        generation = enacting["generation"]
        if artifacts is None:  # recovering: the same model and plan ground to the same bytes
            from catc.api import read_plan

            plan = read_plan(self.current.instance, enacting["plan"])
            artifacts, why_not = self._artifacts(self.current, plan)
            if artifacts is None:
                return self._enact_failed(generation, why_not or "")
        files, manifest = artifacts
        root = self.folder / GENERATIONS
        folder = write_generation(root, generation, files, manifest, {"decision": enacting["decision"]}, self.crash)
        incumbent = self.incumbent
        old = root / generation_name(incumbent["generation"]) if incumbent else None
        diff = diff_generations(old, folder)
        try:
            done = self.enactor.enact(manifest["project"], folder, diff)
        except EnactError as exc:
            return self._enact_failed(generation, str(exc))
        self.crash("before-enact-done")
        point_current(self.folder, folder)
        with self.store.transaction():
            seq = self.store.journal("enact-done", {"generation": generation, "enactor": self.enactor.name,
                                                    **done.to_json()})  # fmt: skip
            self.store.put("incumbent", {"generation": generation, "plan": enacting["plan"]})
            self.store.put("enacting", None)
        what = "enacted" if done.ran else f"written ({self.enactor.name}: nothing run)"
        return Outcome(Status.ACCEPTED, "", "enact", f"generation {generation} {what}", generation=generation, seq=seq)

    def _enact_failed(self, generation: int, why: str) -> Outcome:
        with self.store.transaction():
            seq = self.store.journal("enact-failed", {"generation": generation, "code": "E1011", "message": why})
            self.store.put("enacting", None)
        return Outcome(Status.REJECTED, "", "enact", f"error[E1011]: generation {generation}: {why}", seq=seq)

    # ------------------------------------------------------------ approvals
    def _maybe_approve(self, outcome: Outcome) -> None:
        pending = self.store.approvals(Verdict.PENDING)
        if not pending:
            return
        request = pending[-1]
        if self.approve == Approve.AUTO or (self.approve == Approve.ASK and self.ask is not None and self.ask(request)):
            by = "auto" if self.approve == Approve.AUTO else "terminal"
            self.handle(Event(f"{by}-approve-{request['id']}", {"approve": request["id"]}, by, False))

    # ------------------------------------------------------------ sensors
    def read_sensors(self, due: Iterable[Any]) -> list[Outcome]:
        from catrt.sensors import run_sensor

        out = []
        for sensor in due:
            reading = run_sensor(sensor, self.current.instance.resources.get(sensor.resource), self.folder)
            last = self._sensed.get(sensor.name)
            init = self.state.problem.init.get(sensor.resource)
            if last is not None and (last.value, last.error, last.init) == (reading.value, reading.error, init):
                # the same answer again, and nothing else changed the resource since
                last.repeats += 1  # counted, journaled in sum (below)
                if time.monotonic() - last.since >= REPEATS_EVERY:
                    self._journal_repeats(sensor.name)
                continue
            repeats = last.repeats if last is not None else 0
            sensed = self._sensed[sensor.name] = _Sensed(
                sensor.resource, reading.value, reading.error, time.monotonic()
            )
            with self.store.transaction():
                seq = self.store.journal("sensor", {**reading.to_json(), "argv": list(sensor.argv),
                                                    **({"code": "E1009"} if reading.error else {}),
                                                    "repeats_before": repeats})  # fmt: skip
            if reading.error is not None:
                outcome = Outcome(
                    Status.REJECTED, "", f"sensor {sensor.name}", f"error[E1009]: {reading.error}", seq=seq
                )
                self.say(outcome)
                out.append(outcome)
            elif self.state.problem.init.get(sensor.resource) != reading.value:
                event = Event(f"sensor-{sensor.name}-{seq}", {"set": {sensor.resource: reading.value}},
                              f"sensor {sensor.name}", False)  # fmt: skip
                out.append(self.handle(event))
            sensed.init = self.state.problem.init.get(sensor.resource)  # after its event, if any
        return out

    def _journal_repeats(self, name: str) -> None:
        """A ``sensor-repeats`` entry: how often the sensor read its last journaled answer
        again since its last entry (the count starts anew)."""
        last = self._sensed[name]
        if last.repeats:
            with self.store.transaction():
                self.store.journal("sensor-repeats", {"sensor": name, "resource": last.resource, "value": last.value,
                                                      "error": last.error, "repeats": last.repeats})  # fmt: skip
        last.repeats, last.since = 0, time.monotonic()

    def say_disk_full(self, where: str, message: str, wait: float) -> None:
        """Tell the person watching that the disk is full and when the loop tries again."""
        self.say(Outcome(Status.REJECTED, "", where, f"error[E1016]: {message}; trying again in {wait:g} s"))

    def close(self) -> None:
        try:
            self.flush_model()
            for name in self._sensed:
                self._journal_repeats(name)
        finally:
            self.store.close()
