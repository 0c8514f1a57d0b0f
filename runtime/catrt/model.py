"""The runtime's model: the sources it was started with and every change events made to them,
as data (:class:`ModelState`), and the ``.cat`` texts that data stands for.

The model is kept as data, not as edited files, so that an event changes exactly what it
names and the journal can be replayed: the initial values of the resources (typed, exact),
the goal, metric, soft constraints and horizon as ``.cat`` text, and the catalogue — the
morphisms the events added (as ``.cat`` text), removed, or reported failed.  :func:`texts`
writes the model out as the files catc checks: the sources with removed and failed
morphisms cut out and added ones appended to the domain, and a problem file generated from
the problem's data.  Every piece of generated text remembers where it came from (a
:class:`Region`), so that an error the checker finds in it is reported against the event
field that put it there.  Once checked, the problem file written to disk is catc's own
(:func:`problem_file`: catc's ``.cat`` writer, ``catc fmt``'s layout).  The sources are cut
and spliced by the offsets catc gives (:func:`catc.api.outline`); nothing here parses.
"""

from __future__ import annotations

import functools
import hashlib
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction
from pathlib import PurePosixPath
from typing import Any

from catc import ir
from catc.api import CatError, Definition, Section, initial_state, outline, problem_source
from catc.ir.numbers import number_text, ratio_text

SCHEMA = "catrt.model/1"
PROBLEM_FILE = "problem.cat"

#: A value as the store keeps it: a number as exact text ("0.5", "1/3"), a Boolean, a
#: symbol, or a sorted list of symbols (a set).
StoredValue = str | bool | list[str]


# ---------------------------------------------------------------- values


def stored_value(v: object) -> StoredValue:
    """A value of the validator's state (Fraction, bool, str, frozenset) as stored."""
    if isinstance(v, bool):
        return v
    if isinstance(v, Fraction):
        return ratio_text(v)
    if isinstance(v, frozenset):
        return sorted(str(x) for x in v)
    return str(v)


def cat_value(v: StoredValue) -> str:
    """A stored value as ``.cat`` text: a list is a set literal, text that reads as a number
    a number (``(/ 1 3)`` for a fraction), anything else a symbol."""
    if isinstance(v, list):
        return "{" + " ".join(v) + "}"
    if isinstance(v, bool):
        return "true" if v else "false"
    if _NUMBER.fullmatch(v):
        return number_text(Fraction(v))
    return v


_NUMBER = re.compile(r"-?\d+(\.\d+)?(/\d+)?")


# ---------------------------------------------------------------- the state


@dataclass(frozen=True)
class ProblemState:
    """The problem as data: its name and domain, sections kept as their ``.cat`` text, and
    the initial value of every resource."""

    name: str
    domain: str
    requirements: tuple[str, ...] = ()  # (:requirements ...) sections, as written
    objects: str | None = None  # the (:objects ...) section, as written
    init: Mapping[str, StoredValue] = field(default_factory=dict)
    goal: str = "true"  # the goal condition
    horizon: int | None = None
    softs: tuple[str, ...] = ()  # each soft constraint: "CONDITION :weight W"
    metric: str | None = None  # what follows :metric, e.g. "maximize budget"
    view: str | None = None


@dataclass(frozen=True)
class ModelState:
    """Everything the runtime knows of the model (see the module's description)."""

    domain_file: str  # the source (by name) that defines the problem's domain
    problem: ProblemState
    added: tuple[tuple[str, str], ...] = ()  # (morphism, its (:morphism ...) text), in order
    removed: tuple[str, ...] = ()  # morphisms of the sources taken out of the catalogue
    failed: tuple[str, ...] = ()  # morphisms out of service until they recover

    def to_json(self) -> dict[str, Any]:
        p = self.problem
        return {
            "schema": SCHEMA,
            "domain_file": self.domain_file,
            "problem": {
                "name": p.name,
                "domain": p.domain,
                "requirements": list(p.requirements),
                "objects": p.objects,
                "init": {k: p.init[k] for k in sorted(p.init)},
                "goal": p.goal,
                "horizon": p.horizon,
                "softs": list(p.softs),
                "metric": p.metric,
                "view": p.view,
            },
            "catalog": {
                "added": [{"morphism": m, "text": t} for m, t in self.added],
                "removed": sorted(self.removed),
                "failed": sorted(self.failed),
            },
        }

    @staticmethod
    def from_json(doc: Mapping[str, Any]) -> ModelState:
        if doc.get("schema") != SCHEMA:
            raise ValueError(f"not a {SCHEMA} document")
        p, c = doc["problem"], doc["catalog"]
        problem = ProblemState(
            name=p["name"],
            domain=p["domain"],
            requirements=tuple(p["requirements"]),
            objects=p["objects"],
            init=dict(p["init"]),
            goal=p["goal"],
            horizon=p["horizon"],
            softs=tuple(p["softs"]),
            metric=p["metric"],
            view=p["view"],
        )
        added = tuple((a["morphism"], a["text"]) for a in c["added"])
        return ModelState(doc["domain_file"], problem, added, tuple(c["removed"]), tuple(c["failed"]))

    # ------------------------------------------------------------ changes
    def with_init(self, values: Mapping[str, StoredValue]) -> ModelState:
        return replace(self, problem=replace(self.problem, init={**self.problem.init, **values}))

    def with_problem(self, **changes: Any) -> ModelState:
        return replace(self, problem=replace(self.problem, **changes))

    def with_catalog(
        self,
        add: Sequence[tuple[str, str]] = (),
        remove: Iterable[str] = (),
        failed: Iterable[str] = (),
        recovered: Iterable[str] = (),
        sources: Mapping[str, str] | None = None,
    ) -> ModelState:
        """Add morphisms (replacing an added one of the same name), remove morphisms (an
        added one is dropped, one of the sources is cut out), mark morphisms failed or
        recovered.  ``sources`` tells which names the sources define."""
        remove = set(remove)
        in_sources = set(morphisms_in_sources(sources or {}))
        names = {m for m, _ in add}
        added = tuple((m, t) for m, t in self.added if m not in remove and m not in names) + tuple(add)
        removed = set(self.removed) | (remove & in_sources)  # an added one of a source's name replaces it
        failed_now = (set(self.failed) | set(failed)) - set(recovered)
        return replace(self, added=added, removed=tuple(sorted(removed)), failed=tuple(sorted(failed_now)))

    @property
    def catalog_names(self) -> set[str]:
        return {m for m, _ in self.added}


def sha256_text(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


# ---------------------------------------------------------------- from the user's files


@functools.lru_cache(maxsize=16)  # each step writes the model's files from the same sources
def _parse(path: str, text: str) -> list[Definition]:
    try:
        return outline(text, path)
    except CatError:  # the sources were checked when they were stored
        raise ValueError(f"{path} no longer parses") from None


def morphisms_in_sources(sources: Mapping[str, str]) -> dict[str, tuple[str, Section]]:
    """Every morphism declared in the sources: name → (source name, its declaration)."""
    out: dict[str, tuple[str, Section]] = {}
    for name, text in sources.items():
        for d in _parse(name, text):
            if d.kind == "domain":
                for section in d.sections:
                    if section.keyword == "morphism" and section.name is not None:
                        out[section.name] = (name, section)
    return out


def initial_model(inst: ir.Instance, problem_text: str, domain_file: str) -> ModelState:
    """The model state of a checked instance whose problem is written in ``problem_text``."""
    problems = [d for d in _parse("<problem>", problem_text) if d.kind == "problem" and d.name == inst.problem.name]
    node = problems[0]
    cut = lambda start, end: problem_text[start:end]  # noqa: E731
    requirements: list[str] = []
    objects: str | None = None
    goal, metric, softs = "true", None, []
    for s in node.sections:
        if s.keyword == "requirements":
            requirements.append(cut(s.start, s.end))
        elif s.keyword == "objects":
            objects = cut(s.start, s.end)
        elif s.keyword == "goal" and s.body is not None:
            goal = cut(*s.body)
        elif s.keyword == "soft":
            softs.append(_inner(cut(s.start, s.end), ":soft"))
        elif s.keyword == "metric":
            metric = _inner(cut(s.start, s.end), ":metric")
    init = {name: stored_value(v) for name, v in initial_state(inst).items()}
    problem = ProblemState(
        name=inst.problem.name,
        domain=inst.problem.domain,
        requirements=tuple(requirements),
        objects=objects,
        init=init,
        goal=goal,
        horizon=inst.problem.horizon,
        softs=tuple(softs),
        metric=metric,
        view=inst.problem.view,
    )
    return ModelState(domain_file, problem)


def _inner(section: str, keyword: str) -> str:
    """``(:soft C :weight 2)`` → ``C :weight 2``."""
    body = section.strip()
    assert body.startswith("(") and body.endswith(")")
    body = body[1:-1].strip()
    assert body.startswith(keyword)
    return body[len(keyword) :].strip()


# ---------------------------------------------------------------- to text


@dataclass(frozen=True)
class Region:
    """A piece of generated text and where it came from: ``origin`` names an event field
    (``goal``, ``set.budget``, ``catalog.add[0]``) or ``model`` for text of the sources."""

    file: str
    start: int
    end: int
    origin: str


class _Writer:
    def __init__(self, file: str) -> None:
        self.file, self.parts, self.regions, self.size = file, [], [], 0  # type: ignore[var-annotated]

    def put(self, text: str, origin: str | None = None) -> None:
        if origin is not None:
            self.regions.append(Region(self.file, self.size, self.size + len(text), origin))
        self.parts.append(text)
        self.size += len(text)

    def text(self) -> str:
        return "".join(self.parts)


def texts(
    model: ModelState,
    sources: Mapping[str, str],
    folder: str,
    origins: Mapping[str, str] | None = None,
) -> tuple[dict[str, str], list[Region]]:
    """The model as files in ``folder``: path → text, and the regions of generated text.
    ``origins`` names the
    event field behind a piece of the problem (``goal`` → ``goal``, ``init.budget`` →
    ``set.budget``...) — pieces not named come from the model."""
    origins = origins or {}
    cut = {m for m in (*model.removed, *model.failed)} | {m for m, _ in model.added}
    declared = morphisms_in_sources(sources)
    files: dict[str, str] = {}
    regions: list[Region] = []
    for name, text in sources.items():
        path = str(PurePosixPath(folder) / name)
        spans = sorted((d.start, d.end) for m, (src, d) in declared.items() if src == name and m in cut)
        w = _Writer(path)
        pos = 0
        for start, end in spans:
            w.put(text[pos:start])
            w.put("; (taken out of the catalogue by the runtime)")
            pos = end
        rest = text[pos:]
        if name == model.domain_file and model.added:
            close = _domain_close(text, model.problem.domain) - pos  # after every cut: morphisms lie inside
            w.put(rest[:close])
            for morphism, added in model.added:
                if morphism in model.failed:
                    continue
                w.put("\n  ")
                w.put(added, origins.get(f"catalog.{morphism}", "model"))
            w.put("\n")
            w.put(rest[close:])
        else:
            w.put(rest)
        files[path] = w.text()
        regions += w.regions
    path = str(PurePosixPath(folder) / PROBLEM_FILE)
    files[path], problem_regions = problem_text(model.problem, path, origins)
    return files, regions + problem_regions


def _domain_close(text: str, domain: str) -> int:
    """The offset of the ``)`` that closes ``(define (domain NAME) ...)`` in ``text``."""
    for d in _parse("<domain>", text):
        if d.kind == "domain" and d.name == domain:
            return d.end - 1
    raise ValueError(f"domain {domain} is not defined in its source")


HEADER = "Written by catrt from its store: the model as it is now."


def problem_file(inst: ir.Instance) -> str:
    """``problem.cat`` as the runtime writes it to ``STATE/model/``: the problem of the
    checked instance, written and laid out by catc (:func:`catc.api.problem_source`), so
    that ``catc fmt --check`` leaves it as it is."""
    return problem_source(inst, header=HEADER)


def problem_text(p: ProblemState, path: str, origins: Mapping[str, str]) -> tuple[str, list[Region]]:
    """The problem as the text catc checks: the sections an event brings are spliced in as
    the event gave them, each remembered as a :class:`Region`, so that an error in one is
    reported in the event's field.  Only checked, never written: the file on disk is
    :func:`problem_file` of the checked instance."""
    w = _Writer(path)
    w.put(f"; {HEADER}\n(define (problem {p.name})\n")
    w.put(f"  (:domain {p.domain})\n")
    for r in p.requirements:
        w.put("  ")
        w.put(r, "model")
        w.put("\n")
    if p.objects:
        w.put("  ")
        w.put(p.objects, "model")
        w.put("\n")
    w.put("  (:init")
    for name in sorted(p.init):
        w.put(" ")
        value = p.init[name]
        origin = origins.get(f"init.{name}", "model")
        if value is True:
            w.put(name, origin)
        elif value is False:
            w.put(f"(not {name})", origin)
        else:
            w.put(f"(= {name} {cat_value(value)})", origin)
    w.put(")\n  (:goal ")
    w.put(p.goal, origins.get("goal", "model"))
    w.put("\n  )\n")
    if p.horizon is not None:
        w.put("  ")
        w.put(f"(:horizon {p.horizon})", origins.get("horizon", "model"))
        w.put("\n")
    for i, soft in enumerate(p.softs):
        w.put("  (:soft ")
        w.put(soft, origins.get(f"softs.{i}", "model"))
        w.put("\n  )\n")
    if p.metric is not None:
        w.put("  (:metric ")
        w.put(p.metric, origins.get("metric", "model"))
        w.put("\n  )\n")
    if p.view is not None:
        w.put(f"  (:view {p.view})\n")
    w.put(")\n")
    return w.text(), w.regions
