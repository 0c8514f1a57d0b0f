"""The artifacts of a composition, as bytes, and the manifest that names them.

Deterministic: the same model and composition give the same bytes (golden files in the
tests), so a change on the robot shows as a change of hash.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from catc import ir
from catc.present.values import parameter_units_json
from catc.semantics.plan import plan_to_json
from catc.targets.grounding.bt import bt_xml
from catc.targets.grounding.compose import compose_env, compose_yaml
from catc.targets.grounding.instructions import instructions_md
from catc.targets.grounding.params import params_yaml
from catc.targets.grounding.resolve import Grounded

MANIFEST_SCHEMA = "catc.ground/1"
ARTIFACTS = ("instructions.md", "compose.yaml", ".env", "params.yaml", "bt.xml")


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def artifacts(grounded: Grounded) -> dict[str, bytes]:
    """Every artifact file's name and bytes (UTF-8)."""
    texts = {
        "instructions.md": instructions_md(grounded),
        "compose.yaml": compose_yaml(grounded),
        ".env": compose_env(grounded),
        "params.yaml": params_yaml(grounded),
        "bt.xml": bt_xml(grounded),
    }
    return {name: text.encode("utf-8") for name, text in texts.items()}


def manifest(grounded: Grounded, files: dict[str, bytes], model_sha256: str, inst: ir.Instance | None = None) -> dict:
    """What was grounded: the composition, each artifact's hash, the services and hardware;
    with the model (``inst``), each component's kind and its parameters' units, so the
    composition can be shown without the model (``catrt status --plan``)."""
    used = sorted(grounded.plan.components)
    described = {} if inst is None else {
        "kinds": {m: inst.morphisms[m].kind.value for m in used if m in inst.morphisms},
        "units": {m: u for m, u in parameter_units_json(inst).items() if m in grounded.plan.components},
    }  # fmt: skip
    return {
        "schema": MANIFEST_SCHEMA,
        "project": grounded.project,
        "model": {"sha256": model_sha256},
        "plan": plan_to_json(grounded.plan),
        "artifacts": {name: {"sha256": sha256(data), "bytes": len(data)} for name, data in files.items()},
        "services": [s.name for s in grounded.services],
        "hardware_steps": len(grounded.hardware),
        "hardware": [{"step": h.step, "morphism": h.morphism, "instruction": h.instruction} for h in grounded.hardware],
        "missing_grounding": list(grounded.missing),
        **described,
    }


def write(out: Path, files: dict[str, bytes], document: dict, *, durable: bool = False) -> list[Path]:
    """Write the artifacts, then manifest.json, into ``out`` (created).  Each file is written
    to a temporary name in ``out`` and renamed over the old one, so a reader sees the old file
    or the new one, never half of one; the manifest comes last and its hashes say whether the
    files beside it are the ones it names.  ``durable`` syncs every file, and the folder,
    before returning (the runtime's generations)."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    everything = {**files, "manifest.json": (json.dumps(document, indent=2) + "\n").encode("utf-8")}
    for name, data in everything.items():
        path = out / name
        tmp = out / f".{name}.tmp-{os.getpid()}"
        try:
            with open(tmp, "wb") as fh:
                fh.write(data)
                if durable:
                    fh.flush()
                    os.fsync(fh.fileno())
            os.replace(tmp, path)
        finally:
            if tmp.exists():
                tmp.unlink()
        written.append(path)
    if durable:
        fd = os.open(out, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
    return written
