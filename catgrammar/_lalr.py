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


def _reducer(origin: str, pattern: str, alias: str | None, expand1: bool, builder: Any) -> Callable[[list], Any]:
    """The function that turns a rule's children (a fresh list) into the rule's value.

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
        return filt or (lambda children: children)
    name = alias or origin
    try:
        fn = getattr(builder, name)
    except AttributeError:
        raise TypeError(f"{type(builder).__name__} has no callback {name!r} for rule {origin!r}") from None
    if expand1 and not alias:
        if filt is None:
            return lambda children: children[0] if len(children) == 1 else fn(children)

        def single(children: list) -> Any:
            children = filt(children)
            return children[0] if len(children) == 1 else fn(children)

        return single
    if filt is None:
        return fn
    return lambda children: fn(filt(children))


class Parser:
    """The LALR(1) driver over the generated tables, building values with ``builder``.

    ``builder`` has one method per rule (or alias) name taking the list of children
    (tokens and values) and returning the value — Lark's ``Transformer`` convention."""

    def __init__(self, builder: Any) -> None:
        self.builder = builder
        self._rules = tuple(
            (size, origin, _reducer(origin, pattern, alias, expand1, builder))
            for origin, size, pattern, alias, expand1 in RULES
        )

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
                push_value(reduce(children))
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
            push_value(reduce(children))
            state = states[stack[-1]][origin]
            if state == END_STATE:
                return values[-1]
            push_state(state)
            row = states[state]


# BEGIN GENERATED TABLES
# Generated by `python -m catgrammar.build_parser` from catgrammar/cat.lark; do not edit.
GRAMMAR_SHA256 = "7791d2538f7243cfdb2275ab642d11157e90bf1cc21298fceb75e8d3e4de854d"

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
parameter 5 kkssk - 0  parameter: LPAR NAME _type __parameter_star_10 RPAR
parameter 4 kksk - 0  parameter: LPAR NAME _type RPAR
parameter_option 2 kk bounds_option 1  parameter_option: BOUNDS_KW bounds -> bounds_option
parameter_option 1 k fixed 1  parameter_option: FIXED_KW -> fixed
hole 5 kkksk - 0  hole: LPAR HOLE_KW NAME __hole_star_11 RPAR
hole 4 kkkk - 0  hole: LPAR HOLE_KW NAME RPAR
hole_option 2 kk hole_view 1  hole_option: VIEW_KW NAME -> hole_view
hole_option 2 kk max_effects 1  hole_option: MAX_EFFECTS_KW NUMBER -> max_effects
hole_option 2 kk max_preconditions 1  hole_option: MAX_PRECONDITIONS_KW NUMBER -> max_preconditions
view_decl 5 kkksk - 0  view_decl: LPAR VIEW_KW NAME __view_decl_star_12 RPAR
view_decl 4 kkkk - 0  view_decl: LPAR VIEW_KW NAME RPAR
view_option 4 kksk keep 1  view_option: KEEP_KW LPAR __imports_star_3 RPAR -> keep
view_option 3 kkk keep 1  view_option: KEEP_KW LPAR RPAR -> keep
view_option 4 kksk drop 1  view_option: DROP_KW LPAR __imports_star_3 RPAR -> drop
view_option 3 kkk drop 1  view_option: DROP_KW LPAR RPAR -> drop
problem 8 kdkdkksk - 0  problem: LPAR _DEFINE_WORD LPAR _PROBLEM_WORD NAME RPAR __problem_star_13 RPAR
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
init 4 kksk - 0  init: LPAR INIT_KW __init_star_14 RPAR
init 3 kkk - 0  init: LPAR INIT_KW RPAR
goal 4 kkkk - 0  goal: LPAR GOAL_KW expr RPAR
horizon 4 kkkk - 0  horizon: LPAR HORIZON_KW NUMBER RPAR
soft 5 kkksk - 0  soft: LPAR SOFT_KW expr __soft_star_15 RPAR
soft 4 kkkk - 0  soft: LPAR SOFT_KW expr RPAR
soft_option 2 kk weight 1  soft_option: WEIGHT_KW NUMBER -> weight
metric 4 kkkk - 0  metric: LPAR METRIC_KW metric_body RPAR
metric_body 1 k single 1  metric_body: objective_body -> single
metric_body 2 ds lex 1  metric_body: _LEX_WORD __metric_body_plus_16 -> lex
metric_body 2 ds pareto 1  metric_body: _PARETO_WORD __metric_body_plus_16 -> pareto
objective 3 kkk - 0  objective: LPAR objective_body RPAR
objective_body 2 kk - 0  objective_body: SENSE expr
deployed 4 kksk - 0  deployed: LPAR DEPLOYED_KW __imports_star_3 RPAR
deployed 3 kkk - 0  deployed: LPAR DEPLOYED_KW RPAR
view_use 4 kkkk - 0  view_use: LPAR VIEW_KW NAME RPAR
expr 1 k ref 1  expr: NAME -> ref
expr 1 k number 1  expr: NUMBER -> number
expr 1 k true 1  expr: TRUE -> true
expr 1 k false 1  expr: FALSE -> false
expr 3 ksk set_literal 1  expr: LBRACE __init_star_14 RBRACE -> set_literal
expr 2 kk set_literal 1  expr: LBRACE RBRACE -> set_literal
expr 4 kksk call 1  expr: LPAR NAME __init_star_14 RPAR -> call
expr 3 kkk call 1  expr: LPAR NAME RPAR -> call
expr 4 kksk call 1  expr: LPAR OPSYM __init_star_14 RPAR -> call
expr 3 kkk call 1  expr: LPAR OPSYM RPAR -> call
expr 4 kksk call 1  expr: LPAR MINUS __init_star_14 RPAR -> call
expr 3 kkk call 1  expr: LPAR MINUS RPAR -> call
expr 4 kksk call 1  expr: LPAR STAR __init_star_14 RPAR -> call
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
__hole_star_11 1 k - 0  __hole_star_11: hole_option
__hole_star_11 2 sk - 0  __hole_star_11: __hole_star_11 hole_option
__view_decl_star_12 1 k - 0  __view_decl_star_12: view_option
__view_decl_star_12 2 sk - 0  __view_decl_star_12: __view_decl_star_12 view_option
__problem_star_13 1 s - 0  __problem_star_13: _problem_section
__problem_star_13 2 ss - 0  __problem_star_13: __problem_star_13 _problem_section
__init_star_14 1 k - 0  __init_star_14: expr
__init_star_14 2 sk - 0  __init_star_14: __init_star_14 expr
__soft_star_15 1 k - 0  __soft_star_15: soft_option
__soft_star_15 2 sk - 0  __soft_star_15: __soft_star_15 soft_option
__metric_body_plus_16 1 k - 0  __metric_body_plus_16: objective
__metric_body_plus_16 2 sk - 0  __metric_body_plus_16: __metric_body_plus_16 objective
"""

START_STATE = 0
END_STATE = 6

#: One state per line (line i is state i): pairs of symbol and action; an action >= 0
#: shifts (or, after a reduction, goes) to that state, an action < 0 reduces by rule ~action.
_STATES = """\
$END -2 LPAR 1 __start_star_0 2 _definition 3 domain 4 problem 5 start 6
_DEFINE_WORD 7
$END -1 LPAR 1 _definition 8 domain 4 problem 5
$END -120 LPAR -120
$END -3 LPAR -3
$END -4 LPAR -4

LPAR 9
$END -121 LPAR -121
_DOMAIN_WORD 10 _PROBLEM_WORD 11
NAME 12
NAME 13
RPAR 14
RPAR 15
LPAR 16 RPAR 17 __domain_star_1 18 _domain_section 19 constants 20 hole 21 imports 22 morphism 23 requirements 24 resources 25 sorts 26 view_decl 27
LPAR 28 RPAR 29 __problem_star_13 30 _problem_section 31 deployed 32 domain_ref 33 goal 34 horizon 35 init 36 metric 37 objects 38 requirements 39 soft 40 view_use 41
CONSTANTS_KW 42 HOLE_KW 43 IMPORT_KW 44 MORPHISM_KW 45 REQUIREMENTS_KW 46 RESOURCES_KW 47 SORTS_KW 48 VIEW_KW 49
$END -6 LPAR -6
LPAR 16 RPAR 50 _domain_section 51 constants 20 hole 21 imports 22 morphism 23 requirements 24 resources 25 sorts 26 view_decl 27
LPAR -122 RPAR -122
LPAR -10 RPAR -10
LPAR -13 RPAR -13
LPAR -8 RPAR -8
LPAR -12 RPAR -12
LPAR -7 RPAR -7
LPAR -11 RPAR -11
LPAR -9 RPAR -9
LPAR -14 RPAR -14
DEPLOYED_KW 52 DOMAIN_KW 53 GOAL_KW 54 HORIZON_KW 55 INIT_KW 56 METRIC_KW 57 OBJECTS_KW 58 REQUIREMENTS_KW 46 SOFT_KW 59 VIEW_KW 60
$END -77 LPAR -77
LPAR 28 RPAR 61 _problem_section 62 deployed 32 domain_ref 33 goal 34 horizon 35 init 36 metric 37 objects 38 requirements 39 soft 40 view_use 41
LPAR -146 RPAR -146
LPAR -86 RPAR -86
LPAR -78 RPAR -78
LPAR -82 RPAR -82
LPAR -83 RPAR -83
LPAR -81 RPAR -81
LPAR -85 RPAR -85
LPAR -80 RPAR -80
LPAR -79 RPAR -79
LPAR -84 RPAR -84
LPAR -87 RPAR -87
NAME 63 RPAR -32 __imports_star_3 64 __typed_names_star_5 65 name_list 66 typed_group 67 typed_names 68
NAME 69
NAME 63 RPAR 70 __imports_star_3 71
NAME 72
FLAG 73 RPAR 74 __requirements_star_2 75
LPAR 76 RPAR 77 __resources_star_6 78 resource 79
NAME 63 RPAR 80 __imports_star_3 64 __sorts_star_4 81 name_list 82 sort_group 83
NAME 84
$END -5 LPAR -5
LPAR -123 RPAR -123
NAME 63 RPAR 85 __imports_star_3 86
NAME 87
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 TRUE 93 expr 94
NUMBER 95
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 96 TRUE 93 __init_star_14 97 expr 98
SENSE 99 _LEX_WORD 100 _PARETO_WORD 101 metric_body 102 objective_body 103
NAME 63 RPAR -32 __imports_star_3 64 __typed_names_star_5 65 name_list 66 typed_group 67 typed_names 104
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 TRUE 93 expr 105
NAME 106
$END -76 LPAR -76
LPAR -147 RPAR -147
MINUS -126 NAME -126 RPAR -126
MINUS -34 NAME 107 RPAR -34
NAME 63 RPAR -30 __imports_star_3 64 name_list 108 typed_group 109
MINUS 110 RPAR -31
NAME -130 RPAR -130
RPAR 111
MAX_EFFECTS_KW 112 MAX_PRECONDITIONS_KW 113 RPAR 114 VIEW_KW 115 __hole_star_11 116 hole_option 117
LPAR -18 RPAR -18
NAME 107 RPAR 118
CHURN_KW 119 COST_KW 120 DOC_KW 121 EFFECT_KW 122 KIND_KW 123 PARAMETERS_KW 124 PRECONDITION_KW 125 RPAR 126 USES_KW 127 __morphism_star_8 128 morphism_option 129
FLAG -124 RPAR -124
LPAR -16 RPAR -16
FLAG 130 RPAR 131
NAME 132
LPAR -36 RPAR -36
LPAR 76 RPAR 133 resource 134
LPAR -132 RPAR -132
LPAR -22 RPAR -22
NAME 63 RPAR 135 __imports_star_3 64 name_list 136 sort_group 137
MINUS 138 RPAR 139
NAME -128 RPAR -128
DROP_KW 140 KEEP_KW 141 RPAR 142 __view_decl_star_12 143 view_option 144
LPAR -104 RPAR -104
NAME 107 RPAR 145
RPAR 146
CHURN_KW -109 COST_KW -109 DOC_KW -109 EFFECT_KW -109 FALSE -109 KIND_KW -109 LBRACE -109 LPAR -109 NAME -109 NUMBER -109 PARAMETERS_KW -109 PRECONDITION_KW -109 RBRACE -109 RPAR -109 TRUE -109 USES_KW -109 WEIGHT_KW -109
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RBRACE 147 TRUE 93 __init_star_14 148 expr 98
MINUS 149 NAME 150 OPSYM 151 STAR 152
CHURN_KW -106 COST_KW -106 DOC_KW -106 EFFECT_KW -106 FALSE -106 KIND_KW -106 LBRACE -106 LPAR -106 NAME -106 NUMBER -106 PARAMETERS_KW -106 PRECONDITION_KW -106 RBRACE -106 RPAR -106 TRUE -106 USES_KW -106 WEIGHT_KW -106
CHURN_KW -107 COST_KW -107 DOC_KW -107 EFFECT_KW -107 FALSE -107 KIND_KW -107 LBRACE -107 LPAR -107 NAME -107 NUMBER -107 PARAMETERS_KW -107 PRECONDITION_KW -107 RBRACE -107 RPAR -107 TRUE -107 USES_KW -107 WEIGHT_KW -107
CHURN_KW -108 COST_KW -108 DOC_KW -108 EFFECT_KW -108 FALSE -108 KIND_KW -108 LBRACE -108 LPAR -108 NAME -108 NUMBER -108 PARAMETERS_KW -108 PRECONDITION_KW -108 RBRACE -108 RPAR -108 TRUE -108 USES_KW -108 WEIGHT_KW -108
RPAR 153
RPAR 154
LPAR -91 RPAR -91
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 155 TRUE 93 expr 156
FALSE -148 LBRACE -148 LPAR -148 NAME -148 NUMBER -148 RBRACE -148 RPAR -148 TRUE -148
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 TRUE 93 expr 157
LPAR 158 __metric_body_plus_16 159 objective 160
LPAR 158 __metric_body_plus_16 161 objective 160
RPAR 162
RPAR -98
RPAR 163
RPAR 164 WEIGHT_KW 165 __soft_star_15 166 soft_option 167
RPAR 168
MINUS -127 NAME -127 RPAR -127
MINUS 110 RPAR -29
NAME -131 RPAR -131
NAME 169
LPAR -28 RPAR -28
NUMBER 170
NUMBER 171
LPAR -66 RPAR -66
NAME 172
MAX_EFFECTS_KW 112 MAX_PRECONDITIONS_KW 113 RPAR 173 VIEW_KW 115 hole_option 174
MAX_EFFECTS_KW -142 MAX_PRECONDITIONS_KW -142 RPAR -142 VIEW_KW -142
LPAR -17 RPAR -17
NUMBER 175
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 TRUE 93 expr 176
STRING 177
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 TRUE 93 expr 178
NAME 179
LPAR 180
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 TRUE 93 expr 181
LPAR -51 RPAR -51
NUMBER 182
CHURN_KW 119 COST_KW 120 DOC_KW 121 EFFECT_KW 122 KIND_KW 123 PARAMETERS_KW 124 PRECONDITION_KW 125 RPAR 183 USES_KW 127 morphism_option 184
CHURN_KW -136 COST_KW -136 DOC_KW -136 EFFECT_KW -136 KIND_KW -136 PARAMETERS_KW -136 PRECONDITION_KW -136 RPAR -136 USES_KW -136
FLAG -125 RPAR -125
LPAR -15 RPAR -15
LPAR 185 NAME 186 _type 187 set_type 188
LPAR -35 RPAR -35
LPAR -133 RPAR -133
LPAR -20 RPAR -20
MINUS 138 RPAR 189
NAME -129 RPAR -129
LPAR 190 NAME 191 _sort_parent 192 enum_spec 193
LPAR -21 RPAR -21
LPAR 194
LPAR 195
LPAR -71 RPAR -71
DROP_KW 140 KEEP_KW 141 RPAR 196 view_option 197
DROP_KW -144 KEEP_KW -144 RPAR -144
LPAR -103 RPAR -103
LPAR -88 RPAR -88
CHURN_KW -111 COST_KW -111 DOC_KW -111 EFFECT_KW -111 FALSE -111 KIND_KW -111 LBRACE -111 LPAR -111 NAME -111 NUMBER -111 PARAMETERS_KW -111 PRECONDITION_KW -111 RBRACE -111 RPAR -111 TRUE -111 USES_KW -111 WEIGHT_KW -111
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RBRACE 198 TRUE 93 expr 156
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 199 TRUE 93 __init_star_14 200 expr 98
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 201 TRUE 93 __init_star_14 202 expr 98
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 203 TRUE 93 __init_star_14 204 expr 98
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 205 TRUE 93 __init_star_14 206 expr 98
LPAR -92 RPAR -92
LPAR -93 RPAR -93
LPAR -90 RPAR -90
FALSE -149 LBRACE -149 LPAR -149 NAME -149 NUMBER -149 RBRACE -149 RPAR -149 TRUE -149
RPAR -102
SENSE 99 objective_body 207
LPAR 158 RPAR -99 objective 208
LPAR -152 RPAR -152
LPAR 158 RPAR -100 objective 208
LPAR -97 RPAR -97
LPAR -89 RPAR -89
LPAR -95 RPAR -95
NUMBER 209
RPAR 210 WEIGHT_KW 165 soft_option 211
RPAR -150 WEIGHT_KW -150
LPAR -105 RPAR -105
NAME -33 RPAR -33
MAX_EFFECTS_KW -68 MAX_PRECONDITIONS_KW -68 RPAR -68 VIEW_KW -68
MAX_EFFECTS_KW -69 MAX_PRECONDITIONS_KW -69 RPAR -69 VIEW_KW -69
MAX_EFFECTS_KW -67 MAX_PRECONDITIONS_KW -67 RPAR -67 VIEW_KW -67
LPAR -65 RPAR -65
MAX_EFFECTS_KW -143 MAX_PRECONDITIONS_KW -143 RPAR -143 VIEW_KW -143
CHURN_KW -53 COST_KW -53 DOC_KW -53 EFFECT_KW -53 KIND_KW -53 PARAMETERS_KW -53 PRECONDITION_KW -53 RPAR -53 USES_KW -53
CHURN_KW -55 COST_KW -55 DOC_KW -55 EFFECT_KW -55 KIND_KW -55 PARAMETERS_KW -55 PRECONDITION_KW -55 RPAR -55 USES_KW -55
CHURN_KW -60 COST_KW -60 DOC_KW -60 EFFECT_KW -60 KIND_KW -60 PARAMETERS_KW -60 PRECONDITION_KW -60 RPAR -60 USES_KW -60
CHURN_KW -59 COST_KW -59 DOC_KW -59 EFFECT_KW -59 KIND_KW -59 PARAMETERS_KW -59 PRECONDITION_KW -59 RPAR -59 USES_KW -59
CHURN_KW -52 COST_KW -52 DOC_KW -52 EFFECT_KW -52 KIND_KW -52 PARAMETERS_KW -52 PRECONDITION_KW -52 RPAR -52 USES_KW -52
LPAR 212 RPAR 213 __morphism_option_star_9 214 parameter 215
CHURN_KW -58 COST_KW -58 DOC_KW -58 EFFECT_KW -58 KIND_KW -58 PARAMETERS_KW -58 PRECONDITION_KW -58 RPAR -58 USES_KW -58
CHURN_KW -54 COST_KW -54 DOC_KW -54 EFFECT_KW -54 KIND_KW -54 PARAMETERS_KW -54 PRECONDITION_KW -54 RPAR -54 USES_KW -54
LPAR -50 RPAR -50
CHURN_KW -137 COST_KW -137 DOC_KW -137 EFFECT_KW -137 KIND_KW -137 PARAMETERS_KW -137 PRECONDITION_KW -137 RPAR -137 USES_KW -137
_SET_WORD 216
BOUNDS_KW -44 DOC_KW -44 FIXED_KW -44 GROUP_KW -44 RPAR -44 UNIT_KW -44
BOUNDS_KW 217 DOC_KW 218 GROUP_KW 219 RPAR 220 UNIT_KW 221 __resource_star_7 222 resource_option 223
BOUNDS_KW -45 DOC_KW -45 FIXED_KW -45 GROUP_KW -45 RPAR -45 UNIT_KW -45
LPAR -19 RPAR -19
_ENUM_WORD 224
NAME -24 RPAR -24
NAME -23 RPAR -23
NAME -25 RPAR -25
NAME 63 RPAR 225 __imports_star_3 226
NAME 63 RPAR 227 __imports_star_3 228
LPAR -70 RPAR -70
DROP_KW -145 KEEP_KW -145 RPAR -145
CHURN_KW -110 COST_KW -110 DOC_KW -110 EFFECT_KW -110 FALSE -110 KIND_KW -110 LBRACE -110 LPAR -110 NAME -110 NUMBER -110 PARAMETERS_KW -110 PRECONDITION_KW -110 RBRACE -110 RPAR -110 TRUE -110 USES_KW -110 WEIGHT_KW -110
CHURN_KW -117 COST_KW -117 DOC_KW -117 EFFECT_KW -117 FALSE -117 KIND_KW -117 LBRACE -117 LPAR -117 NAME -117 NUMBER -117 PARAMETERS_KW -117 PRECONDITION_KW -117 RBRACE -117 RPAR -117 TRUE -117 USES_KW -117 WEIGHT_KW -117
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 229 TRUE 93 expr 156
CHURN_KW -113 COST_KW -113 DOC_KW -113 EFFECT_KW -113 FALSE -113 KIND_KW -113 LBRACE -113 LPAR -113 NAME -113 NUMBER -113 PARAMETERS_KW -113 PRECONDITION_KW -113 RBRACE -113 RPAR -113 TRUE -113 USES_KW -113 WEIGHT_KW -113
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 230 TRUE 93 expr 156
CHURN_KW -115 COST_KW -115 DOC_KW -115 EFFECT_KW -115 FALSE -115 KIND_KW -115 LBRACE -115 LPAR -115 NAME -115 NUMBER -115 PARAMETERS_KW -115 PRECONDITION_KW -115 RBRACE -115 RPAR -115 TRUE -115 USES_KW -115 WEIGHT_KW -115
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 231 TRUE 93 expr 156
CHURN_KW -119 COST_KW -119 DOC_KW -119 EFFECT_KW -119 FALSE -119 KIND_KW -119 LBRACE -119 LPAR -119 NAME -119 NUMBER -119 PARAMETERS_KW -119 PRECONDITION_KW -119 RBRACE -119 RPAR -119 TRUE -119 USES_KW -119 WEIGHT_KW -119
FALSE 88 LBRACE 89 LPAR 90 NAME 91 NUMBER 92 RPAR 232 TRUE 93 expr 156
RPAR 233
LPAR -153 RPAR -153
RPAR -96 WEIGHT_KW -96
LPAR -94 RPAR -94
RPAR -151 WEIGHT_KW -151
NAME 234
CHURN_KW -57 COST_KW -57 DOC_KW -57 EFFECT_KW -57 KIND_KW -57 PARAMETERS_KW -57 PRECONDITION_KW -57 RPAR -57 USES_KW -57
LPAR 212 RPAR 235 parameter 236
LPAR -138 RPAR -138
NAME 237
LPAR 238 bounds 239
STRING 240
NAME 241
LPAR -38 RPAR -38
NAME 242 STRING 243
BOUNDS_KW 217 DOC_KW 218 GROUP_KW 219 RPAR 244 UNIT_KW 221 resource_option 245
BOUNDS_KW -134 DOC_KW -134 GROUP_KW -134 RPAR -134 UNIT_KW -134
NAME 63 RPAR 246 __imports_star_3 247
DROP_KW -75 KEEP_KW -75 RPAR -75
NAME 107 RPAR 248
DROP_KW -73 KEEP_KW -73 RPAR -73
NAME 107 RPAR 249
CHURN_KW -116 COST_KW -116 DOC_KW -116 EFFECT_KW -116 FALSE -116 KIND_KW -116 LBRACE -116 LPAR -116 NAME -116 NUMBER -116 PARAMETERS_KW -116 PRECONDITION_KW -116 RBRACE -116 RPAR -116 TRUE -116 USES_KW -116 WEIGHT_KW -116
CHURN_KW -112 COST_KW -112 DOC_KW -112 EFFECT_KW -112 FALSE -112 KIND_KW -112 LBRACE -112 LPAR -112 NAME -112 NUMBER -112 PARAMETERS_KW -112 PRECONDITION_KW -112 RBRACE -112 RPAR -112 TRUE -112 USES_KW -112 WEIGHT_KW -112
CHURN_KW -114 COST_KW -114 DOC_KW -114 EFFECT_KW -114 FALSE -114 KIND_KW -114 LBRACE -114 LPAR -114 NAME -114 NUMBER -114 PARAMETERS_KW -114 PRECONDITION_KW -114 RBRACE -114 RPAR -114 TRUE -114 USES_KW -114 WEIGHT_KW -114
CHURN_KW -118 COST_KW -118 DOC_KW -118 EFFECT_KW -118 FALSE -118 KIND_KW -118 LBRACE -118 LPAR -118 NAME -118 NUMBER -118 PARAMETERS_KW -118 PRECONDITION_KW -118 RBRACE -118 RPAR -118 TRUE -118 USES_KW -118 WEIGHT_KW -118
LPAR -101 RPAR -101
LPAR 185 NAME 186 _type 250 set_type 188
CHURN_KW -56 COST_KW -56 DOC_KW -56 EFFECT_KW -56 KIND_KW -56 PARAMETERS_KW -56 PRECONDITION_KW -56 RPAR -56 USES_KW -56
LPAR -139 RPAR -139
RPAR 251
NUMBER 252 STAR 253 bound 254
BOUNDS_KW -42 DOC_KW -42 GROUP_KW -42 RPAR -42 UNIT_KW -42
BOUNDS_KW -43 DOC_KW -43 GROUP_KW -43 RPAR -43 UNIT_KW -43
BOUNDS_KW -39 DOC_KW -39 GROUP_KW -39 RPAR -39 UNIT_KW -39
BOUNDS_KW -40 DOC_KW -40 GROUP_KW -40 RPAR -40 UNIT_KW -40
BOUNDS_KW -41 DOC_KW -41 GROUP_KW -41 RPAR -41 UNIT_KW -41
LPAR -37 RPAR -37
BOUNDS_KW -135 DOC_KW -135 GROUP_KW -135 RPAR -135 UNIT_KW -135
NAME -27 RPAR -27
NAME 107 RPAR 255
DROP_KW -74 KEEP_KW -74 RPAR -74
DROP_KW -72 KEEP_KW -72 RPAR -72
BOUNDS_KW 256 FIXED_KW 257 RPAR 258 __parameter_star_10 259 parameter_option 260
BOUNDS_KW -46 DOC_KW -46 FIXED_KW -46 GROUP_KW -46 RPAR -46 UNIT_KW -46
NUMBER -48 RPAR -48 STAR -48
NUMBER -49 RPAR -49 STAR -49
NUMBER 252 STAR 253 bound 261
NAME -26 RPAR -26
LPAR 238 bounds 262
BOUNDS_KW -64 FIXED_KW -64 RPAR -64
LPAR -62 RPAR -62
BOUNDS_KW 256 FIXED_KW 257 RPAR 263 parameter_option 264
BOUNDS_KW -140 FIXED_KW -140 RPAR -140
RPAR 265
BOUNDS_KW -63 FIXED_KW -63 RPAR -63
LPAR -61 RPAR -61
BOUNDS_KW -141 FIXED_KW -141 RPAR -141
BOUNDS_KW -47 DOC_KW -47 FIXED_KW -47 GROUP_KW -47 RPAR -47 UNIT_KW -47
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
