"""What ``catrt status`` and ``catrt journal`` show: documents built from the store, and
their text for people."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from catrt.store import Store, Verdict

STATUS_SCHEMA = "catrt.status/1"

#: The kinds of journal entry, in the order a run writes them (``catrt journal --kind``).
ENTRY_KINDS = ("init", "migrated", "start", "event", "rejected", "decision", "approval-request", "approval",
               "enact-begin", "enact-done", "enact-failed", "recovery", "sensor",
               "sensor-repeats")  # fmt: skip


def _components(plan: dict[str, Any] | None) -> list[str]:
    if not plan:
        return []
    return sorted({a["morphism"] for step in plan["steps"] for a in step})


def generation_folder(folder: Path, generation: int) -> Path:
    return folder / "generations" / f"{generation:06d}"


def deployed_composition(generation: Path) -> dict[str, Any] | None:
    """The composition a generation grounded, from its manifest: steps of
    ``{"morphism", "kind", "params": {name: {"value", "unit"}}}``."""
    try:
        manifest = json.loads((generation / "manifest.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    kinds, units = manifest.get("kinds", {}), manifest.get("units", {})
    steps = [
        [
            {
                "morphism": a["morphism"],
                "kind": kinds.get(a["morphism"]),
                "params": {
                    k: {"value": v, **({"unit": units[a["morphism"]][k]} if k in units.get(a["morphism"], {}) else {})}
                    for k, v in a["params"].items()
                },
            }
            for a in step
        ]
        for step in manifest["plan"]["steps"]
    ]
    return {"steps": steps, "fresh": manifest["plan"].get("fresh", {}), "services": manifest.get("services", [])}


def _value_text(value: Any, unit: str | None) -> str:
    from fractions import Fraction

    from catc.ir.numbers import decimal_text

    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list):
        return "{" + " ".join(str(v) for v in value) + "}"
    if isinstance(value, int):  # a whole number the manifest keeps as an int: still in its unit
        return str(value) + (f" {unit}" if unit else "")
    if isinstance(value, str):
        try:
            number = Fraction(value)
        except ValueError:
            return value
        return decimal_text(number) + (f" {unit}" if unit else "")
    return str(value)


def plan_text(composition: dict[str, Any]) -> list[str]:
    """The deployed composition as a table: step, morphism, kind, θ with units."""
    rows = [(str(i), a["morphism"], a["kind"] or "", ", ".join(
        f"{k} = {_value_text(p['value'], p.get('unit'))}" for k, p in a["params"].items()))
        for i, step in enumerate(composition["steps"], 1) for a in step]  # fmt: skip
    width = max([len("morphism"), *(len(r[1]) for r in rows)])
    lines = [f"  step  {'morphism':<{width}}  kind      θ"]
    last = ""
    for step, morphism, kind, theta in rows:
        shown = step if step != last else "⊗"
        last = step
        lines.append(f"  {shown:>4}  {morphism:<{width}}  {kind:<8}  {theta}".rstrip())
    if composition.get("services"):
        lines.append(f"  services: {', '.join(composition['services'])}")
    return lines


def status_document(store: Store, folder: Path) -> dict[str, Any]:
    model = store.get("model")
    incumbent = store.get("incumbent")
    last = next(iter(reversed(list(store.entries(kinds=("decision",))))), None)
    enacted = next(iter(reversed(list(store.entries(kinds=("enact-done",))))), None)
    p, c = model["problem"], model["catalog"]
    return {
        "schema": STATUS_SCHEMA,
        "state": str(folder),
        "meta": store.meta(),
        "model": {
            "problem": p["name"],
            "domain": p["domain"],
            "goal": p["goal"],
            "metric": p["metric"],
            "horizon": p["horizon"],
            "init": p["init"],
            "catalog": {"added": [a["morphism"] for a in c["added"]], "removed": c["removed"], "failed": c["failed"]},
        },
        "deployed": None
        if incumbent is None
        else {
            "generation": incumbent["generation"],
            "steps": len(incumbent["plan"]["steps"]),
            "components": _components(incumbent["plan"]),
            "folder": str(generation_folder(folder, incumbent["generation"])),
            "composition": deployed_composition(generation_folder(folder, incumbent["generation"])),
        },
        "last_enactment": None
        if enacted is None
        else {k: enacted["data"].get(k) for k in ("generation", "enactor", "ran", "hardware", "diff", "commands")},
        "enacting": store.get("enacting"),
        "pending": [{"id": a["id"], **a["proposal"]} for a in store.approvals(Verdict.PENDING)],
        "last_decision": None
        if last is None
        else {
            "seq": last["seq"],
            "at": last["at"],
            "action": last["data"]["action"],
            "reason": last["data"]["reason"],
            "timings": last["data"]["timings"],
            "solver_calls": last["data"]["solver_calls"],
        },
        "sensors": sensor_counts(store),
        "journal_entries": store.last_seq(),
    }


def sensor_counts(store: Store) -> dict[str, dict[str, Any]]:
    """Each sensor's last journaled answer and its readings: ``readings`` in all, and
    ``repeats``, those of the last answer after its entry (unchanged answers are journaled
    as a count, not one by one)."""
    out: dict[str, dict[str, Any]] = {}
    for e in store.entries(kinds=("sensor", "sensor-repeats")):
        d = e["data"]
        now = out.setdefault(d["sensor"], {"readings": 0, "repeats": 0})
        if e["kind"] == "sensor":
            now.update(resource=d["resource"], value=d["value"], error=d["error"], seq=e["seq"], at=e["at"],
                       repeats=0, readings=now["readings"] + 1 + d.get("repeats_before", 0))  # fmt: skip
        else:
            now["repeats"] += d["repeats"]
            now["readings"] += d["repeats"]
    return out


def status_text(doc: dict[str, Any], plan: bool = False) -> str:
    m = doc["model"]
    lines = [f"{doc['state']}: problem {m['problem']} of domain {m['domain']}; goal {m['goal']}"]
    if m["metric"]:
        lines.append(f"  metric: {m['metric']}")
    cat = m["catalog"]
    for key in ("added", "removed", "failed"):
        if cat[key]:
            lines.append(f"  catalogue {key}: {', '.join(cat[key])}")
    d = doc["deployed"]
    if d is None:
        lines.append("deployed: nothing yet")
    else:
        lines.append(f"deployed: generation {d['generation']}, {d['steps']} steps, {len(d['components'])} components"
                     f" ({d['folder']})")  # fmt: skip
        if plan and d.get("composition"):
            lines += plan_text(d["composition"])
        elif plan:
            lines.append("  (the generation's manifest cannot be read: catrt verify says why)")
    lines += _enactment_lines(doc["last_enactment"])
    if doc["enacting"]:
        lines.append(f"enacting: generation {doc['enacting']['generation']} (interrupted: the next run finishes it)")
    for req in doc["pending"]:
        said = ", ".join(f"{k} → {v}" for k, v in req.get("set", {}).items())
        lines.append(f"pending request {req['id']}: restore {said}  (catrt approve {doc['state']} {req['id']})")
    last = doc["last_decision"]
    if last is not None:
        took = sum(last["timings"].values())
        lines.append(f"last decision ({last['at']}): {last['action']} — {last['reason']} [{took:.2f} s, "
                     f"{last['solver_calls']} solver call(s)]")  # fmt: skip
    for name, sensed in doc.get("sensors", {}).items():
        what = sensed.get("error") or f"{sensed.get('resource')} = {sensed.get('value')}"
        lines.append(f"sensor {name}: {what}, {sensed['readings']} readings ({sensed['repeats']} unchanged since its "
                     f"entry {sensed.get('seq')})")  # fmt: skip
    lines.append(f"journal: {doc['journal_entries']} entries")
    return "\n".join(lines)


def _enactment_lines(done: dict[str, Any] | None) -> list[str]:
    """What the last enactment changed: hardware for a person, services for the enactor."""
    if done is None or not done.get("diff"):
        return []
    diff, lines = done["diff"], []
    for key, verb in (("unmount", "unmount"), ("mount", "mount"), ("stop", "stop"), ("start", "start"),
                      ("recreate", "recreate")):  # fmt: skip
        if diff.get(key):
            lines.append(f"  {verb}: {', '.join(diff[key])}")
    if diff.get("tree_changed"):
        lines.append("  behaviour tree: changed")
    head = (
        f"last enactment: generation {done['generation']} ({done['enactor']}{'' if done['ran'] else ', nothing run'})"
    )
    return [head, *lines] if lines else [head + ": no change"]


def entry_text(entry: dict[str, Any]) -> str:
    data, kind = entry["data"], entry["kind"]
    head = f"{entry['seq']:>6}  {entry['at']}  {kind:<17}"
    if kind == "event":
        body = {k: v for k, v in data["event"].items() if k not in ("v",)}
        return f"{head}{data['where']}: {json.dumps(body, ensure_ascii=False)[:160]}"
    if kind == "rejected":
        return f"{head}{data['where']}: error[{data['code']}]: {data['message']}"
    if kind == "decision":
        took = sum(data["timings"].values())
        return f"{head}{data['action']}: {data['reason']} [{took:.2f} s]"
    if kind in ("enact-begin", "enact-done", "enact-failed", "recovery"):
        extra = data.get("message") or data.get("note") or ""
        return f"{head}generation {data.get('generation', '?')} {extra}".rstrip()
    if kind in ("approval-request", "approval"):
        return f"{head}{data['request']}: {data.get('verdict') or json.dumps(data.get('set'))}"
    if kind == "sensor":
        what = data["error"] or f"{data['resource']} = {data['value']}"
        before = data.get("repeats_before")
        return f"{head}{data['sensor']}: {what}" + (f" (the answer before read {before} more times)" if before else "")
    if kind == "sensor-repeats":
        what = data["error"] or f"{data['resource']} = {data['value']}"
        return f"{head}{data['sensor']}: {what} read {data['repeats']} more times (not journaled one by one)"
    return f"{head}{json.dumps(data, ensure_ascii=False)[:160]}"


def diff_text(d: Any, old: int, new: int) -> str:
    """What changes on the robot from generation ``old`` to ``new``."""
    if d.empty:
        return f"generations {old} → {new}: no change"
    lines = [f"generations {old} → {new}: components added: {', '.join(d.added) or 'none'}; "
             f"removed: {', '.join(d.removed) or 'none'}"]  # fmt: skip
    for what in ("unmount", "mount", "stop", "start", "recreate"):
        if getattr(d, what):
            lines.append(f"  {what:9} {', '.join(getattr(d, what))}")
    lines.append(f"  behaviour tree {'changed' if d.tree_changed else 'unchanged'}")
    return "\n".join(lines)
