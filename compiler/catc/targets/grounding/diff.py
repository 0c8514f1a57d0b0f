"""What changes on the robot between two compositions of one model.

Components (morphisms used at least once) are added or removed — exactly the churn of a
recomposition; on the robot that means hardware to unmount and mount, services to stop,
start or recreate, and whether the behaviour tree changed.  A service whose image, node,
parameters or remappings changed must be *recreated*: Compose does not restart a container
when only a mounted file changed.  The Compose commands that enact the change are part of
the answer.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from catc.ir.grounding import Profile
from catc.targets.grounding.artifacts import MANIFEST_SCHEMA
from catc.targets.grounding.bt import bt_xml
from catc.targets.grounding.compose import profiles
from catc.targets.grounding.resolve import Grounded, Service
from catgrammar.record import Record, set_field


class GroundDiff(Record):
    __slots__ = (
        "project",
        "added",
        "removed",
        "unmount",
        "mount",
        "stop",
        "start",
        "recreate",
        "tree_changed",
        "profiles",
    )
    project: str
    added: tuple[str, ...]  # components (morphisms) in the new composition only
    removed: tuple[str, ...]  # in the old one only
    unmount: tuple[str, ...]  # hardware steps to undo (their morphisms)
    mount: tuple[str, ...]
    stop: tuple[str, ...]  # services
    start: tuple[str, ...]
    recreate: tuple[str, ...]
    tree_changed: bool
    profiles: tuple[str, ...]  # the Compose profiles the new composition's services are in

    def __init__(self, project: str, added: tuple[str, ...], removed: tuple[str, ...], unmount: tuple[str, ...],
                 mount: tuple[str, ...], stop: tuple[str, ...], start: tuple[str, ...], recreate: tuple[str, ...],
                 tree_changed: bool, profiles: tuple[str, ...] = ()) -> None:  # fmt: skip
        for name, value in zip(self.__slots__, (project, added, removed, unmount, mount, stop, start, recreate,
                                                tree_changed, profiles)):  # fmt: skip
            set_field(self, name, value)

    @property
    def empty(self) -> bool:
        return not (self.added or self.removed or self.mount or self.unmount or self.stop or self.start
                    or self.recreate or self.tree_changed)  # fmt: skip

    def commands(self) -> list[list[str]]:
        """The Compose command lines that enact the change (in order), run in the new
        composition's folder; every profile in use is activated (the folder's ``.env`` does
        the same for a plain ``docker compose up``)."""
        base = ["docker", "compose", "-p", self.project, "-f", "compose.yaml"]
        base += [a for p in self.profiles for a in ("--profile", p)]
        out = []
        if self.start or self.stop or self.recreate or self.tree_changed:
            out.append([*base, "up", "-d", "--remove-orphans"])
        if self.recreate:
            out.append([*base, "up", "-d", "--no-deps", "--force-recreate", *self.recreate])
        return out


def _same(a: Service, b: Service) -> bool:
    return (a.image, a.node, a.profile, a.params, a.remap) == (b.image, b.node, b.profile, b.params, b.remap)


def ground_diff(old: Grounded, new: Grounded) -> GroundDiff:
    old_components, new_components = old.plan.components, new.plan.components
    old_hw = {h.morphism: h for h in old.hardware}
    new_hw = {h.morphism: h for h in new.hardware}
    remount = {m for m in old_hw.keys() & new_hw.keys() if old_hw[m].instruction != new_hw[m].instruction}
    old_sv = {s.name: s for s in old.services}
    new_sv = {s.name: s for s in new.services}
    tree_changed = bt_xml(old) != bt_xml(new)
    recreate = {n for n in old_sv.keys() & new_sv.keys() if not _same(old_sv[n], new_sv[n])}
    if tree_changed and "bt-executor" in old_sv.keys() & new_sv.keys():
        recreate.add("bt-executor")  # the tree is a mounted file: the executor reads it at start
    return GroundDiff(
        new.project,
        tuple(sorted(new_components - old_components)),
        tuple(sorted(old_components - new_components)),
        tuple(sorted((old_hw.keys() - new_hw.keys()) | remount)),
        tuple(sorted((new_hw.keys() - old_hw.keys()) | remount)),
        tuple(sorted(old_sv.keys() - new_sv.keys())),
        tuple(sorted(new_sv.keys() - old_sv.keys())),
        tuple(sorted(recreate)),
        tree_changed,
        tuple(profiles(new)),
    )


def diff_artifacts(old: Mapping[str, bytes], new: Mapping[str, bytes]) -> GroundDiff:
    """The same answer as :func:`ground_diff`, from two sets of written artifacts (file name
    → bytes, ``manifest.json`` among them) — what a runtime has on disk for the generation
    that is deployed and the one to deploy, with no model needed."""
    import yaml

    def read(files: Mapping[str, bytes]) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
        manifest = json.loads(files["manifest.json"])
        services = (yaml.safe_load(files["compose.yaml"]) or {}).get("services") or {}
        params = (yaml.safe_load(files["params.yaml"]) or {}).get("/**") or {}
        return manifest, services, params

    (m_old, s_old, p_old), (m_new, s_new, p_new) = read(old), read(new)
    components = [{a["morphism"] for step in m["plan"]["steps"] for a in step} for m in (m_old, m_new)]
    hw_old = {h["morphism"]: h["instruction"] for h in m_old.get("hardware", [])}
    hw_new = {h["morphism"]: h["instruction"] for h in m_new.get("hardware", [])}
    remount = {m for m in hw_old.keys() & hw_new.keys() if hw_old[m] != hw_new[m]}
    tree_changed = old["bt.xml"] != new["bt.xml"]

    def node(service: Mapping[str, Any]) -> str | None:
        return next((a.split(":=", 1)[1] for a in service.get("command", []) if a.startswith("__node:=")), None)

    def same(name: str) -> bool:
        a, b = s_old[name], s_new[name]
        return a == b and p_old.get(node(a) or "") == p_new.get(node(b) or "")

    recreate = {n for n in s_old.keys() & s_new.keys() if not same(n)}
    if tree_changed and "bt-executor" in s_old.keys() & s_new.keys():
        recreate.add("bt-executor")
    return GroundDiff(
        m_new["project"],
        tuple(sorted(components[1] - components[0])),
        tuple(sorted(components[0] - components[1])),
        tuple(sorted((hw_old.keys() - hw_new.keys()) | remount)),
        tuple(sorted((hw_new.keys() - hw_old.keys()) | remount)),
        tuple(sorted(s_old.keys() - s_new.keys())),
        tuple(sorted(s_new.keys() - s_old.keys())),
        tuple(sorted(recreate)),
        tree_changed,
        tuple(sorted({p for s in s_new.values() for p in (s.get("profiles") or [])}, key=_profile_order)),
    )


def _profile_order(name: str) -> tuple[int, str]:
    order = [p.value for p in Profile]
    return (order.index(name) if name in order else len(order), name)


class NotAGrounding(ValueError):
    """A path that is neither a grounding's folder nor its manifest.json, or whose files do
    not match their manifest."""


def is_grounding(path: str) -> bool:
    """``path`` is a folder with a manifest.json, or a manifest.json (not a plan file)."""
    p = Path(path)
    if p.is_dir():
        return (p / "manifest.json").is_file()
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(doc, dict) and doc.get("schema") == MANIFEST_SCHEMA


def read_grounding(path: str) -> dict[str, bytes]:
    """The artifacts (and manifest.json) of a grounding given by its folder or its manifest,
    each checked against the manifest's sha256."""
    p = Path(path)
    folder = p if p.is_dir() else p.parent
    try:
        manifest_bytes = (folder / "manifest.json").read_bytes() if p.is_dir() else p.read_bytes()
        manifest = json.loads(manifest_bytes)
        if not isinstance(manifest, dict) or manifest.get("schema") != MANIFEST_SCHEMA:
            raise NotAGrounding(f"{path}: not a catc grounding (no {MANIFEST_SCHEMA} manifest)")
        files = {"manifest.json": manifest_bytes}
        for name, entry in manifest["artifacts"].items():
            data = (folder / name).read_bytes()
            if hashlib.sha256(data).hexdigest() != entry["sha256"]:
                raise NotAGrounding(f"{folder / name}: changed since it was written (its sha256 is not the manifest's)")
            files[name] = data
    except OSError as exc:
        raise NotAGrounding(f"{path}: {exc.strerror or exc}") from None
    except (ValueError, KeyError, TypeError) as exc:
        if isinstance(exc, NotAGrounding):
            raise
        raise NotAGrounding(f"{path}: not a catc grounding manifest ({exc})") from None
    for needed in ("compose.yaml", "params.yaml", "bt.xml"):
        files.setdefault(needed, b"")
    return files
