"""Checking grounding annotations: ``(:ground (KIND ...))`` blocks and ``(:deployment ...)``.

The grammar gives every block the shape ``:key datum ...``; here each key is checked
against the morphism's kind (:data:`catgrammar.symbols.GROUND_OPTIONS`), each datum against
what the key needs, every name a target will write against that target's rules (ROS 2 node,
parameter and topic names, image references, XML names, Compose project names), every hole
``{θ}`` of an instruction against the morphism's parameters, and every binding against the
parameters and resources in scope.  Errors are located and collected, as everywhere.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping

from catc import ir
from catc.ir.grounding import (
    BehaviorGrounding,
    Deployment,
    Grounding,
    HardwareGrounding,
    Profile,
    RealLiteral,
    SoftwareGrounding,
    Template,
    Value,
    ValueKind,
    image_problem,
    ros_name_problem,
    topic_problem,
    xml_name_problem,
)
from catgrammar import ast, codes
from catgrammar.diagnostics import Diagnostics, Fix, Note, Suggestion
from catgrammar.span import Span
from catgrammar.symbols import DEPLOYMENT_OPTIONS, GROUND_OPTIONS, Option

_PROJECT = re.compile(r"[a-z0-9][a-z0-9_-]*")
_HOLE = re.compile(r"\{\{|\}\}|\{([^{}]*)\}|[{}]")


class GroundChecker:
    """Checks one morphism's grounding block (or a deployment section) into IR records."""

    def __init__(
        self,
        diags: Diagnostics,
        params: Mapping[str, ir.Param],
        resources: Mapping[str, ir.Resource],
        owner: str,
    ) -> None:
        self.diags, self.params, self.resources, self.owner = diags, params, resources, owner
        self.ok = True

    def error(self, code: str, message: str, span: Span | None, *notes: Note, fixes: tuple[Fix, ...] = ()) -> None:
        self.ok = False
        self.diags.report(code, message, span, *notes, fixes=fixes)

    # ------------------------------------------------------------ blocks
    def ground(self, block: ast.Ground, kind: ir.MorphismKind) -> Grounding | None:
        name = block.kind.text
        if name not in GROUND_OPTIONS:
            suggestion = Suggestion(name, GROUND_OPTIONS, block.kind.span)
            hint = suggestion.hint or f"; expected one of {', '.join(GROUND_OPTIONS)}"
            self.error(
                codes.BAD_GROUNDING, f"unknown grounding kind '{name}'{hint}", block.kind.span, fixes=suggestion.fixes
            )
            return None
        if name != kind.value:
            self.error(
                codes.BAD_GROUNDING,
                f"{self.owner} is {kind.value}, but its grounding is {name}: a {kind.value} component is grounded as "
                f"({kind.value} ...)",
                block.kind.span,
            )
            return None
        pairs = self.pairs(block.pairs, GROUND_OPTIONS[name], f"a {name} grounding")
        build: dict[str, Callable[[dict[str, ast.Opt], Span], Grounding | None]] = {
            "hardware": self._hardware,
            "software": self._software,
            "behavior": self._behavior,
        }
        result = build[name](pairs, block.span)
        return result if self.ok else None

    def deployment(self, decl: ast.DeploymentDecl) -> Deployment | None:
        pairs = self.pairs(decl.pairs, DEPLOYMENT_OPTIONS, "(:deployment ...)")
        project_opt = self.require(pairs, Option.PROJECT, decl.span, "(:deployment ...)")
        project = self.word(project_opt) if project_opt else None
        if project is not None and project_opt is not None and not _PROJECT.fullmatch(project):
            self.error(
                codes.BAD_TARGET_NAME,
                f"'{project}' cannot name a Compose project: lower-case letters, digits, '_' and '-', starting with a "
                "letter or digit",
                project_opt.value.span,  # type: ignore[attr-defined]
            )
        executor = self.image(pairs.get(Option.EXECUTOR.value))
        if not self.ok or project is None:
            return None
        return Deployment(project, executor, decl.span)

    def pairs(self, pairs: tuple[ast.Opt, ...], allowed: tuple[Option, ...], where: str) -> dict[str, ast.Opt]:
        keys = [o.value for o in allowed]
        out: dict[str, ast.Opt] = {}
        for pair in pairs:
            if pair.key not in keys:
                suggestion = Suggestion(pair.key, keys, _head_span(pair.span, len(pair.key)))
                hint = suggestion.hint or f"; it takes {', '.join(keys)}"
                self.error(
                    codes.BAD_GROUNDING,
                    f"'{pair.key}' does not belong in {where}{hint}",
                    pair.span,
                    fixes=suggestion.fixes,
                )
            elif pair.key in out:
                self.error(
                    codes.DUPLICATE_OPTION,
                    f"'{pair.key}' is given twice in {where}",
                    pair.span,
                    Note("first given here", out[pair.key].span),
                )
            else:
                out[pair.key] = pair
        return out

    def require(self, pairs: dict[str, ast.Opt], key: Option, span: Span, where: str) -> ast.Opt | None:
        if key.value not in pairs:
            self.error(codes.BAD_GROUNDING, f"{where} needs {key.value}", span)
            return None
        return pairs[key.value]

    # ------------------------------------------------------------ kinds
    def _hardware(self, pairs: dict[str, ast.Opt], span: Span) -> Grounding | None:
        instruction = self.require(pairs, Option.INSTRUCTION, span, "a hardware grounding")
        template = self.template(instruction) if instruction else None
        check_opt = pairs.get(Option.CHECK.value)
        check = self.template(check_opt) if check_opt else None
        parts = self.strings(pairs.get(Option.PARTS.value))
        if template is None:
            return None
        return HardwareGrounding(template, check, parts, span)

    def _software(self, pairs: dict[str, ast.Opt], span: Span) -> Grounding | None:
        image = self.image(self.require(pairs, Option.IMAGE, span, "a software grounding"))
        node_opt = pairs.get(Option.NODE.value)
        node = self.word(node_opt) if node_opt else None
        if node is not None and node_opt is not None:
            self.name_rule(node, ros_name_problem, "a ROS 2 node name", node_opt.value.span)  # type: ignore[attr-defined]
        params = self.bindings(pairs.get(Option.PARAMS.value), keys=False, rule=self._param_name_problem)
        remap = self.bindings(pairs.get(Option.REMAP.value), keys=False, rule=topic_problem, topics=True)
        profile = self.profile(pairs.get(Option.PROFILE.value), Profile.DRIVERS)
        if image is None:
            return None
        return SoftwareGrounding(image, node or "", profile, params, remap, span)

    def _behavior(self, pairs: dict[str, ast.Opt], span: Span) -> Grounding | None:
        id_opt = self.require(pairs, Option.ID, span, "a behavior grounding")
        node_id = self.word(id_opt) if id_opt else None
        if node_id is not None and id_opt is not None:
            self.name_rule(node_id, xml_name_problem, "a BehaviorTree.CPP node ID", id_opt.value.span)  # type: ignore[attr-defined]
        inputs = self.bindings(pairs.get(Option.INPUTS.value), keys=True, rule=xml_name_problem)
        outputs = self.bindings(pairs.get(Option.OUTPUTS.value), keys=True, rule=xml_name_problem, outputs=True)
        image_opt = pairs.get(Option.IMAGE.value)
        image = self.image(image_opt) if image_opt else None
        profile = self.profile(pairs.get(Option.PROFILE.value), Profile.SKILLSETS)
        if node_id is None:
            return None
        return BehaviorGrounding(node_id, inputs, outputs, image, profile, span)

    # ------------------------------------------------------------ data
    def word(self, opt: ast.Opt) -> str | None:
        """A name or a string."""
        value = opt.value
        if isinstance(value, ast.Name):
            return value.text
        if isinstance(value, ast.Str):
            return value.text
        self.error(codes.BAD_GROUNDING, f"{opt.key} takes a name or a string", opt.span)
        return None

    def string(self, opt: ast.Opt) -> ast.Str | None:
        if isinstance(opt.value, ast.Str):
            return opt.value
        self.error(codes.BAD_GROUNDING, f'{opt.key} takes a string ("...")', opt.span)
        return None

    def strings(self, opt: ast.Opt | None) -> tuple[str, ...]:
        if opt is None:
            return ()
        items = opt.value.items if isinstance(opt.value, ast.DatumList) else None
        if items is None or not all(isinstance(i, ast.Str) for i in items):
            self.error(codes.BAD_GROUNDING, f'{opt.key} takes a list of strings: ("..." "...")', opt.span)
            return ()
        return tuple(i.text for i in items)  # type: ignore[union-attr]

    def image(self, opt: ast.Opt | None) -> str | None:
        if opt is None:
            return None
        s = self.string(opt)
        if s is None:
            return None
        self.name_rule(s.text, image_problem, "a container image", s.span)
        return s.text

    def profile(self, opt: ast.Opt | None, default: Profile) -> Profile:
        if opt is None:
            return default
        word = self.word(opt)
        names = [p.value for p in Profile]
        if word not in names:
            span = opt.value.span  # type: ignore[attr-defined]
            suggestion = Suggestion(word or "", names, span if word else None)
            hint = suggestion.hint or f"; expected one of {', '.join(names)}"
            self.error(codes.BAD_GROUNDING, f"unknown profile '{word}'{hint}", span, fixes=suggestion.fixes)
            return default
        return Profile(word)

    def name_rule(self, name: str, rule: Callable[[str], str | None], what: str, span: Span | None) -> None:
        why = rule(name)
        if why is not None:
            self.error(codes.BAD_TARGET_NAME, f"'{name}' cannot be {what}: {why}", span)

    @staticmethod
    def _param_name_problem(name: str) -> str | None:
        for token in name.split("."):
            why = ros_name_problem(token)
            if why is not None:
                return why
        return None

    def template(self, opt: ast.Opt) -> Template | None:
        """A string with ``{θ}`` holes (``{{`` and ``}}`` for braces)."""
        s = self.string(opt)
        if s is None:
            return None
        parts: list[str | Value] = []
        text, pos = s.text, 0
        for m in _HOLE.finditer(text):
            parts.append(text[pos : m.start()])
            pos = m.end()
            token = m.group(0)
            if token in ("{{", "}}"):
                parts.append(token[0])
            elif m.group(1) is None:
                self.error(codes.BAD_GROUNDING, f"a lone '{token}' in {opt.key}: write '{token * 2}'", s.span)
            elif m.group(1) in self.params:
                parts.append(Value(ValueKind.PARAM, m.group(1), span=s.span))
            else:
                where = _inner_span(s, m.start(), m.end())
                inner = where != s.span  # the hole's own span: its fix replaces it
                suggestion = Suggestion(m.group(1), self.params, where if inner else None, "{{{}}}")
                hint = suggestion.hint or (
                    f"; holes name parameters of {self.owner}" + (f" ({', '.join(self.params)})" if self.params else "")
                )
                self.error(
                    codes.BAD_GROUNDING,
                    f"{{{m.group(1)}}} names no parameter of {self.owner}{hint}",
                    where,
                    fixes=suggestion.fixes,
                )
        parts.append(text[pos:])
        return Template(tuple(p for p in parts if p != ""), s.span)

    def bindings(
        self,
        opt: ast.Opt | None,
        *,
        keys: bool,
        rule: Callable[[str], str | None],
        topics: bool = False,
        outputs: bool = False,
    ) -> tuple[tuple[str, Value], ...]:
        """``((name value) ...)``: each name checked by ``rule``, each value a θ, a
        resource, a literal, or ``(key NAME)`` where ``keys``."""
        if opt is None:
            return ()
        if not isinstance(opt.value, ast.DatumList):
            self.error(codes.BAD_GROUNDING, f"{opt.key} takes a list of (name value) pairs", opt.span)
            return ()
        out: list[tuple[str, Value]] = []
        for item in opt.value.items:
            pair = self.binding(item, opt.key, keys, rule, topics, outputs)
            if pair is not None:
                out.append(pair)
        return tuple(out)

    def binding(
        self,
        item: ast.Datum,
        key: str,
        keys: bool,
        rule: Callable[[str], str | None],
        topics: bool,
        outputs: bool,
    ) -> tuple[str, Value] | None:
        if not (
            isinstance(item, ast.DatumList) and len(item.items) == 2 and isinstance(item.items[0], (ast.Name, ast.Str))
        ):
            self.error(codes.BAD_GROUNDING, f"each entry of {key} is (name value)", item.span)
            return None
        name_node, value_node = item.items
        name = name_node.text  # type: ignore[union-attr]
        self.name_rule(name, rule, "a topic name" if topics else f"a name in {key}", name_node.span)
        value = self.value(value_node, keys)
        if value is None:
            return None
        if outputs and value.kind is not ValueKind.KEY:
            self.error(codes.BAD_GROUNDING, "an output port writes a blackboard entry: (key NAME)", value_node.span)
        if topics and not self._topic_like(value):
            self.error(codes.BAD_GROUNDING, "a remapping's target is a topic: a symbol or a string", value_node.span)
        return name, value

    def _topic_like(self, value: Value) -> bool:
        if value.kind is ValueKind.LITERAL:
            return isinstance(value.literal, str)
        sort = self.params[value.name].sort if value.kind is ValueKind.PARAM else self.resources[value.name or ""].sort  # type: ignore[index]
        return sort.is_symbolic

    def value(self, node: ast.Datum, keys: bool) -> Value | None:
        if isinstance(node, ast.Num):
            real = any(c in node.text for c in ".eE")  # written as a real: a real, even when whole
            return Value(ValueKind.LITERAL, literal=RealLiteral(node.value) if real else node.value, span=node.span)
        if isinstance(node, ast.Str):
            return Value(ValueKind.LITERAL, literal=node.text, span=node.span)
        if isinstance(node, ast.BoolLit):
            return Value(ValueKind.LITERAL, literal=node.value, span=node.span)
        if isinstance(node, ast.Name):
            if node.text in self.params:
                return Value(ValueKind.PARAM, node.text, span=node.span)
            if node.text in self.resources:
                return Value(ValueKind.RESOURCE, node.text, span=node.span)
            scope = [*self.params, *self.resources]
            suggestion = Suggestion(node.text, scope, node.span)
            self.error(
                codes.UNKNOWN_NAME,
                f"'{node.text}' is neither a parameter of {self.owner} nor a resource{suggestion.hint}"
                '; a string is written "..."',
                node.span,
                fixes=suggestion.fixes,
            )
            return None
        items = node.items  # a list: only (key NAME)
        if (
            len(items) == 2
            and isinstance(items[0], ast.Name)
            and items[0].text == "key"
            and isinstance(items[1], ast.Name)
        ):
            if not keys:
                self.error(codes.BAD_GROUNDING, "blackboard keys (key NAME) belong to behaviour ports", node.span)
                return None
            self.name_rule(items[1].text, ros_name_problem, "a blackboard key", items[1].span)
            return Value(ValueKind.KEY, items[1].text, span=node.span)
        self.error(codes.BAD_GROUNDING, "a value is a parameter, a resource, a number, a string, true/false or (key NAME)",
                   node.span)  # fmt: skip
        return None


def _head_span(span: Span, length: int) -> Span:
    """The first ``length`` characters of ``span`` (a ``:key`` at the start of a pair)."""
    return Span(span.file, span.line, span.column, span.line, span.column + length, span.start, span.start + length)


def _inner_span(s: ast.Str, start: int, end: int) -> Span:
    """The span of ``s.text[start:end]`` in the source, when the string is written on one
    line without escapes (else the whole string)."""
    span = s.span
    if span.end_line != span.line or span.end - span.start != len(s.text) + 2:
        return span
    offset = span.start + 1
    return Span(
        span.file, span.line, span.column + 1 + start, span.line, span.column + 1 + end, offset + start, offset + end
    )
