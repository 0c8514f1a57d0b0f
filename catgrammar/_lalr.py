"""The LALR(1) parser of .cat files, without Lark at run time.

The tables between the ``# BEGIN/END GENERATED TABLES`` lines near the end of this file
are GENERATED from ``catgrammar/cat.lark`` by the real Lark (its grammar compiler and LALR
analysis, with ``strict=True``)::

    python -m catgrammar.build_parser           # after any change to cat.lark
    python -m catgrammar.build_parser --check   # exit status 1 when the tables are stale

Never edit the tables by hand; ``tests/test_generated_parser.py`` fails when they do not
match what ``build_parser`` produces from the current ``cat.lark``.  The rest of the file —
:class:`Token`, the exceptions and the driver :class:`Parser` — is ordinary code: it reads
the tables and builds each rule's value exactly as Lark's tree builder would with the
same ``transformer`` (``maybe_placeholders=False``, no ``keep_all_tokens``), so that
importing the parser costs about a millisecond instead of Lark's 40 ms:

* terminals starting with ``_`` are dropped from a rule's children;
* rules starting with ``_`` (including Lark's ``__rule_star_N`` helpers) are inlined: their
  children are spliced into the parent's;
* every other rule calls ``getattr(builder, alias or rule name)(children)``;
* a ``?rule`` alternative without an alias returns its only child unchanged.

Why not ``python -m lark.tools.standalone``?  Its output takes 30–60 ms to import (it
carries the whole of Lark's runtime and deserializes the grammar at load time), so it
would not save anything; and that generated code is under the MPL 2.0, not Lark's MIT
license.
"""

from __future__ import annotations

from sys import intern
from typing import Any, Callable, Iterable

__all__ = [
    "Parser",
    "Token",
    "UnexpectedCharacters",
    "UnexpectedEOF",
    "UnexpectedInput",
    "UnexpectedToken",
]


class Token:
    """One terminal: its type (``NAME``, ``LPAR``, ``MORPHISM_KW``, ...), text and position.

    The attribute names are Lark's; ``str(token)`` is the matched text.  Lines and columns
    are 1-based, ``end_column`` is exclusive, ``start_pos``/``end_pos`` are offsets."""

    __slots__ = ("type", "value", "start_pos", "line", "column", "end_line", "end_column", "end_pos")

    def __init__(
        self,
        type: str,  # noqa: A002 - Lark's name
        value: str,
        start_pos: int | None = None,
        line: int | None = None,
        column: int | None = None,
        end_line: int | None = None,
        end_column: int | None = None,
        end_pos: int | None = None,
    ) -> None:
        self.type = type
        self.value = value
        self.start_pos = start_pos
        self.line = line
        self.column = column
        self.end_line = end_line
        self.end_column = end_column
        self.end_pos = end_pos

    def __str__(self) -> str:
        return self.value

    def __repr__(self) -> str:
        return f"Token({self.type!r}, {self.value!r})"


class UnexpectedInput(Exception):
    """Base of the syntax errors (Lark's names and attributes)."""

    pos_in_stream: int | None = None
    line: int | None = None
    column: int | None = None


class UnexpectedCharacters(UnexpectedInput):
    """The tokenizer found text that starts no token."""

    def __init__(self, seq: str, lex_pos: int, line: int, column: int, allowed: set[str] | None = None) -> None:
        self.seq = seq
        self.pos_in_stream = lex_pos
        self.line = line
        self.column = column
        self.allowed = allowed
        self.char = seq[lex_pos] if 0 <= lex_pos < len(seq) else ""
        super().__init__(f"No terminal matches {self.char!r} at line {line} col {column}")


class UnexpectedToken(UnexpectedInput):
    """The parser cannot shift ``token`` (type ``$END`` at the end of the input).

    ``expected`` holds the terminals the parser could have shifted in that state."""

    def __init__(self, token: Token, expected: set[str], state: int | None = None) -> None:
        self.token = token
        self.expected = expected
        self.state = state
        self.pos_in_stream = token.start_pos
        self.line = token.line
        self.column = token.column
        super().__init__(
            f"Unexpected token {token!r} at line {token.line}, column {token.column}; "
            f"expected one of {sorted(expected)}"
        )


class UnexpectedEOF(UnexpectedInput):
    """Kept for interface compatibility: an LALR parser reports the end of the input as an
    :class:`UnexpectedToken` of type ``$END``, so this is never raised here."""

    def __init__(self, expected: set[str]) -> None:
        self.expected = expected
        super().__init__(f"Unexpected end of input; expected one of {sorted(expected)}")


END = "$END"


def _reducer(origin: str, pattern: str, alias: str | None, expand1: bool, kind: type) -> Callable[[Any, list], Any]:
    """The function that turns a rule's children (a fresh list) into the rule's value, called
    as ``reduce(builder, children)`` with a builder of class ``kind``.

    ``pattern`` has one letter per symbol of the rule: ``k`` keep, ``d`` drop (a filtered
    ``_TERMINAL``), ``s`` splice (the value of an inlined ``_rule``, itself a list)."""
    ops = tuple((i, c == "s") for i, c in enumerate(pattern) if c != "d")
    filt: Callable[[list], list] | None
    if len(ops) == len(pattern) and not any(splice for _, splice in ops):
        filt = None  # keep every child as it is
    elif pattern == "sk":  # ``__x_star: __x_star item`` — grow the list in place

        def grow(children: list) -> list:
            first = children[0]
            first.append(children[1])
            return first

        filt = grow
    else:
        first_i, first_splice = ops[0] if ops else (0, False)
        rest = ops[1:] if first_splice else ops

        def gather(children: list) -> list:
            out = children[first_i] if first_splice else []
            for i, splice in rest:
                if splice:
                    out += children[i]
                else:
                    out.append(children[i])
            return out

        filt = gather

    if origin.startswith("_"):  # inlined: the value is the list of children
        if filt is None:
            return lambda builder, children: children
        only = filt
        return lambda builder, children: only(children)
    name = alias or origin
    try:
        fn = getattr(kind, name)  # the function behind the builder's method
    except AttributeError:
        raise TypeError(f"{kind.__name__} has no callback {name!r} for rule {origin!r}") from None
    if expand1 and not alias:
        if filt is None:
            return lambda builder, children: children[0] if len(children) == 1 else fn(builder, children)

        def single(builder: Any, children: list) -> Any:
            children = filt(children)
            return children[0] if len(children) == 1 else fn(builder, children)

        return single
    if filt is None:
        return fn
    return lambda builder, children: fn(builder, filt(children))


#: The rules' reducers for each builder class, made once (a parse then costs no set-up:
#: a domain that imports six others is parsed seven times in one process).
_REDUCERS: dict[type, tuple[tuple[int, str, Callable[[Any, list], Any]], ...]] = {}


def _reducers(kind: type) -> tuple[tuple[int, str, Callable[[Any, list], Any]], ...]:
    found = _REDUCERS.get(kind)
    if found is None:
        found = tuple(
            (size, origin, _reducer(origin, pattern, alias, expand1, kind))
            for origin, size, pattern, alias, expand1 in RULES
        )
        _REDUCERS[kind] = found
    return found


class Parser:
    """The LALR(1) driver over the generated tables, building values with ``builder``.

    ``builder`` has one method per rule (or alias) name taking the list of children
    (tokens and values) and returning the value — Lark's ``Transformer`` convention.  The
    methods are looked up on the builder's class, once per class."""

    def __init__(self, builder: Any) -> None:
        self.builder = builder
        self._rules = _reducers(type(builder))

    @staticmethod
    def expected(state: int) -> set[str]:
        """The terminals that can be shifted (or reduced on) in ``state``."""
        return {symbol for symbol in STATES[state] if symbol.isupper()}

    def parse(self, tokens: Iterable[Token]) -> Any:
        """Run the automaton over ``tokens``; return the start rule's value.

        Raises :class:`UnexpectedToken`; exceptions raised by ``tokens`` (such as
        :class:`UnexpectedCharacters`) propagate unchanged."""
        states = STATES
        rules = self._rules
        builder = self.builder
        state = START_STATE
        row = states[state]
        stack = [state]
        values: list = []
        push_state, push_value = stack.append, values.append
        token = None
        for token in tokens:
            kind = token.type
            while True:
                try:
                    action = row[kind]
                except KeyError:
                    raise UnexpectedToken(token, self.expected(state), state) from None
                if action >= 0:  # shift
                    push_state(action)
                    push_value(token)
                    state = action
                    row = states[action]
                    break
                size, origin, reduce = rules[~action]
                if size:
                    children = values[-size:]
                    del values[-size:]
                    del stack[-size:]
                else:
                    children = []
                push_value(reduce(builder, children))
                state = states[stack[-1]][origin]
                push_state(state)
                row = states[state]
        if token is None:
            end = Token(END, "", 0, 1, 1, 1, 1, 0)
        else:  # positioned like the last token, as Lark does
            end = Token(END, "", token.start_pos, token.line, token.column, token.end_line, token.end_column, token.end_pos)
        while True:
            try:
                action = row[END]
            except KeyError:
                raise UnexpectedToken(end, self.expected(state), state) from None
            if action >= 0:  # pragma: no cover - the tables never shift $END
                raise AssertionError(f"the tables shift {END} in state {state}")
            size, origin, reduce = rules[~action]
            if size:
                children = values[-size:]
                del values[-size:]
                del stack[-size:]
            else:
                children = []
            push_value(reduce(builder, children))
            state = states[stack[-1]][origin]
            if state == END_STATE:
                return values[-1]
            push_state(state)
            row = states[state]


# BEGIN GENERATED TABLES
# Generated by `python -m catgrammar.build_parser` from catgrammar/cat.lark; do not edit.
GRAMMAR_SHA256 = "f428336bca695fb552f3492d37e2a9d8dd72de6c30aa5cd4bdb5ddb0e2a25816"

#: One rule per line (line i is rule i): origin, number of symbols, children pattern
#: (one letter per symbol: k keep, d drop, s splice; - when empty), alias (- for none),
#: 1 for an alternative of a ?rule, else 0; then the rule itself, for the reader.
_RULES = """\
start 1 s - 0  start: __start_star_0
start 0 - - 0  start: <empty>
_definition 1 k - 0  _definition: domain
_definition 1 k - 0  _definition: problem
domain 8 kdkdkksk - 0  domain: LPAR _DEFINE_WORD LPAR _DOMAIN_WORD NAME RPAR __domain_star_1 RPAR
domain 7 kdkdkkk - 0  domain: LPAR _DEFINE_WORD LPAR _DOMAIN_WORD NAME RPAR RPAR
_domain_section 1 k - 0  _domain_section: requirements
_domain_section 1 k - 0  _domain_section: imports
_domain_section 1 k - 0  _domain_section: sorts
_domain_section 1 k - 0  _domain_section: constants
_domain_section 1 k - 0  _domain_section: resources
_domain_section 1 k - 0  _domain_section: morphism
_domain_section 1 k - 0  _domain_section: hole
_domain_section 1 k - 0  _domain_section: view_decl
_domain_section 1 k - 0  _domain_section: deployment
requirements 4 kksk - 0  requirements: LPAR REQUIREMENTS_KW __requirements_star_2 RPAR
requirements 3 kkk - 0  requirements: LPAR REQUIREMENTS_KW RPAR
imports 4 kksk - 0  imports: LPAR IMPORT_KW __imports_star_3 RPAR
imports 3 kkk - 0  imports: LPAR IMPORT_KW RPAR
sorts 5 kkskk - 0  sorts: LPAR SORTS_KW __sorts_star_4 name_list RPAR
sorts 4 kksk - 0  sorts: LPAR SORTS_KW __sorts_star_4 RPAR
sorts 4 kkkk - 0  sorts: LPAR SORTS_KW name_list RPAR
sorts 3 kkk - 0  sorts: LPAR SORTS_KW RPAR
sort_group 3 kks - 0  sort_group: name_list MINUS _sort_parent
_sort_parent 1 k - 0  _sort_parent: NAME
_sort_parent 1 k - 0  _sort_parent: enum_spec
enum_spec 4 kdsk - 0  enum_spec: LPAR _ENUM_WORD __imports_star_3 RPAR
enum_spec 3 kdk - 0  enum_spec: LPAR _ENUM_WORD RPAR
constants 4 kkkk - 0  constants: LPAR CONSTANTS_KW typed_names RPAR
typed_names 2 sk - 0  typed_names: __typed_names_star_5 name_list
typed_names 1 s - 0  typed_names: __typed_names_star_5
typed_names 1 k - 0  typed_names: name_list
typed_names 0 - - 0  typed_names: <empty>
typed_group 3 kkk - 0  typed_group: name_list MINUS NAME
name_list 1 s - 0  name_list: __imports_star_3
resources 4 kksk - 0  resources: LPAR RESOURCES_KW __resources_star_6 RPAR
resources 3 kkk - 0  resources: LPAR RESOURCES_KW RPAR
resource 5 kkssk - 0  resource: LPAR NAME _type __resource_star_7 RPAR
resource 4 kksk - 0  resource: LPAR NAME _type RPAR
resource_option 2 kk group 1  resource_option: GROUP_KW NAME -> group
resource_option 2 kk unit 1  resource_option: UNIT_KW NAME -> unit
resource_option 2 kk unit 1  resource_option: UNIT_KW STRING -> unit
resource_option 2 kk bounds_option 1  resource_option: BOUNDS_KW bounds -> bounds_option
resource_option 2 kk doc 1  resource_option: DOC_KW STRING -> doc
_type 1 k - 0  _type: NAME
_type 1 k - 0  _type: set_type
set_type 4 kdkk - 0  set_type: LPAR _SET_WORD NAME RPAR
bounds 4 kkkk - 0  bounds: LPAR bound bound RPAR
bound 1 k - 0  bound: NUMBER
bound 1 k - 0  bound: STAR
morphism 5 kkksk - 0  morphism: LPAR MORPHISM_KW NAME __morphism_star_8 RPAR
morphism 4 kkkk - 0  morphism: LPAR MORPHISM_KW NAME RPAR
morphism_option 2 kk kind 1  morphism_option: KIND_KW NAME -> kind
morphism_option 2 kk churn 1  morphism_option: CHURN_KW NUMBER -> churn
morphism_option 2 kk uses 1  morphism_option: USES_KW NUMBER -> uses
morphism_option 2 kk cost 1  morphism_option: COST_KW expr -> cost
morphism_option 4 kksk parameters 1  morphism_option: PARAMETERS_KW LPAR __morphism_option_star_9 RPAR -> parameters
morphism_option 3 kkk parameters 1  morphism_option: PARAMETERS_KW LPAR RPAR -> parameters
morphism_option 2 kk precondition 1  morphism_option: PRECONDITION_KW expr -> precondition
morphism_option 2 kk effect 1  morphism_option: EFFECT_KW expr -> effect
morphism_option 2 kk doc 1  morphism_option: DOC_KW STRING -> doc
morphism_option 2 kk ground_option 1  morphism_option: GROUND_KW ground -> ground_option
parameter 5 kkssk - 0  parameter: LPAR NAME _type __parameter_star_10 RPAR
parameter 4 kksk - 0  parameter: LPAR NAME _type RPAR
parameter_option 2 kk bounds_option 1  parameter_option: BOUNDS_KW bounds -> bounds_option
parameter_option 1 k fixed 1  parameter_option: FIXED_KW -> fixed
parameter_option 2 kk unit 1  parameter_option: UNIT_KW NAME -> unit
parameter_option 2 kk unit 1  parameter_option: UNIT_KW STRING -> unit
ground 4 kksk - 0  ground: LPAR NAME __ground_star_11 RPAR
ground 3 kkk - 0  ground: LPAR NAME RPAR
ground_pair 2 sk - 0  ground_pair: _grounding_key datum
_grounding_key 1 k - 0  _grounding_key: INSTRUCTION_KW
_grounding_key 1 k - 0  _grounding_key: CHECK_KW
_grounding_key 1 k - 0  _grounding_key: PARTS_KW
_grounding_key 1 k - 0  _grounding_key: IMAGE_KW
_grounding_key 1 k - 0  _grounding_key: NODE_KW
_grounding_key 1 k - 0  _grounding_key: PROFILE_KW
_grounding_key 1 k - 0  _grounding_key: PARAMS_KW
_grounding_key 1 k - 0  _grounding_key: REMAP_KW
_grounding_key 1 k - 0  _grounding_key: ID_KW
_grounding_key 1 k - 0  _grounding_key: INPUTS_KW
_grounding_key 1 k - 0  _grounding_key: OUTPUTS_KW
_grounding_key 1 k - 0  _grounding_key: PROJECT_KW
_grounding_key 1 k - 0  _grounding_key: EXECUTOR_KW
_grounding_key 1 k - 0  _grounding_key: FLAG
datum 1 k datum_name 1  datum: NAME -> datum_name
datum 1 k datum_number 1  datum: NUMBER -> datum_number
datum 1 k datum_string 1  datum: STRING -> datum_string
datum 1 k true 1  datum: TRUE -> true
datum 1 k false 1  datum: FALSE -> false
datum 3 ksk datum_list 1  datum: LPAR __datum_star_12 RPAR -> datum_list
datum 2 kk datum_list 1  datum: LPAR RPAR -> datum_list
deployment 4 kksk - 0  deployment: LPAR DEPLOYMENT_KW __ground_star_11 RPAR
deployment 3 kkk - 0  deployment: LPAR DEPLOYMENT_KW RPAR
hole 5 kkksk - 0  hole: LPAR HOLE_KW NAME __hole_star_13 RPAR
hole 4 kkkk - 0  hole: LPAR HOLE_KW NAME RPAR
hole_option 2 kk hole_view 1  hole_option: VIEW_KW NAME -> hole_view
hole_option 2 kk max_effects 1  hole_option: MAX_EFFECTS_KW NUMBER -> max_effects
hole_option 2 kk max_preconditions 1  hole_option: MAX_PRECONDITIONS_KW NUMBER -> max_preconditions
view_decl 5 kkksk - 0  view_decl: LPAR VIEW_KW NAME __view_decl_star_14 RPAR
view_decl 4 kkkk - 0  view_decl: LPAR VIEW_KW NAME RPAR
view_option 4 kksk keep 1  view_option: KEEP_KW LPAR __imports_star_3 RPAR -> keep
view_option 3 kkk keep 1  view_option: KEEP_KW LPAR RPAR -> keep
view_option 4 kksk drop 1  view_option: DROP_KW LPAR __imports_star_3 RPAR -> drop
view_option 3 kkk drop 1  view_option: DROP_KW LPAR RPAR -> drop
problem 8 kdkdkksk - 0  problem: LPAR _DEFINE_WORD LPAR _PROBLEM_WORD NAME RPAR __problem_star_15 RPAR
problem 7 kdkdkkk - 0  problem: LPAR _DEFINE_WORD LPAR _PROBLEM_WORD NAME RPAR RPAR
_problem_section 1 k - 0  _problem_section: domain_ref
_problem_section 1 k - 0  _problem_section: requirements
_problem_section 1 k - 0  _problem_section: objects
_problem_section 1 k - 0  _problem_section: init
_problem_section 1 k - 0  _problem_section: goal
_problem_section 1 k - 0  _problem_section: horizon
_problem_section 1 k - 0  _problem_section: soft
_problem_section 1 k - 0  _problem_section: metric
_problem_section 1 k - 0  _problem_section: deployed
_problem_section 1 k - 0  _problem_section: view_use
domain_ref 4 kkkk - 0  domain_ref: LPAR DOMAIN_KW NAME RPAR
objects 4 kkkk - 0  objects: LPAR OBJECTS_KW typed_names RPAR
init 4 kksk - 0  init: LPAR INIT_KW __init_star_16 RPAR
init 3 kkk - 0  init: LPAR INIT_KW RPAR
goal 4 kkkk - 0  goal: LPAR GOAL_KW expr RPAR
horizon 4 kkkk - 0  horizon: LPAR HORIZON_KW NUMBER RPAR
soft 5 kkksk - 0  soft: LPAR SOFT_KW expr __soft_star_17 RPAR
soft 4 kkkk - 0  soft: LPAR SOFT_KW expr RPAR
soft_option 2 kk weight 1  soft_option: WEIGHT_KW NUMBER -> weight
metric 4 kkkk - 0  metric: LPAR METRIC_KW metric_body RPAR
metric_body 1 k single 1  metric_body: objective_body -> single
metric_body 2 ds lex 1  metric_body: _LEX_WORD __metric_body_plus_18 -> lex
metric_body 2 ds pareto 1  metric_body: _PARETO_WORD __metric_body_plus_18 -> pareto
objective 3 kkk - 0  objective: LPAR objective_body RPAR
objective_body 2 kk - 0  objective_body: SENSE expr
deployed 4 kksk - 0  deployed: LPAR DEPLOYED_KW __imports_star_3 RPAR
deployed 3 kkk - 0  deployed: LPAR DEPLOYED_KW RPAR
view_use 4 kkkk - 0  view_use: LPAR VIEW_KW NAME RPAR
expr 1 k ref 1  expr: NAME -> ref
expr 1 k number 1  expr: NUMBER -> number
expr 1 k true 1  expr: TRUE -> true
expr 1 k false 1  expr: FALSE -> false
expr 3 ksk set_literal 1  expr: LBRACE __init_star_16 RBRACE -> set_literal
expr 2 kk set_literal 1  expr: LBRACE RBRACE -> set_literal
expr 4 kksk call 1  expr: LPAR NAME __init_star_16 RPAR -> call
expr 3 kkk call 1  expr: LPAR NAME RPAR -> call
expr 4 kksk call 1  expr: LPAR OPSYM __init_star_16 RPAR -> call
expr 3 kkk call 1  expr: LPAR OPSYM RPAR -> call
expr 4 kksk call 1  expr: LPAR MINUS __init_star_16 RPAR -> call
expr 3 kkk call 1  expr: LPAR MINUS RPAR -> call
expr 4 kksk call 1  expr: LPAR STAR __init_star_16 RPAR -> call
expr 3 kkk call 1  expr: LPAR STAR RPAR -> call
__start_star_0 1 s - 0  __start_star_0: _definition
__start_star_0 2 ss - 0  __start_star_0: __start_star_0 _definition
__domain_star_1 1 s - 0  __domain_star_1: _domain_section
__domain_star_1 2 ss - 0  __domain_star_1: __domain_star_1 _domain_section
__requirements_star_2 1 k - 0  __requirements_star_2: FLAG
__requirements_star_2 2 sk - 0  __requirements_star_2: __requirements_star_2 FLAG
__imports_star_3 1 k - 0  __imports_star_3: NAME
__imports_star_3 2 sk - 0  __imports_star_3: __imports_star_3 NAME
__sorts_star_4 1 k - 0  __sorts_star_4: sort_group
__sorts_star_4 2 sk - 0  __sorts_star_4: __sorts_star_4 sort_group
__typed_names_star_5 1 k - 0  __typed_names_star_5: typed_group
__typed_names_star_5 2 sk - 0  __typed_names_star_5: __typed_names_star_5 typed_group
__resources_star_6 1 k - 0  __resources_star_6: resource
__resources_star_6 2 sk - 0  __resources_star_6: __resources_star_6 resource
__resource_star_7 1 k - 0  __resource_star_7: resource_option
__resource_star_7 2 sk - 0  __resource_star_7: __resource_star_7 resource_option
__morphism_star_8 1 k - 0  __morphism_star_8: morphism_option
__morphism_star_8 2 sk - 0  __morphism_star_8: __morphism_star_8 morphism_option
__morphism_option_star_9 1 k - 0  __morphism_option_star_9: parameter
__morphism_option_star_9 2 sk - 0  __morphism_option_star_9: __morphism_option_star_9 parameter
__parameter_star_10 1 k - 0  __parameter_star_10: parameter_option
__parameter_star_10 2 sk - 0  __parameter_star_10: __parameter_star_10 parameter_option
__ground_star_11 1 k - 0  __ground_star_11: ground_pair
__ground_star_11 2 sk - 0  __ground_star_11: __ground_star_11 ground_pair
__datum_star_12 1 k - 0  __datum_star_12: datum
__datum_star_12 2 sk - 0  __datum_star_12: __datum_star_12 datum
__hole_star_13 1 k - 0  __hole_star_13: hole_option
__hole_star_13 2 sk - 0  __hole_star_13: __hole_star_13 hole_option
__view_decl_star_14 1 k - 0  __view_decl_star_14: view_option
__view_decl_star_14 2 sk - 0  __view_decl_star_14: __view_decl_star_14 view_option
__problem_star_15 1 s - 0  __problem_star_15: _problem_section
__problem_star_15 2 ss - 0  __problem_star_15: __problem_star_15 _problem_section
__init_star_16 1 k - 0  __init_star_16: expr
__init_star_16 2 sk - 0  __init_star_16: __init_star_16 expr
__soft_star_17 1 k - 0  __soft_star_17: soft_option
__soft_star_17 2 sk - 0  __soft_star_17: __soft_star_17 soft_option
__metric_body_plus_18 1 k - 0  __metric_body_plus_18: objective
__metric_body_plus_18 2 sk - 0  __metric_body_plus_18: __metric_body_plus_18 objective
"""

START_STATE = 0
END_STATE = 6

#: One state per line (line i is state i): pairs of symbol and action; an action >= 0
#: shifts (or, after a reduction, goes) to that state, an action < 0 reduces by rule ~action.
_STATES = """\
$END -2 LPAR 1 __start_star_0 2 _definition 3 domain 4 problem 5 start 6
_DEFINE_WORD 7
$END -1 LPAR 1 _definition 8 domain 4 problem 5
$END -150 LPAR -150
$END -3 LPAR -3
$END -4 LPAR -4

LPAR 9
$END -151 LPAR -151
_DOMAIN_WORD 10 _PROBLEM_WORD 11
NAME 12
NAME 13
RPAR 14
RPAR 15
LPAR 16 RPAR 17 __domain_star_1 18 _domain_section 19 constants 20 deployment 21 hole 22 imports 23 morphism 24 requirements 25 resources 26 sorts 27 view_decl 28
LPAR 29 RPAR 30 __problem_star_15 31 _problem_section 32 deployed 33 domain_ref 34 goal 35 horizon 36 init 37 metric 38 objects 39 requirements 40 soft 41 view_use 42
CONSTANTS_KW 43 DEPLOYMENT_KW 44 HOLE_KW 45 IMPORT_KW 46 MORPHISM_KW 47 REQUIREMENTS_KW 48 RESOURCES_KW 49 SORTS_KW 50 VIEW_KW 51
$END -6 LPAR -6
LPAR 16 RPAR 52 _domain_section 53 constants 20 deployment 21 hole 22 imports 23 morphism 24 requirements 25 resources 26 sorts 27 view_decl 28
LPAR -152 RPAR -152
LPAR -10 RPAR -10
LPAR -15 RPAR -15
LPAR -13 RPAR -13
LPAR -8 RPAR -8
LPAR -12 RPAR -12
LPAR -7 RPAR -7
LPAR -11 RPAR -11
LPAR -9 RPAR -9
LPAR -14 RPAR -14
DEPLOYED_KW 54 DOMAIN_KW 55 GOAL_KW 56 HORIZON_KW 57 INIT_KW 58 METRIC_KW 59 OBJECTS_KW 60 REQUIREMENTS_KW 48 SOFT_KW 61 VIEW_KW 62
$END -107 LPAR -107
LPAR 29 RPAR 63 _problem_section 64 deployed 33 domain_ref 34 goal 35 horizon 36 init 37 metric 38 objects 39 requirements 40 soft 41 view_use 42
LPAR -180 RPAR -180
LPAR -116 RPAR -116
LPAR -108 RPAR -108
LPAR -112 RPAR -112
LPAR -113 RPAR -113
LPAR -111 RPAR -111
LPAR -115 RPAR -115
LPAR -110 RPAR -110
LPAR -109 RPAR -109
LPAR -114 RPAR -114
LPAR -117 RPAR -117
NAME 65 RPAR -33 __imports_star_3 66 __typed_names_star_5 67 name_list 68 typed_group 69 typed_names 70
CHECK_KW 71 EXECUTOR_KW 72 FLAG 73 ID_KW 74 IMAGE_KW 75 INPUTS_KW 76 INSTRUCTION_KW 77 NODE_KW 78 OUTPUTS_KW 79 PARAMS_KW 80 PARTS_KW 81 PROFILE_KW 82 PROJECT_KW 83 REMAP_KW 84 RPAR 85 __ground_star_11 86 _grounding_key 87 ground_pair 88
NAME 89
NAME 65 RPAR 90 __imports_star_3 91
NAME 92
FLAG 93 RPAR 94 __requirements_star_2 95
LPAR 96 RPAR 97 __resources_star_6 98 resource 99
NAME 65 RPAR 100 __imports_star_3 66 __sorts_star_4 101 name_list 102 sort_group 103
NAME 104
$END -5 LPAR -5
LPAR -153 RPAR -153
NAME 65 RPAR 105 __imports_star_3 106
NAME 107
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 TRUE 113 expr 114
NUMBER 115
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 116 TRUE 113 __init_star_16 117 expr 118
SENSE 119 _LEX_WORD 120 _PARETO_WORD 121 metric_body 122 objective_body 123
NAME 65 RPAR -33 __imports_star_3 66 __typed_names_star_5 67 name_list 68 typed_group 69 typed_names 124
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 TRUE 113 expr 125
NAME 126
$END -106 LPAR -106
LPAR -181 RPAR -181
MINUS -156 NAME -156 RPAR -156
MINUS -35 NAME 127 RPAR -35
NAME 65 RPAR -31 __imports_star_3 66 name_list 128 typed_group 129
MINUS 130 RPAR -32
NAME -160 RPAR -160
RPAR 131
FALSE -73 LPAR -73 NAME -73 NUMBER -73 STRING -73 TRUE -73
FALSE -84 LPAR -84 NAME -84 NUMBER -84 STRING -84 TRUE -84
FALSE -85 LPAR -85 NAME -85 NUMBER -85 STRING -85 TRUE -85
FALSE -80 LPAR -80 NAME -80 NUMBER -80 STRING -80 TRUE -80
FALSE -75 LPAR -75 NAME -75 NUMBER -75 STRING -75 TRUE -75
FALSE -81 LPAR -81 NAME -81 NUMBER -81 STRING -81 TRUE -81
FALSE -72 LPAR -72 NAME -72 NUMBER -72 STRING -72 TRUE -72
FALSE -76 LPAR -76 NAME -76 NUMBER -76 STRING -76 TRUE -76
FALSE -82 LPAR -82 NAME -82 NUMBER -82 STRING -82 TRUE -82
FALSE -78 LPAR -78 NAME -78 NUMBER -78 STRING -78 TRUE -78
FALSE -74 LPAR -74 NAME -74 NUMBER -74 STRING -74 TRUE -74
FALSE -77 LPAR -77 NAME -77 NUMBER -77 STRING -77 TRUE -77
FALSE -83 LPAR -83 NAME -83 NUMBER -83 STRING -83 TRUE -83
FALSE -79 LPAR -79 NAME -79 NUMBER -79 STRING -79 TRUE -79
LPAR -94 RPAR -94
CHECK_KW 71 EXECUTOR_KW 72 FLAG 73 ID_KW 74 IMAGE_KW 75 INPUTS_KW 76 INSTRUCTION_KW 77 NODE_KW 78 OUTPUTS_KW 79 PARAMS_KW 80 PARTS_KW 81 PROFILE_KW 82 PROJECT_KW 83 REMAP_KW 84 RPAR 132 _grounding_key 87 ground_pair 133
FALSE 134 LPAR 135 NAME 136 NUMBER 137 STRING 138 TRUE 139 datum 140
CHECK_KW -172 EXECUTOR_KW -172 FLAG -172 ID_KW -172 IMAGE_KW -172 INPUTS_KW -172 INSTRUCTION_KW -172 NODE_KW -172 OUTPUTS_KW -172 PARAMS_KW -172 PARTS_KW -172 PROFILE_KW -172 PROJECT_KW -172 REMAP_KW -172 RPAR -172
MAX_EFFECTS_KW 141 MAX_PRECONDITIONS_KW 142 RPAR 143 VIEW_KW 144 __hole_star_13 145 hole_option 146
LPAR -19 RPAR -19
NAME 127 RPAR 147
CHURN_KW 148 COST_KW 149 DOC_KW 150 EFFECT_KW 151 GROUND_KW 152 KIND_KW 153 PARAMETERS_KW 154 PRECONDITION_KW 155 RPAR 156 USES_KW 157 __morphism_star_8 158 morphism_option 159
FLAG -154 RPAR -154
LPAR -17 RPAR -17
FLAG 160 RPAR 161
NAME 162
LPAR -37 RPAR -37
LPAR 96 RPAR 163 resource 164
LPAR -162 RPAR -162
LPAR -23 RPAR -23
NAME 65 RPAR 165 __imports_star_3 66 name_list 166 sort_group 167
MINUS 168 RPAR 169
NAME -158 RPAR -158
DROP_KW 170 KEEP_KW 171 RPAR 172 __view_decl_star_14 173 view_option 174
LPAR -134 RPAR -134
NAME 127 RPAR 175
RPAR 176
CHURN_KW -139 COST_KW -139 DOC_KW -139 EFFECT_KW -139 FALSE -139 GROUND_KW -139 KIND_KW -139 LBRACE -139 LPAR -139 NAME -139 NUMBER -139 PARAMETERS_KW -139 PRECONDITION_KW -139 RBRACE -139 RPAR -139 TRUE -139 USES_KW -139 WEIGHT_KW -139
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RBRACE 177 TRUE 113 __init_star_16 178 expr 118
MINUS 179 NAME 180 OPSYM 181 STAR 182
CHURN_KW -136 COST_KW -136 DOC_KW -136 EFFECT_KW -136 FALSE -136 GROUND_KW -136 KIND_KW -136 LBRACE -136 LPAR -136 NAME -136 NUMBER -136 PARAMETERS_KW -136 PRECONDITION_KW -136 RBRACE -136 RPAR -136 TRUE -136 USES_KW -136 WEIGHT_KW -136
CHURN_KW -137 COST_KW -137 DOC_KW -137 EFFECT_KW -137 FALSE -137 GROUND_KW -137 KIND_KW -137 LBRACE -137 LPAR -137 NAME -137 NUMBER -137 PARAMETERS_KW -137 PRECONDITION_KW -137 RBRACE -137 RPAR -137 TRUE -137 USES_KW -137 WEIGHT_KW -137
CHURN_KW -138 COST_KW -138 DOC_KW -138 EFFECT_KW -138 FALSE -138 GROUND_KW -138 KIND_KW -138 LBRACE -138 LPAR -138 NAME -138 NUMBER -138 PARAMETERS_KW -138 PRECONDITION_KW -138 RBRACE -138 RPAR -138 TRUE -138 USES_KW -138 WEIGHT_KW -138
RPAR 183
RPAR 184
LPAR -121 RPAR -121
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 185 TRUE 113 expr 186
FALSE -182 LBRACE -182 LPAR -182 NAME -182 NUMBER -182 RBRACE -182 RPAR -182 TRUE -182
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 TRUE 113 expr 187
LPAR 188 __metric_body_plus_18 189 objective 190
LPAR 188 __metric_body_plus_18 191 objective 190
RPAR 192
RPAR -128
RPAR 193
RPAR 194 WEIGHT_KW 195 __soft_star_17 196 soft_option 197
RPAR 198
MINUS -157 NAME -157 RPAR -157
MINUS 130 RPAR -30
NAME -161 RPAR -161
NAME 199
LPAR -29 RPAR -29
LPAR -93 RPAR -93
CHECK_KW -173 EXECUTOR_KW -173 FLAG -173 ID_KW -173 IMAGE_KW -173 INPUTS_KW -173 INSTRUCTION_KW -173 NODE_KW -173 OUTPUTS_KW -173 PARAMS_KW -173 PARTS_KW -173 PROFILE_KW -173 PROJECT_KW -173 REMAP_KW -173 RPAR -173
CHECK_KW -90 EXECUTOR_KW -90 FALSE -90 FLAG -90 ID_KW -90 IMAGE_KW -90 INPUTS_KW -90 INSTRUCTION_KW -90 LPAR -90 NAME -90 NODE_KW -90 NUMBER -90 OUTPUTS_KW -90 PARAMS_KW -90 PARTS_KW -90 PROFILE_KW -90 PROJECT_KW -90 REMAP_KW -90 RPAR -90 STRING -90 TRUE -90
FALSE 134 LPAR 135 NAME 136 NUMBER 137 RPAR 200 STRING 138 TRUE 139 __datum_star_12 201 datum 202
CHECK_KW -86 EXECUTOR_KW -86 FALSE -86 FLAG -86 ID_KW -86 IMAGE_KW -86 INPUTS_KW -86 INSTRUCTION_KW -86 LPAR -86 NAME -86 NODE_KW -86 NUMBER -86 OUTPUTS_KW -86 PARAMS_KW -86 PARTS_KW -86 PROFILE_KW -86 PROJECT_KW -86 REMAP_KW -86 RPAR -86 STRING -86 TRUE -86
CHECK_KW -87 EXECUTOR_KW -87 FALSE -87 FLAG -87 ID_KW -87 IMAGE_KW -87 INPUTS_KW -87 INSTRUCTION_KW -87 LPAR -87 NAME -87 NODE_KW -87 NUMBER -87 OUTPUTS_KW -87 PARAMS_KW -87 PARTS_KW -87 PROFILE_KW -87 PROJECT_KW -87 REMAP_KW -87 RPAR -87 STRING -87 TRUE -87
CHECK_KW -88 EXECUTOR_KW -88 FALSE -88 FLAG -88 ID_KW -88 IMAGE_KW -88 INPUTS_KW -88 INSTRUCTION_KW -88 LPAR -88 NAME -88 NODE_KW -88 NUMBER -88 OUTPUTS_KW -88 PARAMS_KW -88 PARTS_KW -88 PROFILE_KW -88 PROJECT_KW -88 REMAP_KW -88 RPAR -88 STRING -88 TRUE -88
CHECK_KW -89 EXECUTOR_KW -89 FALSE -89 FLAG -89 ID_KW -89 IMAGE_KW -89 INPUTS_KW -89 INSTRUCTION_KW -89 LPAR -89 NAME -89 NODE_KW -89 NUMBER -89 OUTPUTS_KW -89 PARAMS_KW -89 PARTS_KW -89 PROFILE_KW -89 PROJECT_KW -89 REMAP_KW -89 RPAR -89 STRING -89 TRUE -89
CHECK_KW -71 EXECUTOR_KW -71 FLAG -71 ID_KW -71 IMAGE_KW -71 INPUTS_KW -71 INSTRUCTION_KW -71 NODE_KW -71 OUTPUTS_KW -71 PARAMS_KW -71 PARTS_KW -71 PROFILE_KW -71 PROJECT_KW -71 REMAP_KW -71 RPAR -71
NUMBER 203
NUMBER 204
LPAR -96 RPAR -96
NAME 205
MAX_EFFECTS_KW 141 MAX_PRECONDITIONS_KW 142 RPAR 206 VIEW_KW 144 hole_option 207
MAX_EFFECTS_KW -176 MAX_PRECONDITIONS_KW -176 RPAR -176 VIEW_KW -176
LPAR -18 RPAR -18
NUMBER 208
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 TRUE 113 expr 209
STRING 210
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 TRUE 113 expr 211
LPAR 212 ground 213
NAME 214
LPAR 215
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 TRUE 113 expr 216
LPAR -52 RPAR -52
NUMBER 217
CHURN_KW 148 COST_KW 149 DOC_KW 150 EFFECT_KW 151 GROUND_KW 152 KIND_KW 153 PARAMETERS_KW 154 PRECONDITION_KW 155 RPAR 218 USES_KW 157 morphism_option 219
CHURN_KW -166 COST_KW -166 DOC_KW -166 EFFECT_KW -166 GROUND_KW -166 KIND_KW -166 PARAMETERS_KW -166 PRECONDITION_KW -166 RPAR -166 USES_KW -166
FLAG -155 RPAR -155
LPAR -16 RPAR -16
LPAR 220 NAME 221 _type 222 set_type 223
LPAR -36 RPAR -36
LPAR -163 RPAR -163
LPAR -21 RPAR -21
MINUS 168 RPAR 224
NAME -159 RPAR -159
LPAR 225 NAME 226 _sort_parent 227 enum_spec 228
LPAR -22 RPAR -22
LPAR 229
LPAR 230
LPAR -101 RPAR -101
DROP_KW 170 KEEP_KW 171 RPAR 231 view_option 232
DROP_KW -178 KEEP_KW -178 RPAR -178
LPAR -133 RPAR -133
LPAR -118 RPAR -118
CHURN_KW -141 COST_KW -141 DOC_KW -141 EFFECT_KW -141 FALSE -141 GROUND_KW -141 KIND_KW -141 LBRACE -141 LPAR -141 NAME -141 NUMBER -141 PARAMETERS_KW -141 PRECONDITION_KW -141 RBRACE -141 RPAR -141 TRUE -141 USES_KW -141 WEIGHT_KW -141
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RBRACE 233 TRUE 113 expr 186
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 234 TRUE 113 __init_star_16 235 expr 118
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 236 TRUE 113 __init_star_16 237 expr 118
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 238 TRUE 113 __init_star_16 239 expr 118
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 240 TRUE 113 __init_star_16 241 expr 118
LPAR -122 RPAR -122
LPAR -123 RPAR -123
LPAR -120 RPAR -120
FALSE -183 LBRACE -183 LPAR -183 NAME -183 NUMBER -183 RBRACE -183 RPAR -183 TRUE -183
RPAR -132
SENSE 119 objective_body 242
LPAR 188 RPAR -129 objective 243
LPAR -186 RPAR -186
LPAR 188 RPAR -130 objective 243
LPAR -127 RPAR -127
LPAR -119 RPAR -119
LPAR -125 RPAR -125
NUMBER 244
RPAR 245 WEIGHT_KW 195 soft_option 246
RPAR -184 WEIGHT_KW -184
LPAR -135 RPAR -135
NAME -34 RPAR -34
CHECK_KW -92 EXECUTOR_KW -92 FALSE -92 FLAG -92 ID_KW -92 IMAGE_KW -92 INPUTS_KW -92 INSTRUCTION_KW -92 LPAR -92 NAME -92 NODE_KW -92 NUMBER -92 OUTPUTS_KW -92 PARAMS_KW -92 PARTS_KW -92 PROFILE_KW -92 PROJECT_KW -92 REMAP_KW -92 RPAR -92 STRING -92 TRUE -92
FALSE 134 LPAR 135 NAME 136 NUMBER 137 RPAR 247 STRING 138 TRUE 139 datum 248
FALSE -174 LPAR -174 NAME -174 NUMBER -174 RPAR -174 STRING -174 TRUE -174
MAX_EFFECTS_KW -98 MAX_PRECONDITIONS_KW -98 RPAR -98 VIEW_KW -98
MAX_EFFECTS_KW -99 MAX_PRECONDITIONS_KW -99 RPAR -99 VIEW_KW -99
MAX_EFFECTS_KW -97 MAX_PRECONDITIONS_KW -97 RPAR -97 VIEW_KW -97
LPAR -95 RPAR -95
MAX_EFFECTS_KW -177 MAX_PRECONDITIONS_KW -177 RPAR -177 VIEW_KW -177
CHURN_KW -54 COST_KW -54 DOC_KW -54 EFFECT_KW -54 GROUND_KW -54 KIND_KW -54 PARAMETERS_KW -54 PRECONDITION_KW -54 RPAR -54 USES_KW -54
CHURN_KW -56 COST_KW -56 DOC_KW -56 EFFECT_KW -56 GROUND_KW -56 KIND_KW -56 PARAMETERS_KW -56 PRECONDITION_KW -56 RPAR -56 USES_KW -56
CHURN_KW -61 COST_KW -61 DOC_KW -61 EFFECT_KW -61 GROUND_KW -61 KIND_KW -61 PARAMETERS_KW -61 PRECONDITION_KW -61 RPAR -61 USES_KW -61
CHURN_KW -60 COST_KW -60 DOC_KW -60 EFFECT_KW -60 GROUND_KW -60 KIND_KW -60 PARAMETERS_KW -60 PRECONDITION_KW -60 RPAR -60 USES_KW -60
NAME 249
CHURN_KW -62 COST_KW -62 DOC_KW -62 EFFECT_KW -62 GROUND_KW -62 KIND_KW -62 PARAMETERS_KW -62 PRECONDITION_KW -62 RPAR -62 USES_KW -62
CHURN_KW -53 COST_KW -53 DOC_KW -53 EFFECT_KW -53 GROUND_KW -53 KIND_KW -53 PARAMETERS_KW -53 PRECONDITION_KW -53 RPAR -53 USES_KW -53
LPAR 250 RPAR 251 __morphism_option_star_9 252 parameter 253
CHURN_KW -59 COST_KW -59 DOC_KW -59 EFFECT_KW -59 GROUND_KW -59 KIND_KW -59 PARAMETERS_KW -59 PRECONDITION_KW -59 RPAR -59 USES_KW -59
CHURN_KW -55 COST_KW -55 DOC_KW -55 EFFECT_KW -55 GROUND_KW -55 KIND_KW -55 PARAMETERS_KW -55 PRECONDITION_KW -55 RPAR -55 USES_KW -55
LPAR -51 RPAR -51
CHURN_KW -167 COST_KW -167 DOC_KW -167 EFFECT_KW -167 GROUND_KW -167 KIND_KW -167 PARAMETERS_KW -167 PRECONDITION_KW -167 RPAR -167 USES_KW -167
_SET_WORD 254
BOUNDS_KW -45 DOC_KW -45 FIXED_KW -45 GROUP_KW -45 RPAR -45 UNIT_KW -45
BOUNDS_KW 255 DOC_KW 256 GROUP_KW 257 RPAR 258 UNIT_KW 259 __resource_star_7 260 resource_option 261
BOUNDS_KW -46 DOC_KW -46 FIXED_KW -46 GROUP_KW -46 RPAR -46 UNIT_KW -46
LPAR -20 RPAR -20
_ENUM_WORD 262
NAME -25 RPAR -25
NAME -24 RPAR -24
NAME -26 RPAR -26
NAME 65 RPAR 263 __imports_star_3 264
NAME 65 RPAR 265 __imports_star_3 266
LPAR -100 RPAR -100
DROP_KW -179 KEEP_KW -179 RPAR -179
CHURN_KW -140 COST_KW -140 DOC_KW -140 EFFECT_KW -140 FALSE -140 GROUND_KW -140 KIND_KW -140 LBRACE -140 LPAR -140 NAME -140 NUMBER -140 PARAMETERS_KW -140 PRECONDITION_KW -140 RBRACE -140 RPAR -140 TRUE -140 USES_KW -140 WEIGHT_KW -140
CHURN_KW -147 COST_KW -147 DOC_KW -147 EFFECT_KW -147 FALSE -147 GROUND_KW -147 KIND_KW -147 LBRACE -147 LPAR -147 NAME -147 NUMBER -147 PARAMETERS_KW -147 PRECONDITION_KW -147 RBRACE -147 RPAR -147 TRUE -147 USES_KW -147 WEIGHT_KW -147
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 267 TRUE 113 expr 186
CHURN_KW -143 COST_KW -143 DOC_KW -143 EFFECT_KW -143 FALSE -143 GROUND_KW -143 KIND_KW -143 LBRACE -143 LPAR -143 NAME -143 NUMBER -143 PARAMETERS_KW -143 PRECONDITION_KW -143 RBRACE -143 RPAR -143 TRUE -143 USES_KW -143 WEIGHT_KW -143
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 268 TRUE 113 expr 186
CHURN_KW -145 COST_KW -145 DOC_KW -145 EFFECT_KW -145 FALSE -145 GROUND_KW -145 KIND_KW -145 LBRACE -145 LPAR -145 NAME -145 NUMBER -145 PARAMETERS_KW -145 PRECONDITION_KW -145 RBRACE -145 RPAR -145 TRUE -145 USES_KW -145 WEIGHT_KW -145
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 269 TRUE 113 expr 186
CHURN_KW -149 COST_KW -149 DOC_KW -149 EFFECT_KW -149 FALSE -149 GROUND_KW -149 KIND_KW -149 LBRACE -149 LPAR -149 NAME -149 NUMBER -149 PARAMETERS_KW -149 PRECONDITION_KW -149 RBRACE -149 RPAR -149 TRUE -149 USES_KW -149 WEIGHT_KW -149
FALSE 108 LBRACE 109 LPAR 110 NAME 111 NUMBER 112 RPAR 270 TRUE 113 expr 186
RPAR 271
LPAR -187 RPAR -187
RPAR -126 WEIGHT_KW -126
LPAR -124 RPAR -124
RPAR -185 WEIGHT_KW -185
CHECK_KW -91 EXECUTOR_KW -91 FALSE -91 FLAG -91 ID_KW -91 IMAGE_KW -91 INPUTS_KW -91 INSTRUCTION_KW -91 LPAR -91 NAME -91 NODE_KW -91 NUMBER -91 OUTPUTS_KW -91 PARAMS_KW -91 PARTS_KW -91 PROFILE_KW -91 PROJECT_KW -91 REMAP_KW -91 RPAR -91 STRING -91 TRUE -91
FALSE -175 LPAR -175 NAME -175 NUMBER -175 RPAR -175 STRING -175 TRUE -175
CHECK_KW 71 EXECUTOR_KW 72 FLAG 73 ID_KW 74 IMAGE_KW 75 INPUTS_KW 76 INSTRUCTION_KW 77 NODE_KW 78 OUTPUTS_KW 79 PARAMS_KW 80 PARTS_KW 81 PROFILE_KW 82 PROJECT_KW 83 REMAP_KW 84 RPAR 272 __ground_star_11 273 _grounding_key 87 ground_pair 88
NAME 274
CHURN_KW -58 COST_KW -58 DOC_KW -58 EFFECT_KW -58 GROUND_KW -58 KIND_KW -58 PARAMETERS_KW -58 PRECONDITION_KW -58 RPAR -58 USES_KW -58
LPAR 250 RPAR 275 parameter 276
LPAR -168 RPAR -168
NAME 277
LPAR 278 bounds 279
STRING 280
NAME 281
LPAR -39 RPAR -39
NAME 282 STRING 283
BOUNDS_KW 255 DOC_KW 256 GROUP_KW 257 RPAR 284 UNIT_KW 259 resource_option 285
BOUNDS_KW -164 DOC_KW -164 GROUP_KW -164 RPAR -164 UNIT_KW -164
NAME 65 RPAR 286 __imports_star_3 287
DROP_KW -105 KEEP_KW -105 RPAR -105
NAME 127 RPAR 288
DROP_KW -103 KEEP_KW -103 RPAR -103
NAME 127 RPAR 289
CHURN_KW -146 COST_KW -146 DOC_KW -146 EFFECT_KW -146 FALSE -146 GROUND_KW -146 KIND_KW -146 LBRACE -146 LPAR -146 NAME -146 NUMBER -146 PARAMETERS_KW -146 PRECONDITION_KW -146 RBRACE -146 RPAR -146 TRUE -146 USES_KW -146 WEIGHT_KW -146
CHURN_KW -142 COST_KW -142 DOC_KW -142 EFFECT_KW -142 FALSE -142 GROUND_KW -142 KIND_KW -142 LBRACE -142 LPAR -142 NAME -142 NUMBER -142 PARAMETERS_KW -142 PRECONDITION_KW -142 RBRACE -142 RPAR -142 TRUE -142 USES_KW -142 WEIGHT_KW -142
CHURN_KW -144 COST_KW -144 DOC_KW -144 EFFECT_KW -144 FALSE -144 GROUND_KW -144 KIND_KW -144 LBRACE -144 LPAR -144 NAME -144 NUMBER -144 PARAMETERS_KW -144 PRECONDITION_KW -144 RBRACE -144 RPAR -144 TRUE -144 USES_KW -144 WEIGHT_KW -144
CHURN_KW -148 COST_KW -148 DOC_KW -148 EFFECT_KW -148 FALSE -148 GROUND_KW -148 KIND_KW -148 LBRACE -148 LPAR -148 NAME -148 NUMBER -148 PARAMETERS_KW -148 PRECONDITION_KW -148 RBRACE -148 RPAR -148 TRUE -148 USES_KW -148 WEIGHT_KW -148
LPAR -131 RPAR -131
CHURN_KW -70 COST_KW -70 DOC_KW -70 EFFECT_KW -70 GROUND_KW -70 KIND_KW -70 PARAMETERS_KW -70 PRECONDITION_KW -70 RPAR -70 USES_KW -70
CHECK_KW 71 EXECUTOR_KW 72 FLAG 73 ID_KW 74 IMAGE_KW 75 INPUTS_KW 76 INSTRUCTION_KW 77 NODE_KW 78 OUTPUTS_KW 79 PARAMS_KW 80 PARTS_KW 81 PROFILE_KW 82 PROJECT_KW 83 REMAP_KW 84 RPAR 290 _grounding_key 87 ground_pair 133
LPAR 220 NAME 221 _type 291 set_type 223
CHURN_KW -57 COST_KW -57 DOC_KW -57 EFFECT_KW -57 GROUND_KW -57 KIND_KW -57 PARAMETERS_KW -57 PRECONDITION_KW -57 RPAR -57 USES_KW -57
LPAR -169 RPAR -169
RPAR 292
NUMBER 293 STAR 294 bound 295
BOUNDS_KW -43 DOC_KW -43 GROUP_KW -43 RPAR -43 UNIT_KW -43
BOUNDS_KW -44 DOC_KW -44 GROUP_KW -44 RPAR -44 UNIT_KW -44
BOUNDS_KW -40 DOC_KW -40 GROUP_KW -40 RPAR -40 UNIT_KW -40
BOUNDS_KW -41 DOC_KW -41 GROUP_KW -41 RPAR -41 UNIT_KW -41
BOUNDS_KW -42 DOC_KW -42 GROUP_KW -42 RPAR -42 UNIT_KW -42
LPAR -38 RPAR -38
BOUNDS_KW -165 DOC_KW -165 GROUP_KW -165 RPAR -165 UNIT_KW -165
NAME -28 RPAR -28
NAME 127 RPAR 296
DROP_KW -104 KEEP_KW -104 RPAR -104
DROP_KW -102 KEEP_KW -102 RPAR -102
CHURN_KW -69 COST_KW -69 DOC_KW -69 EFFECT_KW -69 GROUND_KW -69 KIND_KW -69 PARAMETERS_KW -69 PRECONDITION_KW -69 RPAR -69 USES_KW -69
BOUNDS_KW 297 FIXED_KW 298 RPAR 299 UNIT_KW 300 __parameter_star_10 301 parameter_option 302
BOUNDS_KW -47 DOC_KW -47 FIXED_KW -47 GROUP_KW -47 RPAR -47 UNIT_KW -47
NUMBER -49 RPAR -49 STAR -49
NUMBER -50 RPAR -50 STAR -50
NUMBER 293 STAR 294 bound 303
NAME -27 RPAR -27
LPAR 278 bounds 304
BOUNDS_KW -66 FIXED_KW -66 RPAR -66 UNIT_KW -66
LPAR -64 RPAR -64
NAME 305 STRING 306
BOUNDS_KW 297 FIXED_KW 298 RPAR 307 UNIT_KW 300 parameter_option 308
BOUNDS_KW -170 FIXED_KW -170 RPAR -170 UNIT_KW -170
RPAR 309
BOUNDS_KW -65 FIXED_KW -65 RPAR -65 UNIT_KW -65
BOUNDS_KW -67 FIXED_KW -67 RPAR -67 UNIT_KW -67
BOUNDS_KW -68 FIXED_KW -68 RPAR -68 UNIT_KW -68
LPAR -63 RPAR -63
BOUNDS_KW -171 FIXED_KW -171 RPAR -171 UNIT_KW -171
BOUNDS_KW -48 DOC_KW -48 FIXED_KW -48 GROUP_KW -48 RPAR -48 UNIT_KW -48
"""
# END GENERATED TABLES


def _decode_rules(text: str) -> tuple[tuple[str, int, str, str | None, bool], ...]:
    rules = []
    for line in text.splitlines():
        origin, size, pattern, alias, expand1 = line.split(None, 5)[:5]
        rules.append((origin, int(size), "" if pattern == "-" else pattern, None if alias == "-" else alias, expand1 == "1"))
    return tuple(rules)


def _decode_states(text: str) -> tuple[dict[str, int], ...]:
    states = []
    for line in text.splitlines():
        parts = line.split()
        states.append(dict(zip(map(intern, parts[0::2]), map(int, parts[1::2]))))
    return tuple(states)


#: ``(origin, number of symbols, children pattern, alias, ?rule)`` per rule.
RULES = _decode_rules(_RULES)
#: ``STATES[state][symbol]``: a state to shift/go to (>= 0), or ``~rule`` to reduce by (< 0).
STATES = _decode_states(_STATES)
