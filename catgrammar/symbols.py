"""The vocabulary of the .cat language, defined once.

Every keyword, section name, option, operator and requirement flag lives here.  The
grammar (``cat.lark``) is generated against these lists, and so are the Pygments lexer,
the formatter, the language server's completion and the editor grammars under
``editors/`` — a test fails when any of them drifts from this module.
"""

from __future__ import annotations

from enum import Enum


class Section(str, Enum):
    """Top-level ``(:keyword ...)`` sections of a domain or a problem."""

    REQUIREMENTS = ":requirements"
    IMPORT = ":import"
    SORTS = ":sorts"
    CONSTANTS = ":constants"
    RESOURCES = ":resources"
    MORPHISM = ":morphism"
    HOLE = ":hole"
    VIEW = ":view"
    DEPLOYMENT = ":deployment"
    DOMAIN = ":domain"
    OBJECTS = ":objects"
    INIT = ":init"
    GOAL = ":goal"
    HORIZON = ":horizon"
    SOFT = ":soft"
    METRIC = ":metric"
    DEPLOYED = ":deployed"


DOMAIN_SECTIONS: tuple[Section, ...] = (
    Section.REQUIREMENTS,
    Section.IMPORT,
    Section.SORTS,
    Section.CONSTANTS,
    Section.RESOURCES,
    Section.MORPHISM,
    Section.HOLE,
    Section.VIEW,
    Section.DEPLOYMENT,
)

PROBLEM_SECTIONS: tuple[Section, ...] = (
    Section.DOMAIN,
    Section.REQUIREMENTS,
    Section.OBJECTS,
    Section.INIT,
    Section.GOAL,
    Section.HORIZON,
    Section.SOFT,
    Section.METRIC,
    Section.DEPLOYED,
    Section.VIEW,
)


class Option(str, Enum):
    """``:keyword value`` options inside a section."""

    # morphism
    KIND = ":kind"
    CHURN = ":churn"
    USES = ":uses"
    COST = ":cost"
    PARAMETERS = ":parameters"
    PRECONDITION = ":precondition"
    EFFECT = ":effect"
    DOC = ":doc"
    # resource
    GROUP = ":group"
    UNIT = ":unit"
    BOUNDS = ":bounds"
    # parameter
    FIXED = ":fixed"
    # hole
    HOLE_VIEW = ":view"
    MAX_EFFECTS = ":max-effects"
    MAX_PRECONDITIONS = ":max-preconditions"
    # view
    KEEP = ":keep"
    DROP = ":drop"
    # soft constraint
    WEIGHT = ":weight"
    # grounding: a morphism's (:ground (KIND ...)) block and the (:deployment ...) section
    GROUND = ":ground"
    INSTRUCTION = ":instruction"
    CHECK = ":check"
    PARTS = ":parts"
    IMAGE = ":image"
    NODE = ":node"
    PROFILE = ":profile"
    PARAMS = ":params"
    REMAP = ":remap"
    ID = ":id"
    INPUTS = ":inputs"
    OUTPUTS = ":outputs"
    PROJECT = ":project"
    EXECUTOR = ":executor"


MORPHISM_OPTIONS = (
    Option.KIND,
    Option.CHURN,
    Option.USES,
    Option.COST,
    Option.PARAMETERS,
    Option.PRECONDITION,
    Option.EFFECT,
    Option.DOC,
    Option.GROUND,
)
RESOURCE_OPTIONS = (Option.GROUP, Option.UNIT, Option.BOUNDS, Option.DOC)
PARAMETER_OPTIONS = (Option.BOUNDS, Option.FIXED, Option.UNIT)
HOLE_OPTIONS = (Option.HOLE_VIEW, Option.MAX_EFFECTS, Option.MAX_PRECONDITIONS)
VIEW_OPTIONS = (Option.KEEP, Option.DROP)
SOFT_OPTIONS = (Option.WEIGHT,)
#: Inside ``(:ground (KIND ...))``, by kind of morphism.
GROUND_OPTIONS: dict[str, tuple[Option, ...]] = {
    "hardware": (Option.INSTRUCTION, Option.CHECK, Option.PARTS),
    "software": (Option.IMAGE, Option.NODE, Option.PROFILE, Option.PARAMS, Option.REMAP),
    "behavior": (Option.ID, Option.INPUTS, Option.OUTPUTS, Option.IMAGE, Option.PROFILE),
}
DEPLOYMENT_OPTIONS = (Option.PROJECT, Option.EXECUTOR)
#: The keys the grammar accepts in a grounding block or a deployment section (the checker
#: says which belong where).
GROUNDING_KEYS = tuple(dict.fromkeys([*(o for opts in GROUND_OPTIONS.values() for o in opts), *DEPLOYMENT_OPTIONS]))


class Requirement(str, Enum):
    """Requirement flags.  A construct whose flag is not declared is an error."""

    NUMERIC = ":numeric"
    SYMBOLS = ":symbols"
    SETS = ":sets"
    FREE_PARAMETERS = ":free-parameters"
    VIEWS = ":views"
    HOLES = ":holes"
    OPTIMIZATION = ":optimization"
    RECOMPOSITION = ":recomposition"
    GROUNDING = ":grounding"
    ALL = ":robot-circuit"


#: Declaring the key declares every flag of its value too (expanded to a fixpoint).
REQUIREMENT_IMPLIES: dict[Requirement, frozenset[Requirement]] = {
    Requirement.SETS: frozenset({Requirement.SYMBOLS}),
    Requirement.HOLES: frozenset({Requirement.VIEWS}),
    Requirement.OPTIMIZATION: frozenset({Requirement.NUMERIC}),
    Requirement.RECOMPOSITION: frozenset({Requirement.OPTIMIZATION}),
    Requirement.ALL: frozenset(r for r in Requirement if r is not Requirement.ALL),
}


def expand_requirements(flags: set[Requirement] | frozenset[Requirement]) -> frozenset[Requirement]:
    """Close a set of requirement flags under :data:`REQUIREMENT_IMPLIES`."""
    result = set(flags)
    todo = list(flags)
    while todo:
        for implied in REQUIREMENT_IMPLIES.get(todo.pop(), ()):
            if implied not in result:
                result.add(implied)
                todo.append(implied)
    return frozenset(result)


class Operator(str, Enum):
    """Heads of ``(op args...)`` expressions, conditions and effects."""

    AND = "and"
    OR = "or"
    NOT = "not"
    IMPLY = "imply"
    EQ = "="
    LT = "<"
    LE = "<="
    GT = ">"
    GE = ">="
    ADD = "+"
    SUB = "-"
    MUL = "*"
    DIV = "/"
    MIN = "min"
    MAX = "max"
    IF = "if"
    MEMBER = "member"
    # effects
    ASSIGN = "assign"
    INCREASE = "increase"
    DECREASE = "decrease"
    SET_ADD = "add"
    SET_REMOVE = "remove"
    # objective terms
    TOTAL_CHURN = "total-churn"
    TOTAL_COST = "total-cost"
    USES = "uses"
    PARAM = "param"


#: Operators usable in conditions and terms (not effects, not objectives).
EXPRESSION_OPERATORS = (
    Operator.AND,
    Operator.OR,
    Operator.NOT,
    Operator.IMPLY,
    Operator.EQ,
    Operator.LT,
    Operator.LE,
    Operator.GT,
    Operator.GE,
    Operator.ADD,
    Operator.SUB,
    Operator.MUL,
    Operator.DIV,
    Operator.MIN,
    Operator.MAX,
    Operator.IF,
    Operator.MEMBER,
)
EFFECT_OPERATORS = (
    Operator.AND,
    Operator.ASSIGN,
    Operator.INCREASE,
    Operator.DECREASE,
    Operator.SET_ADD,
    Operator.SET_REMOVE,
)
OBJECTIVE_OPERATORS = (Operator.TOTAL_CHURN, Operator.TOTAL_COST, Operator.USES, Operator.PARAM)


class MorphismKind(str, Enum):
    HARDWARE = "hardware"
    SOFTWARE = "software"
    BEHAVIOR = "behavior"


class MetricSense(str, Enum):
    MINIMIZE = "minimize"
    MAXIMIZE = "maximize"


class MetricMode(str, Enum):
    LEX = "lex"
    PARETO = "pareto"


#: Words with a fixed meaning in the grammar (besides sections, options and operators).
STRUCTURE_WORDS = ("define", "domain", "problem")
TYPE_WORDS = ("bool", "int", "real", "set", "symbol", "enum")
LITERAL_WORDS = ("true", "false")

#: Names a user may not give to a sort, resource, constant, parameter or morphism.
RESERVED_NAMES = frozenset(
    set(STRUCTURE_WORDS)
    | set(TYPE_WORDS)
    | set(LITERAL_WORDS)
    | {m.value for m in MetricSense}
    | {m.value for m in MetricMode}
    | {op.value for op in Operator if op.value[0].isalpha()}
)


def all_keywords() -> dict[str, tuple[str, ...]]:
    """Every word of the language by highlighting category (for lexers and editors)."""
    return {
        "structure": STRUCTURE_WORDS,
        "section": tuple(s.value for s in Section),
        "option": tuple(dict.fromkeys(o.value for o in Option)),
        "requirement": tuple(r.value for r in Requirement),
        "operator": tuple(o.value for o in Operator if o.value[0].isalpha()),
        "symbol-operator": tuple(o.value for o in Operator if not o.value[0].isalpha()),
        "type": TYPE_WORDS,
        "constant": LITERAL_WORDS,
        "kind": tuple(k.value for k in MorphismKind),
        "metric": tuple(m.value for m in MetricSense) + tuple(m.value for m in MetricMode),
    }
