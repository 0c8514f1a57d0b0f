"""AST domain → checked :class:`~catc.ir.Domain`: imports, sorts, constants, resources,
morphisms (their parameters, literals and effects), holes and views."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from fractions import Fraction
from typing import TYPE_CHECKING, TypeVar

from catc import ir
from catc.frontend.check_common import (
    _KINDS,
    _bounds,
    _options,
    _positive_int,
    _Requirements,
    _unitless_target,
    _value,
)
from catc.frontend.check_ground import GroundChecker
from catc.frontend.typecheck import Context, ExprChecker, Scope, assignable, describe
from catc.ir import BOOL, INT, REAL, Sort, SortKind
from catc.ir.fold import ConstantTooLarge, FoldError, fold_constant
from catc.ir.grounding import Deployment
from catgrammar import ast, codes, limits
from catgrammar.diagnostics import Diagnostics, Fix, Note, Suggestion
from catgrammar.symbols import (
    HOLE_OPTIONS,
    MORPHISM_OPTIONS,
    PARAMETER_OPTIONS,
    RESERVED_NAMES,
    RESOURCE_OPTIONS,
    VIEW_OPTIONS,
    Option,
    Requirement,
)

if TYPE_CHECKING:
    from catc.frontend.units import Unit  # pragma: no cover
    from catc.frontend.workspace import Workspace


_V = TypeVar("_V")


class DomainChecker:
    def __init__(self, workspace: Workspace, node: ast.Domain, path: str, diags: Diagnostics):
        self.ws = workspace
        self.node = node
        self.path = path
        self.diags = diags
        self.sorts: dict[str, Sort] = {}
        self.constants: dict[str, ir.Constant] = {}
        self.resources: dict[str, ir.Resource] = {}
        self.morphisms: dict[str, ir.Morphism] = {}
        self.holes: dict[str, ir.Hole] = {}
        self.views: dict[str, ir.View] = {}
        self.imported: list[str] = []
        self.imported_domains: list[ir.Domain] = []
        self.failed = False
        self.cost_unit: tuple[Unit, str] | None = None  # the unit of the first :cost with one

    # ------------------------------------------------------------------ names
    def _fold(self, expr: ir.Expr) -> ir.Const | ir.SetLit | None:
        """The constant value of ``expr`` (None if it has none); division by zero is E0310."""
        try:
            return fold_constant(expr)
        except FoldError as exc:
            code = codes.CONSTANT_TOO_LARGE if isinstance(exc, ConstantTooLarge) else codes.DIVISION_BY_ZERO
            self.diags.report(code, str(exc), exc.expr.span or expr.span)
            return None

    def _declare(self, table: dict, name: ast.Name, what: str, existing_span=None) -> bool:
        text = name.text
        if text in RESERVED_NAMES:
            self.diags.report(codes.RESERVED_NAME, f"'{text}' is a keyword and cannot name a {what}", name.span)
            return False
        if text in table:
            prev = table[text]
            span = getattr(prev, "span", None) or existing_span
            notes = [Note("previously declared here", span)] if span else []
            self.diags.report(codes.DUPLICATE_NAME, f"{what} '{text}' is declared twice", name.span, *notes)
            return False
        return True

    def _value_name_taken(self, name: ast.Name, what: str) -> bool:
        """Resources, constants and enumeration values share one namespace."""
        for table, kind in ((self.resources, "resource"), (self.constants, "constant")):
            if name.text in table:
                prev = table[name.text]
                notes = [Note(f"the {kind} is declared here", prev.span)] if prev.span else []
                self.diags.report(
                    codes.DUPLICATE_NAME, f"{what} '{name.text}' has the name of a {kind}", name.span, *notes
                )
                return True
        return False

    # ------------------------------------------------------------------ run
    def run(self) -> ir.Domain | None:
        before = len(self.diags.errors)
        sections = self.node.sections
        self.req = _Requirements(
            (s for s in sections if isinstance(s, ast.Requirements)), self.diags, header=self.node.name.span
        )
        for sec in sections:
            if isinstance(sec, ast.Imports):
                self._imports(sec)
        for sec in sections:
            if isinstance(sec, ast.Sorts):
                self._sorts(sec)
        self._check_sort_cycles()
        for sec in sections:
            if isinstance(sec, ast.Constants):
                self._constants(sec)
        for sec in sections:
            if isinstance(sec, ast.Resources):
                for r in sec.resources:
                    self._resource(r)
        for sec in sections:
            if isinstance(sec, ast.ViewDecl):
                self._view(sec)
        for sec in sections:
            if isinstance(sec, ast.MorphismDecl):
                # a command's --timeout also bounds reading its model (with the grace of a phase
                # the answer needs: a query whose time is up still gives its UNKNOWN answer)
                limits.check_time("checking", finishing=True)
                self._morphism(sec)
        for sec in sections:
            if isinstance(sec, ast.HoleDecl):
                self._hole(sec)
        deployment = self._deployment([s for s in sections if isinstance(s, ast.DeploymentDecl)])
        self._within_limit(self.resources, "resources")
        self._within_limit(self.morphisms, "morphisms")
        if len(self.diags.errors) > before or self.failed:
            return None
        return ir.Domain(
            name=self.node.name.text,
            requirements=self.req.names | self._imported_requirements(),
            sorts=ir.frozen(self.sorts),
            constants=ir.frozen(self.constants),
            resources=ir.frozen(self.resources),
            morphisms=ir.frozen(self.morphisms),
            holes=ir.frozen(self.holes),
            views=ir.frozen(self.views),
            imports=tuple(self.imported),
            deployment=deployment,
            span=self.node.span,
        )

    def _within_limit(self, table: Mapping[str, ir.Resource] | Mapping[str, ir.Morphism], name: str) -> None:
        """E1104/E1105 at the first resource or morphism past its limit (imports included)."""
        limit = limits.BY_NAME[name]
        most = getattr(limits.current(), limit.field)
        if len(table) <= most:
            return
        first_past = list(table.values())[most]
        self.diags.report(
            limit.code,
            f"domain '{self.node.name.text}' has {limits.count_text(len(table))} {name} (imports included), more "
            f"than the {name} limit ({limits.count_text(most)}); {limit.how_to_raise}",
            first_past.span or self.node.span,
        )

    def _deployment(self, decls: list[ast.DeploymentDecl]) -> Deployment | None:
        """The domain's ``(:deployment ...)``: at most one."""
        for extra in decls[1:]:
            self.diags.report(
                codes.DUPLICATE_OPTION,
                "(:deployment ...) is given twice in one domain",
                extra.span,
                Note("first given here", decls[0].span),
            )
        if not decls:
            return None
        self.req.need(Requirement.GROUNDING, decls[0].span, "(:deployment ...)")
        return GroundChecker(self.diags, {}, self.resources, f"domain '{self.node.name.text}'").deployment(decls[0])

    def _imported_requirements(self) -> frozenset[str]:
        out: set[str] = set()
        for dom in self.imported_domains:
            out |= dom.requirements
        return frozenset(out)

    # ------------------------------------------------------------------ imports
    def _imports(self, sec: ast.Imports) -> None:
        for name in sec.names:
            dom = self.ws.domain_ir(name.text, self.path, name.span, importing=True)
            if dom is None:
                self.failed = True
                continue
            if name.text in self.imported:
                continue
            self.imported.append(name.text)
            self.imported_domains.append(dom)
            self._merge(dom, name)

    def _merge(self, dom: ir.Domain, via: ast.Name) -> None:
        self._merge_table(self.sorts, dom.sorts, "sort", dom, via)
        self._merge_table(self.constants, dom.constants, "constant", dom, via)
        self._merge_table(self.resources, dom.resources, "resource", dom, via)
        self._merge_table(self.morphisms, dom.morphisms, "morphism", dom, via)
        self._merge_table(self.holes, dom.holes, "hole", dom, via)
        self._merge_table(self.views, dom.views, "view", dom, via)

    def _merge_table(
        self, mine: dict[str, _V], theirs: Mapping[str, _V], what: str, dom: ir.Domain, via: ast.Name
    ) -> None:
        for key, value in theirs.items():
            if key in mine and mine[key] != value:
                self.diags.report(
                    codes.DUPLICATE_NAME,
                    f"{what} '{key}' from '{dom.name}' conflicts with another definition of it",
                    via.span,
                )
                continue
            mine[key] = value

    # ------------------------------------------------------------------ sorts
    def _sorts(self, sec: ast.Sorts) -> None:
        self.req.need(Requirement.SYMBOLS, sec.span, "declaring sorts")
        for group in sec.groups:
            parent = group.parent
            for name in group.names:
                if not self._declare(self.sorts, name, "sort"):
                    continue
                if isinstance(parent, ast.EnumSpec):
                    self._enum(name, parent)
                    continue
                parent_name = None
                if parent is not None and parent.text != "symbol":
                    parent_name = parent.text
                self.sorts[name.text] = Sort(SortKind.SYMBOL, name.text, parent=parent_name, span=name.span)
        # Resolve parents only now: a sort may name a parent declared later in the section.
        for group in sec.groups:
            parent = group.parent
            if not isinstance(parent, ast.Name) or parent.text == "symbol":
                continue
            if parent.text in ("bool", "int", "real", "set", "enum"):
                self.diags.report(
                    codes.BAD_SORT,
                    f"a symbolic sort's parent must be 'symbol' or another symbolic sort, not '{parent.text}'",
                    parent.span,
                )
            elif parent.text not in self.sorts:
                hint = Suggestion(parent.text, list(self.sorts) + ["symbol"], parent.span)
                self.diags.report(
                    codes.UNKNOWN_NAME, f"unknown sort '{parent.text}'{hint.hint}", parent.span, fixes=hint.fixes
                )
            elif self.sorts[parent.text].kind is SortKind.ENUM:
                self.diags.report(
                    codes.BAD_SORT, f"enumeration '{parent.text}' is closed and cannot have sub-sorts", parent.span
                )

    def _enum(self, name: ast.Name, spec: ast.EnumSpec) -> None:
        values: list[str] = []
        for v in spec.values:
            if v.text in values:
                self.diags.report(codes.DUPLICATE_NAME, f"enumeration value '{v.text}' is listed twice", v.span)
                continue
            if not self._declare(self.constants, v, "enumeration value") or self._value_name_taken(
                v, "enumeration value"
            ):
                continue
            values.append(v.text)
        if not values:
            self.diags.report(codes.BAD_SORT, f"enumeration '{name.text}' has no values", spec.span)
        sort = Sort(SortKind.ENUM, name.text, values=tuple(values), span=name.span)
        self.sorts[name.text] = sort
        for v in spec.values:
            if v.text in values and v.text not in self.constants:
                self.constants[v.text] = ir.Constant(v.text, sort, v.span)

    def _check_sort_cycles(self) -> None:
        for start in list(self.sorts):
            seen = [start]
            name = self.sorts[start].parent
            while name is not None and name in self.sorts:
                if name == start:
                    self.diags.report(
                        codes.BAD_SORT,
                        f"sort '{start}' is its own ancestor: {' - '.join(seen + [start])}",
                        self.sorts[start].span,
                    )
                    self.failed = True
                    break
                if name in seen:
                    break
                seen.append(name)
                name = self.sorts[name].parent

    def resolve_type(self, t: ast.TypeExpr, what: str, req: _Requirements) -> Sort | None:
        if isinstance(t, ast.SetType):
            req.need(Requirement.SETS, t.span, f"the set-valued {what}")
            elem = self._named_sort(t.element, req, what)
            if elem is None:
                return None
            if not elem.is_symbolic:
                self.diags.report(
                    codes.BAD_SORT, f"sets hold symbols; a set of '{elem.name}' is not supported", t.element.span
                )
                return None
            return ir.set_of(elem)
        return self._named_sort(t.name, req, what)

    def _named_sort(self, name: ast.Name, req: _Requirements, what: str) -> Sort | None:
        builtin = {"bool": BOOL, "int": INT, "real": REAL}.get(name.text)
        if builtin is not None:
            if builtin.is_numeric:
                req.need(Requirement.NUMERIC, name.span, f"the numeric {what}")
            return builtin
        if name.text in self.sorts:
            return self.sorts[name.text]
        if name.text in ("symbol", "set", "enum"):
            self.diags.report(
                codes.BAD_SORT, f"'{name.text}' is not a sort by itself; declare a sort in (:sorts ...)", name.span
            )
            return None
        hint = Suggestion(name.text, list(self.sorts) + ["bool", "int", "real"], name.span)
        self.diags.report(codes.UNKNOWN_NAME, f"unknown sort '{name.text}'{hint.hint}", name.span, fixes=hint.fixes)
        return None

    # ------------------------------------------------------------------ constants
    def _constants(self, sec: ast.Constants) -> None:
        self.req.need(Requirement.SYMBOLS, sec.span, "declaring constants")
        for group in sec.groups:
            sort = self._constant_sort(group)
            for name in group.names:
                if not self._declare(self.constants, name, "constant") or self._value_name_taken(name, "constant"):
                    continue
                if sort is not None:
                    self.constants[name.text] = ir.Constant(name.text, sort, name.span)

    def _constant_sort(self, group: ast.TypedGroup) -> Sort | None:
        if group.type is None:
            self.diags.report(
                codes.BAD_SORT,
                f"constant{'s' if len(group.names) > 1 else ''} "
                f"{', '.join(repr(n.text) for n in group.names)} need a sort: write '... - SORT'",
                group.span,
            )
            return None
        sort = self._named_sort(group.type, self.req, "constant")
        if sort is None:
            return None
        if sort.kind is SortKind.ENUM:
            self.diags.report(
                codes.CLOSED_SORT,
                f"enumeration '{sort.name}' is closed; its values are listed in its (enum ...) declaration",
                group.type.span,
            )
            return None
        if sort.kind is not SortKind.SYMBOL:
            self.diags.report(
                codes.BAD_SORT, f"constants must have a symbolic sort, not '{sort.name}'", group.type.span
            )
            return None
        return sort

    # ------------------------------------------------------------------ resources
    def _resource(self, r: ast.ResourceDecl) -> None:
        if not self._declare(self.resources, r.name, "resource") or self._value_name_taken(r.name, "resource"):
            return
        sort = self.resolve_type(r.type, f"resource '{r.name.text}'", self.req)
        opts = _options(r.options, RESOURCE_OPTIONS, f"resource '{r.name.text}'", self.diags)
        if sort is None:
            return
        if sort.is_symbolic:
            self.req.need(Requirement.SYMBOLS, r.type.span, f"the symbolic resource '{r.name.text}'")
        lo = hi = None
        if Option.BOUNDS.value in opts:
            lo, hi, _ = _bounds(
                _value(opts[Option.BOUNDS.value], ast.Bounds), sort, self.diags, f"resource '{r.name.text}'"
            )
        group = opts.get(Option.GROUP.value)
        unit = _declared_unit(opts.get(Option.UNIT.value), sort, f"resource '{r.name.text}'", self.diags)
        doc = opts.get(Option.DOC.value)
        self.resources[r.name.text] = ir.Resource(
            r.name.text,
            sort,
            group=_value(group, ast.Name).text if group else None,
            unit=unit,
            lower=lo,
            upper=hi,
            doc=_value(doc, ast.Name).text if doc else None,
            span=r.name.span,
        )

    # ------------------------------------------------------------------ views
    def _view(self, v: ast.ViewDecl) -> None:
        self.req.need(Requirement.VIEWS, v.span, f"view '{v.name.text}'")
        if not self._declare(self.views, v.name, "view"):
            return
        opts = _options(v.options, VIEW_OPTIONS, f"view '{v.name.text}'", self.diags)
        keep, drop = opts.get(Option.KEEP.value), opts.get(Option.DROP.value)
        if keep and drop:
            self.diags.report(codes.BAD_VIEW, f"view '{v.name.text}' gives both :keep and :drop; give one", drop.span)
            return
        listed: set[str] = set()
        chosen = keep or drop
        names: tuple[ast.Name, ...] = chosen.value if chosen else ()  # type: ignore[assignment]  # :keep/:drop list names
        for name in names:
            if name.text not in self.resources:
                hint = Suggestion(name.text, self.resources, name.span)
                self.diags.report(
                    codes.UNKNOWN_NAME, f"unknown resource '{name.text}'{hint.hint}", name.span, fixes=hint.fixes
                )
            listed.add(name.text)
        everything = frozenset(self.resources)
        kept = frozenset(listed) & everything if keep else everything - listed
        self.views[v.name.text] = ir.View(v.name.text, kept, everything - kept, v.name.span)

    # ------------------------------------------------------------------ morphisms
    def _morphism(self, m: ast.MorphismDecl) -> None:
        name = m.name.text
        if not self._declare(self.morphisms, m.name, "morphism"):
            return
        if name in self.holes:
            self.diags.report(codes.DUPLICATE_NAME, f"'{name}' names both a hole and a morphism", m.name.span)
            return
        owner = f"morphism '{name}'"
        opts = _options(m.options, MORPHISM_OPTIONS, owner, self.diags)
        kind = ir.MorphismKind.SOFTWARE
        if Option.KIND.value in opts:
            k = _value(opts[Option.KIND.value], ast.Name)
            if k.text in _KINDS:
                kind = _KINDS[k.text]
            else:
                hint = Suggestion(k.text, _KINDS, k.span)
                self.diags.report(
                    codes.BAD_VALUE,
                    f"unknown morphism kind '{k.text}'" + (hint.hint or f"; expected one of {', '.join(_KINDS)}"),
                    k.span,
                    fixes=hint.fixes,
                )
        churn = Fraction(1)
        if Option.CHURN.value in opts:
            self.req.need(Requirement.RECOMPOSITION, opts[Option.CHURN.value].span, ":churn")
            num = _value(opts[Option.CHURN.value], ast.Num)
            if num.value < 0:
                self.diags.report(codes.BAD_VALUE, f":churn must not be negative, got {num.text}", num.span)
            churn = num.value
        uses = None
        if Option.USES.value in opts:
            # :uses 0 switches a component off (it stays in the model, never activated)
            uses = _positive_int(_value(opts[Option.USES.value], ast.Num), ":uses", self.diags, allow_zero=True)

        params = self._params(m, opts.get(Option.PARAMETERS.value))
        scope = Scope(self.sorts, self.constants, self.resources, {p.name: p for p in params})
        checker = ExprChecker(scope, self.diags, self.req.need)
        pre = self._literals(checker, opts.get(Option.PRECONDITION.value), lambda i: ir.Label.pre(name, i))
        effects = self._effects(checker, opts.get(Option.EFFECT.value), name)
        cost = None
        if Option.COST.value in opts:
            node: ast.Expr = opts[Option.COST.value].value  # type: ignore[assignment]  # :cost is an expression
            cost = checker.numeric(node, Context.COST)
            if cost is not None:
                cost = self._cost_in_unit(checker, cost, node, name)
            folded = self._fold(cost) if cost is not None else None
            if isinstance(folded, ir.Const) and folded.value < 0:  # type: ignore[operator]
                self.diags.report(codes.BAD_VALUE, ":cost must not be negative", node.span)
        doc = opts.get(Option.DOC.value)
        grounding = None
        if Option.GROUND.value in opts:
            ground = opts[Option.GROUND.value]
            self.req.need(Requirement.GROUNDING, ground.span, "a grounding annotation")
            checker_g = GroundChecker(self.diags, {p.name: p for p in params}, self.resources, owner)
            grounding = checker_g.ground(_value(ground, ast.Ground), kind)
        self.morphisms[name] = ir.Morphism(
            name=name,
            kind=kind,
            params=tuple(params),
            pre=tuple(pre),
            effects=tuple(effects),
            churn=churn,
            uses=uses,
            cost=cost,
            doc=_value(doc, ast.Name).text if doc else None,
            grounding=grounding,
            span=m.name.span,
        )

    def _cost_in_unit(self, checker: ExprChecker, cost: ir.Expr, node: ast.Expr, morphism: str) -> ir.Expr | None:
        """(total-cost) adds the costs up: the first cost with a unit fixes it, a later one is
        converted to it (E0312 for another dimension)."""
        unit = checker.unit(cost)
        if unit is None:
            return cost
        if self.cost_unit is None:
            self.cost_unit = (unit, morphism)
            return cost
        first, owner = self.cost_unit
        unified = checker.unify(
            [cost],
            [node],
            codes.UNIT_MISMATCH_ARITH,
            lambda a, b: f"(total-cost) cannot add {b} to {a}",
            first,
            f"the cost of '{owner}'",
        )
        return unified[0][0] if unified is not None else None

    def _params(self, m: ast.MorphismDecl, opt: ast.Opt | None) -> list[ir.Param]:
        if opt is None:
            return []
        self.req.need(Requirement.FREE_PARAMETERS, opt.span, "free parameters")
        out: list[ir.Param] = []
        seen: dict[str, ir.Param] = {}
        decls: tuple[ast.ParameterDecl, ...] = opt.value  # type: ignore[assignment]  # :parameters lists them
        for p in decls:
            pname = p.name.text
            if pname in RESERVED_NAMES:
                self.diags.report(
                    codes.RESERVED_NAME, f"'{pname}' is a keyword and cannot name a parameter", p.name.span
                )
                continue
            if pname in seen:
                self.diags.report(
                    codes.DUPLICATE_NAME,
                    f"parameter '{pname}' is declared twice",
                    p.name.span,
                    Note("previously declared here", seen[pname].span),
                )
                continue
            clash = self.resources.get(pname) or self.constants.get(pname)
            if clash is not None:
                kind = "resource" if pname in self.resources else "constant"
                self.diags.report(
                    codes.SHADOWING,
                    f"parameter '{pname}' has the name of a {kind}; rename it so references are unambiguous",
                    p.name.span,
                    *([Note(f"the {kind} is declared here", clash.span)] if clash.span else []),
                )
                continue
            sort = self.resolve_type(p.type, f"parameter '{pname}'", self.req)
            popts = _options(p.options, PARAMETER_OPTIONS, f"parameter '{pname}'", self.diags)
            if sort is None:
                continue
            if sort.kind is SortKind.SET:
                self.diags.report(
                    codes.BAD_SORT,
                    "set-valued parameters are not supported; use a symbol parameter and 'add'",
                    p.type.span,
                )
                continue
            lo = hi = None
            bspan = None
            if Option.BOUNDS.value in popts:
                b = _value(popts[Option.BOUNDS.value], ast.Bounds)
                lo, hi, _ = _bounds(b, sort, self.diags, f"parameter '{pname}'")
                bspan = b.span
            unit = _declared_unit(popts.get(Option.UNIT.value), sort, f"parameter '{pname}'", self.diags)
            param = ir.Param(pname, sort, lo, hi, Option.FIXED.value in popts, p.name.span, bspan, unit)
            seen[pname] = param
            out.append(param)
        return out

    def _literals(
        self, checker: ExprChecker, opt: ast.Opt | None, label: Callable[[int], ir.Label]
    ) -> list[ir.Literal]:
        if opt is None:
            return []
        return split_literals(checker, opt.value, label, Context.CONDITION)  # type: ignore[arg-type]

    def _effects(self, checker: ExprChecker, opt: ast.Opt | None, morphism: str) -> list[ir.Effect]:
        if opt is None:
            return []
        out: list[ir.Effect] = []
        stack: list[ast.Expr] = [opt.value]  # type: ignore[list-item]
        flat: list[ast.Expr] = []
        while stack:
            node = stack.pop()
            if isinstance(node, ast.Call) and node.head.text == "and":
                stack.extend(reversed(node.args))
            else:
                flat.append(node)
        for i, node in enumerate(flat, 1):
            eff = self._effect(checker, node, ir.Label.eff(morphism, i))
            if eff is not None:
                out.append(eff)
        _check_effect_conflicts(out, self.diags)
        return out

    _EFFECT_HEADS = ("assign", "increase", "decrease", "add", "remove")

    def _effect(self, checker: ExprChecker, node: ast.Expr, label: ir.Label) -> ir.Effect | None:
        """One effect literal: ``(op resource value)``, checked for the resource's sort."""
        if not isinstance(node, ast.Call) or node.head.text not in self._EFFECT_HEADS:
            self._not_an_effect(node)
            return None
        merged = checker.merge_quantities(node.args)
        if merged is not node.args:
            node = ast.Call(node.head, merged, node.span)
        if not checker._arity(node, 2, 2):
            return None
        target_node, value_node = node.args
        res = self._effect_target(checker, node.head.text, target_node)
        if res is None:
            return None
        kind = ir.EffectKind(node.head.text)
        value = self._effect_value(checker, kind, res, target_node, value_node)
        if value is None:
            return None
        return ir.Effect(kind, res.name, value, label, node.span)

    def _not_an_effect(self, node: ast.Expr) -> None:
        fixes: tuple[Fix, ...] = ()
        if isinstance(node, ast.Call):
            head = node.head.text
            suggestion = Suggestion(head, (*self._EFFECT_HEADS, "and"), node.head.span)
            fixes = suggestion.fixes
            msg = (
                f"'{head}' is not an effect{suggestion.hint}"
                if suggestion.hint
                else (
                    f"'{head}' is not an effect; effects are (and ...), (assign r v), (increase r v), "
                    f"(decrease r v), (add s x) and (remove s x)"
                )
            )
        else:
            msg = "an effect must be (assign r v), (increase r v), (decrease r v), (add s x) or (remove s x)"
        self.diags.report(codes.MISPLACED_OPERATOR, msg, node.span, fixes=fixes)

    def _effect_target(self, checker: ExprChecker, head: str, target_node: ast.Expr) -> ir.Resource | None:
        """The resource an effect writes, or None after reporting what the target is instead."""
        if isinstance(target_node, ast.Ref) and target_node.name in self.resources:
            return self.resources[target_node.name]
        what = "this"
        if isinstance(target_node, ast.Ref):
            if target_node.name in checker.scope.params:
                what = f"parameter '{target_node.name}'"
            elif target_node.name in self.constants:
                what = f"constant '{target_node.name}'"
            else:
                hint = Suggestion(target_node.name, self.resources, target_node.span)
                self.diags.report(
                    codes.UNKNOWN_NAME,
                    f"unknown resource '{target_node.name}'{hint.hint}",
                    target_node.span,
                    fixes=hint.fixes,
                )
                return None
        self.diags.report(codes.NOT_ASSIGNABLE, f"'{head}' writes a resource; {what} is not one", target_node.span)
        return None

    def _effect_value(
        self,
        checker: ExprChecker,
        kind: ir.EffectKind,
        res: ir.Resource,
        target_node: ast.Expr,
        value_node: ast.Expr,
    ) -> ir.Expr | None:
        """The effect's value, of a sort the effect can write to ``res``."""
        head = kind.value
        if kind in (ir.EffectKind.ADD, ir.EffectKind.REMOVE):
            if res.sort.kind is not SortKind.SET:
                self.diags.report(
                    codes.NOT_A_SET,
                    f"'{head}' needs a set resource, but '{res.name}' is {describe(res.sort)}",
                    target_node.span,
                )
                return None
            want = res.sort.element
            mismatch = f"cannot {head} {{value}} {'to' if head == 'add' else 'from'} '{res.name}', {describe(res.sort)}"
            value = checker.term(value_node, Context.TERM)
        elif kind in (ir.EffectKind.INCREASE, ir.EffectKind.DECREASE):
            if not res.sort.is_numeric:
                self.diags.report(
                    codes.TYPE_MISMATCH,
                    f"'{head}' needs a numeric resource, but '{res.name}' is {describe(res.sort)}",
                    target_node.span,
                )
                return None
            want = res.sort
            mismatch = f"cannot {head} '{res.name}', {describe(res.sort)}, by {{value}}"
            value = checker.term(value_node, Context.TERM)
        else:
            want = res.sort
            mismatch = f"cannot assign {{value}} to '{res.name}', {describe(res.sort)}"
            value = checker.term(value_node, Context.TERM, res.sort)
        if value is None:
            return None
        if not assignable(want, value.sort, self.sorts):  # type: ignore[arg-type]
            self.diags.report(codes.TYPE_MISMATCH, mismatch.format(value=describe(value.sort)), value_node.span)
            return None
        if res.sort.is_numeric and value.sort.is_numeric:
            verb = {
                ir.EffectKind.ASSIGN: lambda a, b: f"cannot assign {b} to {a}",
                ir.EffectKind.INCREASE: lambda a, b: f"cannot increase {a} by {b}",
                ir.EffectKind.DECREASE: lambda a, b: f"cannot decrease {a} by {b}",
            }[kind]
            unified = checker.unify(
                [value],
                [value_node],
                codes.UNIT_MISMATCH_EFFECT,
                verb,
                checker.scope.unit_of(res.name),
                res.name,
            )
            if unified is None:
                return None
            value = unified[0][0]
            _unitless_target(checker, res, value, value_node, self.diags)
            if not assignable(want, value.sort, self.sorts):  # type: ignore[arg-type]  # converted to a non-integer
                self.diags.report(codes.TYPE_MISMATCH, mismatch.format(value=describe(value.sort)), value_node.span)
                return None
        return value

    # ------------------------------------------------------------------ holes
    def _hole(self, h: ast.HoleDecl) -> None:
        self.req.need(Requirement.HOLES, h.span, f"hole '{h.name.text}'")
        if not self._declare(self.holes, h.name, "hole"):
            return
        if h.name.text in self.morphisms:
            self.diags.report(codes.DUPLICATE_NAME, f"'{h.name.text}' names both a hole and a morphism", h.name.span)
            return
        opts = _options(h.options, HOLE_OPTIONS, f"hole '{h.name.text}'", self.diags)
        view = None
        if Option.HOLE_VIEW.value in opts:
            vname = _value(opts[Option.HOLE_VIEW.value], ast.Name)
            if vname.text not in self.views:
                hint = Suggestion(vname.text, self.views, vname.span)
                self.diags.report(
                    codes.UNKNOWN_NAME, f"unknown view '{vname.text}'{hint.hint}", vname.span, fixes=hint.fixes
                )
            view = vname.text
        max_eff = max_pre = None
        if Option.MAX_EFFECTS.value in opts:
            max_eff = _positive_int(_value(opts[Option.MAX_EFFECTS.value], ast.Num), ":max-effects", self.diags)
        if Option.MAX_PRECONDITIONS.value in opts:
            max_pre = _positive_int(
                _value(opts[Option.MAX_PRECONDITIONS.value], ast.Num),
                ":max-preconditions",
                self.diags,
                allow_zero=True,
            )
        self.holes[h.name.text] = ir.Hole(h.name.text, view, max_eff, max_pre, h.name.span)


def split_literals(
    checker: ExprChecker, node: ast.Expr, label: Callable[[int], ir.Label], ctx: Context
) -> list[ir.Literal]:
    """Split a top-level conjunction into literals labelled ``label(1)``, ``label(2)``, ..."""
    flat: list[ast.Expr] = []
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, ast.Call) and n.head.text == "and":
            stack.extend(reversed(n.args))
        else:
            flat.append(n)
    out = []
    for i, n in enumerate(flat, 1):
        e = checker.condition(n, ctx)
        if e is not None:
            out.append(ir.Literal(e, label(i), n.span))
    return out


def _check_effect_conflicts(effects: list[ir.Effect], diags: Diagnostics) -> None:
    by_res: dict[str, list[ir.Effect]] = {}
    for e in effects:
        by_res.setdefault(e.resource, []).append(e)
    for res, effs in by_res.items():
        assigns = [e for e in effs if e.kind is ir.EffectKind.ASSIGN]
        if assigns and len(effs) > 1:
            other = next(e for e in effs if e is not assigns[0])
            diags.report(
                codes.CONFLICTING_EFFECTS,
                f"'{res}' is written twice in one effect: an assign cannot be combined with another write",
                other.span,
                Note("the assign is here", assigns[0].span),
            )
            continue
        adds = {_elem_key(e.value): e for e in effs if e.kind is ir.EffectKind.ADD}
        for e in effs:
            if e.kind is ir.EffectKind.REMOVE and _elem_key(e.value) in adds:
                diags.report(
                    codes.CONFLICTING_EFFECTS,
                    f"the same element is both added to and removed from '{res}' in one effect",
                    e.span,
                    Note("the add is here", adds[_elem_key(e.value)].span),
                )


def _elem_key(expr: ir.Expr) -> tuple:
    """What identifies an added or removed element: a constant, a parameter, else the node."""
    match expr:
        case ir.Const():
            return ("c", expr.value)
        case ir.ParamRef():
            return ("p", expr.name)
        case _:
            return ("x", id(expr))


def _declared_unit(opt: ast.Opt | None, sort: Sort, what: str, diags: Diagnostics) -> str | None:
    """The text of a ``:unit`` option, checked: a unit of the registry (E0314) on a number
    (E0315).  Only a model that declares a unit imports pint."""
    if opt is None:
        return None
    name = _value(opt, ast.Name)
    if not sort.is_numeric:
        diags.report(codes.UNIT_ON_NON_NUMBER, f"{what} is {describe(sort)}; only numbers have units", opt.span)
        return None
    from catc.frontend import units

    try:
        units.parse(name.text)
    except units.UnitError as exc:
        hint = Suggestion(name.text, units.COMMON, name.span)
        diags.report(codes.UNKNOWN_UNIT, f"{exc}{hint.hint}", name.span, fixes=hint.fixes)
        return None
    return name.text
