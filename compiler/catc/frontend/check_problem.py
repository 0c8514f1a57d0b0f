"""AST problem → checked :class:`~catc.ir.Instance` (over its checked domain), and objective
texts given on the command line."""

from __future__ import annotations

from fractions import Fraction

from catc import ir
from catc.frontend.check_common import (
    DomainSource,
    _options,
    _positive_int,
    _Requirements,
    _unitless_target,
    _value,
)
from catc.frontend.check_domain import split_literals
from catc.frontend.typecheck import Context, ExprChecker, Scope, assignable, describe
from catc.ir import BOOL, SortKind
from catc.ir.fold import ConstantTooLarge, FoldError, fold_constant
from catc.ir.numbers import ratio_text
from catc.ir.views import project_instance
from catgrammar import ast, codes, limits
from catgrammar.diagnostics import Diagnostics, Note, Suggestion
from catgrammar.record import Record
from catgrammar.span import Span
from catgrammar.symbols import (
    RESERVED_NAMES,
    SOFT_OPTIONS,
    Option,
    Requirement,
)


class ProblemChecker:
    def __init__(self, workspace: DomainSource, node: ast.Problem, path: str, diags: Diagnostics):
        self.ws = workspace
        self.node = node
        self.path = path
        self.diags = diags
        self.left_out: set[str] = set()

    def _single(self, cls, what: str):
        found = [s for s in self.node.sections if isinstance(s, cls)]
        for extra in found[1:]:
            self.diags.report(
                codes.DUPLICATE_OPTION, f"{what} is given twice", extra.span, Note("first given here", found[0].span)
            )
        return found[0] if found else None

    def run(self) -> ir.Instance | None:
        before = len(self.diags.errors)
        node = self.node
        dref = self._single(ast.DomainRef, "(:domain ...)")
        if dref is None:
            self.diags.report(
                codes.MISSING_OPTION,
                f"problem '{node.name.text}' does not name its domain: add (:domain NAME)",
                node.name.span,
            )
            return None
        domain = self.ws.domain_ir(dref.name.text, self.path, dref.name.span)
        if domain is None:
            return None
        self.domain = domain
        self.req = _Requirements(
            (s for s in node.sections if isinstance(s, ast.Requirements)),
            self.diags,
            domain.requirements,
            header=node.name.span,
        )
        objects = self._objects()
        constants = dict(domain.constants)
        constants.update(objects)
        self.scope = Scope(domain.sorts, constants, domain.resources, {}, domain.morphisms)
        self.checker = ExprChecker(self.scope, self.diags, self.req.need)

        view = self._view()
        init = self._init(view)
        goal_sec = self._single(ast.Goal, "(:goal ...)")
        goal = split_literals(self.checker, goal_sec.condition, ir.Label.goal, Context.CONDITION) if goal_sec else []
        if goal_sec is None:
            self.diags.report(codes.MISSING_OPTION, f"problem '{node.name.text}' has no (:goal ...)", node.name.span)
        horizon_sec = self._single(ast.Horizon, "(:horizon ...)")
        horizon = None
        if horizon_sec is not None:
            horizon = _positive_int(horizon_sec.steps, "the horizon", self.diags, allow_zero=True)
            if horizon is not None and horizon > limits.current().horizon:
                limit = limits.BY_NAME["horizon"]
                self.diags.report(
                    limit.code,
                    f"the horizon {horizon_sec.steps.text} is more than the horizon limit "
                    f"({limits.count_text(limits.current().horizon, 'step')}); {limit.how_to_raise}",
                    horizon_sec.steps.span,
                )
        softs = self._softs()
        metric = self._metric()
        deployed = self._deployed()
        if len(self.diags.errors) > before:
            return None
        problem = ir.Problem(
            name=node.name.text,
            domain=domain.name,
            requirements=self.req.names,
            objects=ir.frozen(objects),
            init=ir.frozen(init),
            goal=tuple(goal),
            horizon=horizon,
            softs=tuple(softs),
            metric=metric,
            deployed=tuple(deployed),
            view=view,
            span=node.span,
            horizon_span=horizon_sec.span if horizon_sec else None,
        )
        inst = ir.Instance(domain, problem)
        if self.left_out:  # imported resources the model never mentions: projected away, as a view would
            inst = project_instance(inst, frozenset(domain.resources) - self.left_out, None)
        return inst

    def _unmentioned_imports(self) -> frozenset[str]:
        """Resources declared by an imported domain (another file) that need no initial value and
        are left out: a number or symbol that neither the domain's own morphisms nor the problem
        mention; a bool or set (whose default, false or empty, stays otherwise) that no morphism at
        all reads or writes.  docs/stdlib.md."""
        own = self.domain.span.file if self.domain.span else None
        mentioned: set[str] = set(_names_in(self.node))
        touched: set[str] = set()
        for m in self.domain.morphisms.values():
            touched |= m.reads | m.writes
            if m.span is None or m.span.file == own:
                mentioned |= m.reads | m.writes
        return frozenset(
            r.name
            for r in self.domain.resources.values()
            if r.span is not None
            and own is not None
            and r.span.file != own
            and r.name not in mentioned
            and (r.sort.kind not in (SortKind.BOOL, SortKind.SET) or r.name not in touched)
        )

    def _objects(self) -> dict[str, ir.Constant]:
        out: dict[str, ir.Constant] = {}
        for sec in self.node.sections:
            if not isinstance(sec, ast.Objects):
                continue
            self.req.need(Requirement.SYMBOLS, sec.span, "problem objects")
            for group in sec.groups:
                sort = None
                if group.type is None:
                    self.diags.report(codes.BAD_SORT, "objects need a sort: write '... - SORT'", group.span)
                else:
                    sort = self.domain.sorts.get(group.type.text)
                    if sort is None:
                        hint = Suggestion(group.type.text, self.domain.sorts, group.type.span)
                        self.diags.report(
                            codes.UNKNOWN_NAME,
                            f"unknown sort '{group.type.text}'{hint.hint}",
                            group.type.span,
                            fixes=hint.fixes,
                        )
                    elif sort.kind is SortKind.ENUM:
                        self.diags.report(
                            codes.CLOSED_SORT,
                            f"enumeration '{sort.name}' is closed; problems cannot add values to it "
                            f"(declare it '- symbol' to make it open)",
                            group.type.span,
                        )
                        sort = None
                for name in group.names:
                    prev = out.get(name.text) or self.domain.constants.get(name.text)
                    if name.text in RESERVED_NAMES:
                        self.diags.report(
                            codes.RESERVED_NAME, f"'{name.text}' is a keyword and cannot name an object", name.span
                        )
                    elif prev is not None:
                        notes = [Note("previously declared here", prev.span)] if prev.span else []
                        self.diags.report(
                            codes.DUPLICATE_NAME, f"object '{name.text}' is declared twice", name.span, *notes
                        )
                    elif name.text in self.domain.resources:
                        self.diags.report(
                            codes.DUPLICATE_NAME, f"object '{name.text}' has the name of a resource", name.span
                        )
                    elif sort is not None:
                        out[name.text] = ir.Constant(name.text, sort, name.span)
        return out

    def _view(self) -> str | None:
        sec = self._single(ast.ViewUse, "(:view ...)")
        if sec is None:
            return None
        self.req.need(Requirement.VIEWS, sec.span, "(:view ...)")
        if sec.name.text not in self.domain.views:
            hint = Suggestion(sec.name.text, self.domain.views, sec.name.span)
            self.diags.report(
                codes.UNKNOWN_NAME, f"unknown view '{sec.name.text}'{hint.hint}", sec.name.span, fixes=hint.fixes
            )
            return None
        return sec.name.text

    def _init(self, view: str | None) -> dict[str, ir.InitValue]:
        out: dict[str, ir.InitValue] = {}
        resources = self.domain.resources
        sections = [s for s in self.node.sections if isinstance(s, ast.Init)]
        attempted: set[str] = set()
        for sec in sections:
            for lit in sec.literals:
                attempted |= _init_target(lit)
                parsed = self._init_literal(lit)
                if parsed is None:
                    continue
                name, value = parsed
                if name in out:
                    self.diags.report(
                        codes.DUPLICATE_OPTION,
                        f"'{name}' is given an initial value twice",
                        lit.span,
                        Note("first given here", out[name].span),
                    )
                    continue
                out[name] = ir.InitValue(name, value, ir.Label.init(name), lit.span)
        dropped = self.domain.views[view].dropped if view else frozenset()
        unmentioned = self._unmentioned_imports()
        missing = []
        for res in resources.values():
            if res.name in out:
                continue
            if res.name in unmentioned and res.name not in attempted:
                self.left_out.add(res.name)
            elif res.sort.kind is SortKind.BOOL:
                out[res.name] = ir.InitValue(res.name, ir.Const(False, BOOL), res.init_label, None)
            elif res.sort.kind is SortKind.SET:
                out[res.name] = ir.InitValue(res.name, ir.SetLit((), res.sort), res.init_label, None)
            elif res.name not in dropped and res.name not in attempted:
                missing.append(res)
        if missing:
            where = sections[0].span if sections else self.node.name.span
            names = ", ".join(f"'{r.name}'" for r in missing)
            self.diags.report(
                codes.MISSING_INIT,
                f"no initial value for {names}: numeric and symbolic resources must be given one with (= resource value)",
                where,
                *[Note(f"'{r.name}' is declared here", r.span) for r in missing[:3] if r.span],
            )
        return out

    def _init_literal(self, lit: ast.Expr) -> tuple[str, ir.Const | ir.SetLit] | None:
        res = self.domain.resources
        if isinstance(lit, ast.Ref) and lit.name in res and res[lit.name].sort.kind is SortKind.BOOL:
            return lit.name, ir.Const(True, BOOL, lit.span)
        if (
            isinstance(lit, ast.Call)
            and lit.head.text == "not"
            and len(lit.args) == 1
            and isinstance(lit.args[0], ast.Ref)
            and lit.args[0].name in res
            and res[lit.args[0].name].sort.kind is SortKind.BOOL
        ):
            return lit.args[0].name, ir.Const(False, BOOL, lit.span)
        if isinstance(lit, ast.Call) and lit.head.text == "=":
            merged = self.checker.merge_quantities(lit.args)
            if merged is not lit.args:
                lit = ast.Call(lit.head, merged, lit.span)
        if not (isinstance(lit, ast.Call) and lit.head.text == "=" and len(lit.args) == 2):
            self.diags.report(
                codes.BAD_INIT,
                "an initial-state literal is (= resource value), a bool resource, or (not resource)",
                lit.span,
            )
            return None
        target, value_node = lit.args
        if not isinstance(target, ast.Ref) or target.name not in res:
            label = target.name if isinstance(target, ast.Ref) else None
            if label is not None:
                hint = Suggestion(label, res, target.span)
                self.diags.report(
                    codes.UNKNOWN_NAME, f"unknown resource '{label}'{hint.hint}", target.span, fixes=hint.fixes
                )
            else:
                self.diags.report(
                    codes.BAD_INIT, "the left side of an initial-state literal must be a resource", target.span
                )
            return None
        r = res[target.name]
        value = self.checker.term(value_node, Context.CONSTANT, r.sort)
        if value is None:
            return None
        if r.sort.is_numeric and value.sort.is_numeric:
            converted = self._init_in_unit(r, value, value_node)
            if converted is None:
                return None
            value = converted
        try:
            folded = fold_constant(value)
        except FoldError as exc:
            code = codes.CONSTANT_TOO_LARGE if isinstance(exc, ConstantTooLarge) else codes.DIVISION_BY_ZERO
            self.diags.report(code, str(exc), exc.expr.span or value_node.span)
            return None
        if folded is None:
            self.diags.report(codes.BAD_INIT, "an initial value must be a constant", value_node.span)
            return None
        if not assignable(r.sort, folded.sort, self.domain.sorts):
            self.diags.report(
                codes.TYPE_MISMATCH,
                f"'{r.name}' is {describe(r.sort)} and cannot start as {describe(folded.sort)}",
                value_node.span,
            )
            return None
        if isinstance(folded, ir.Const) and r.sort.is_numeric:
            v = folded.value
            if (r.lower is not None and v < r.lower) or (r.upper is not None and v > r.upper):  # type: ignore[operator]
                self.diags.report(
                    codes.BAD_VALUE,
                    f"initial value {_fmt(v)} of '{r.name}' lies outside its bounds "  # type: ignore[arg-type]
                    f"[{_fmt(r.lower)}, {_fmt(r.upper)}]",
                    value_node.span,
                )
                return None
            folded = ir.Const(v, r.sort, folded.span)
        return target.name, folded

    def _init_in_unit(self, r: ir.Resource, value: ir.Expr, value_node: ast.Expr) -> ir.Expr | None:
        """An initial value converted to the resource's unit (E0313 for another dimension)."""
        unified = self.checker.unify(
            [value],
            [value_node],
            codes.UNIT_MISMATCH_EFFECT,
            lambda a, b: f"{a} cannot start as {b}",
            self.checker.scope.unit_of(r.name),
            r.name,
        )
        if unified is None:
            return None
        _unitless_target(self.checker, r, unified[0][0], value_node, self.diags)
        return unified[0][0]

    def _softs(self) -> list[ir.Soft]:
        out = []
        for i, sec in enumerate((s for s in self.node.sections if isinstance(s, ast.Soft)), 1):
            self.req.need(Requirement.OPTIMIZATION, sec.span, "a soft constraint")
            opts = _options(sec.options, SOFT_OPTIONS, "(:soft ...)", self.diags)
            weight = Fraction(1)
            if Option.WEIGHT.value in opts:
                num = _value(opts[Option.WEIGHT.value], ast.Num)
                if num.value <= 0:
                    self.diags.report(
                        codes.BAD_VALUE, f"a soft constraint's weight must be positive, got {num.text}", num.span
                    )
                weight = num.value
            expr = self.checker.condition(sec.condition)
            if expr is not None:
                out.append(ir.Soft(expr, weight, ir.Label.soft(i), sec.span))
        return out

    def _metric(self) -> ir.Metric | None:
        sec = self._single(ast.Metric, "(:metric ...)")
        if sec is None:
            return None
        self.req.need(Requirement.OPTIMIZATION, sec.span, "(:metric ...)")
        objectives = []
        for obj in sec.objectives:
            term = self.checker.numeric(obj.term, Context.OBJECTIVE)
            if term is not None:
                objectives.append(ir.Objective(ir.Sense(obj.sense.text), term, obj.span))
        mode = ir.MetricMode(sec.mode)
        if mode is ir.MetricMode.PARETO and len(sec.objectives) < 2:
            self.diags.report(codes.BAD_OBJECTIVE, "a pareto metric needs at least two objectives", sec.span)
        return ir.Metric(mode, tuple(objectives), sec.span)

    def _deployed(self) -> list[str]:
        out: list[str] = []
        for sec in self.node.sections:
            if not isinstance(sec, ast.Deployed):
                continue
            self.req.need(Requirement.RECOMPOSITION, sec.span, "(:deployed ...)")
            for name in sec.names:
                if name.text not in self.domain.morphisms:
                    hint = Suggestion(name.text, self.domain.morphisms, name.span)
                    self.diags.report(
                        codes.UNKNOWN_NAME, f"unknown morphism '{name.text}'{hint.hint}", name.span, fixes=hint.fixes
                    )
                elif name.text in out:
                    self.diags.report(
                        codes.DUPLICATE_OPTION, f"'{name.text}' is listed twice in (:deployed ...)", name.span
                    )
                else:
                    out.append(name.text)
        return out


def _init_target(lit: ast.Expr) -> set[str]:
    """The resource an init literal is about, even when the literal is ill-typed."""
    if isinstance(lit, ast.Call) and lit.args and isinstance(lit.args[0], ast.Ref):
        return {lit.args[0].name}
    return {lit.name} if isinstance(lit, ast.Ref) else set()


def _fmt(v: Fraction | None) -> str:
    return "*" if v is None else ratio_text(v)


def check_objective_text(text: str, inst: ir.Instance, diags: Diagnostics, origin: str) -> ir.Expr | None:
    """A numeric objective term given on the command line (``--minimize EXPR``) or through
    the API, checked against an instance.  Diagnostics point into ``text`` itself, as the
    pseudo-file ``origin`` (the term is parsed inside a wrapper problem; the wrapper never
    shows)."""
    from catgrammar.parser import parse_text
    from catgrammar.span import Source

    prefix = "(define (problem objective) (:metric minimize "
    wrapped = prefix + text + "))"
    local = Diagnostics()
    term = None
    parsed = parse_text(wrapped, origin, local)
    if parsed is not None:
        metric = next((s for s in parsed.definitions[0].sections if isinstance(s, ast.Metric)), None)
        if metric is None or len(metric.objectives) != 1:
            local.report(codes.BAD_OBJECTIVE, f"expected one objective term, got {text!r}", None)
        else:
            constants = inst.constants()
            scope = Scope(inst.domain.sorts, constants, inst.domain.resources, {}, inst.domain.morphisms)
            term = ExprChecker(scope, local, lambda *args: None).numeric(metric.objectives[0].term, Context.OBJECTIVE)
    diags.add_source(Source(origin, text))
    for d in local:
        diags.report(
            d.code,
            d.message,
            _unwrapped(d.span, len(prefix), text),
            *[Note(n.message, _unwrapped(n.span, len(prefix), text)) for n in d.notes],
            severity=d.severity,
        )
    return None if local.has_errors else term


def _unwrapped(span: Span | None, shift: int, text: str) -> Span | None:
    """A span of the wrapped objective text moved onto the term ``text`` alone (clamped to it)."""
    if span is None:
        return None
    start = min(max(span.start - shift, 0), len(text))
    end = min(max(span.end - shift, start), len(text))

    def position(offset: int) -> tuple[int, int]:
        line_start = text.rfind("\n", 0, offset) + 1
        return text.count("\n", 0, offset) + 1, offset - line_start + 1

    (line, column), (end_line, end_column) = position(start), position(end)
    return span._replace(line=line, column=column, end_line=end_line, end_column=end_column, start=start, end=end)


def _names_in(node: object) -> set[str]:
    """Every name an AST subtree refers to (references and call heads), without recursion limits."""
    out: set[str] = set()
    stack: list[object] = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, ast.Ref):
            out.add(n.name)
        elif isinstance(n, ast.Name):
            out.add(n.text)
        elif isinstance(n, (tuple, list)):
            stack.extend(n)
        elif isinstance(n, Record):
            fields: tuple[str, ...] = n.__slots__  # every node names its slots
            stack.extend(getattr(n, f) for f in fields if f != "span")
    return out
