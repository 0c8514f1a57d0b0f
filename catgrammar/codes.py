"""The diagnostic codes: a stable code, a name and a one-line summary for every problem the
toolchain reports, with a named constant per code (``codes.UNKNOWN_NAME == "E0202"``) so that
no module spells a code as a string literal.

Codes are never reused; a retired code stays listed.  docs/errors.md lists them all
(``tests/test_symbols.py`` checks that, and that every code is exercised by a test).
Ranges: E00xx reading input, E01xx syntax, E02xx names, E03xx types, E04xx requirements,
E05xx semantics, E07xx command-line arguments, E08xx plan files, E09xx exports, E10xx the
runtime, E11xx limits, E12xx interoperability (imports), W01xx lints.
"""

from __future__ import annotations

from enum import Enum

from catgrammar.record import Record, set_field


class Severity(str, Enum):
    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


class Code(Record):
    __slots__ = ("code", "name", "severity", "summary")
    code: str
    name: str
    severity: Severity
    summary: str

    def __init__(self, code: str, name: str, severity: Severity, summary: str) -> None:
        set_field(self, "code", code)
        set_field(self, "name", name)
        set_field(self, "severity", severity)
        set_field(self, "summary", summary)


E, W = Severity.ERROR, Severity.WARNING

#: The registry: code → :class:`Code`.
CODES: dict[str, Code] = {
    c.code: c
    for c in (
        # E00xx — reading input
        Code(
            "E0001",
            "unreadable-file",
            E,
            "The file cannot be read (missing, a folder, a FIFO or device, or permission denied).",
        ),
        Code("E0002", "binary-file", E, "The file contains NUL bytes; it is not a text file."),
        Code("E0003", "invalid-utf8", E, "The file is not valid UTF-8."),
        Code("E0004", "empty-file", E, "The file holds no definition."),
        Code("E0005", "no-input", E, "No .cat file was found among the given paths."),
        # E01xx — syntax
        Code("E0101", "syntax", E, "The text does not follow the grammar."),
        Code("E0102", "unbalanced-close", E, "A ')' has no matching '('."),
        Code("E0103", "unclosed-paren", E, "A '(' is never closed."),
        Code("E0104", "too-deep", E, "Parentheses nest deeper than the nesting limit (docs/limits.md)."),
        Code(
            "E0105",
            "literal-too-long",
            E,
            "A numeric literal has more digits than the literal-digits limit (docs/limits.md).",
        ),
        Code("E0106", "unknown-section", E, "A section or option keyword is not part of the language."),
        Code("E0107", "bad-character", E, "A character that cannot start any token."),
        # E02xx — names
        Code("E0201", "duplicate-name", E, "A name is declared twice in one namespace."),
        Code("E0202", "unknown-name", E, "A name is used but never declared."),
        Code("E0203", "reserved-name", E, "A keyword is used as a name."),
        Code("E0204", "shadowing", E, "A parameter has the name of a resource or constant."),
        Code("E0205", "duplicate-option", E, "An option or section is given twice where one is allowed."),
        Code("E0206", "missing-option", E, "A required option or section is missing."),
        Code("E0207", "unknown-domain", E, "A problem names a domain that cannot be found."),
        Code("E0208", "unknown-import", E, "An imported domain cannot be found."),
        Code("E0209", "circular-import", E, "Domains import each other in a cycle."),
        Code("E0210", "duplicate-definition", E, "Two files define a domain or problem of the same name."),
        Code("E0211", "unknown-operator", E, "An expression head is not an operator of the language."),
        Code("E0212", "unknown-requirement", E, "A requirement flag is not part of the language."),
        # E03xx — types
        Code("E0301", "type-mismatch", E, "An expression has the wrong sort for where it is used."),
        Code("E0302", "arity", E, "An operator is given the wrong number of arguments."),
        Code("E0303", "not-a-set", E, "Membership or set update on something that is not a set."),
        Code("E0304", "bad-sort", E, "A sort declaration or reference is invalid."),
        Code(
            "E0305",
            "misplaced-operator",
            E,
            "An operator is used where it is not allowed (e.g. an effect in a condition).",
        ),
        Code("E0306", "bad-bounds", E, "Bounds are malformed or empty."),
        Code("E0307", "bad-value", E, "A value is out of its allowed range (e.g. a negative weight)."),
        Code("E0308", "not-assignable", E, "An effect writes something that is not a resource."),
        Code("E0310", "division-by-zero", E, "Division by the constant zero."),
        Code("E0311", "unit-mismatch-compare", E, "A comparison relates quantities of different dimensions."),
        Code(
            "E0312",
            "unit-mismatch-arithmetic",
            E,
            "'+', '-', 'min', 'max' or the branches of 'if' combine quantities of different dimensions.",
        ),
        Code(
            "E0313",
            "unit-mismatch-effect",
            E,
            "An effect or an initial value gives a resource a quantity of another dimension than its unit's.",
        ),
        Code("E0314", "unknown-unit", E, "A :unit names no unit of the registry (pint's and catc's units.txt)."),
        Code("E0315", "unit-on-non-number", E, "A :unit is given to a resource or parameter that is not a number."),
        # E04xx — requirements
        Code(
            "E0401", "missing-requirement", E, "A construct needs a requirement flag the definition does not declare."
        ),
        # E05xx — semantics
        Code("E0501", "conflicting-effects", E, "One effect writes a resource in two incompatible ways."),
        Code("E0502", "bad-init", E, "An initial-state literal is not of the form (= resource value)."),
        Code("E0503", "missing-init", E, "A numeric or symbolic resource has no initial value."),
        Code("E0504", "closed-sort", E, "Objects added to a closed enumeration."),
        Code("E0505", "bad-objective", E, "An objective term is not a number or refers to something undefined."),
        Code("E0506", "bad-view", E, "A view keeps or drops resources inconsistently."),
        Code("E0507", "ambiguous-parameter", E, "A per-activation parameter is referenced where one value is needed."),
        Code(
            "E0508",
            "bad-grounding",
            E,
            "A grounding annotation does not fit its morphism: another kind, an option that does not belong, a "
            "missing one, a value of the wrong shape, or a hole naming no parameter.",
        ),
        Code(
            "E0509",
            "bad-target-name",
            E,
            "A name a grounding target cannot take: a ROS 2 node, parameter or topic name, a container image, a "
            "BehaviorTree.CPP node ID or port, a Compose project.",
        ),
        # E07xx — command-line arguments
        Code(
            "E0701",
            "bad-argument",
            E,
            "A command-line argument cannot be used (malformed, or the wrong number of paths).",
        ),
        Code(
            "E0702",
            "unknown-component",
            E,
            "A morphism named on the command line (--deployed, --relative-to) is not in the model.",
        ),
        Code("E0703", "bad-weight", E, "A --weights entry is not KEY=NUMBER."),
        Code(
            "E0704",
            "not-applicable",
            E,
            "The query cannot run on this problem as asked (nothing to optimise, fewer than two objectives, no deployed composition, no such hole).",
        ),
        Code("E0705", "cannot-write", E, "An output file (--diagram, --plot, -o) cannot be written."),
        Code("E0706", "missing-extra", E, "An optional part is not installed; the message names the extra to install."),
        Code("E0707", "unknown-code", E, "catc explain was given something that is not a diagnostic code."),
        Code("E0708", "would-overwrite", E, "catc init would overwrite a file that exists; nothing is written."),
        # E08xx — plan files
        Code("E0801", "plan-not-json", E, "A plan file is not JSON."),
        Code("E0802", "bad-plan", E, "A plan file does not follow the catc.plan/1 schema."),
        # E09xx — exports
        Code(
            "E0901",
            "export-unsupported",
            E,
            "The model cannot be exported as asked (e.g. a real parameter without a --grid step).",
        ),
        Code(
            "E0902", "export-rejected", E, "An independent parser rejects the exported files (a bug in catc's export)."
        ),
        Code(
            "E0903", "baseline-unavailable", E, "The baseline planner cannot be run (Java, ENHSP or SMTPlan+ missing)."
        ),
        # E10xx — the runtime (catrt)
        Code(
            "E1001",
            "bad-event",
            E,
            "An event line is not a catrt event: not JSON, an unknown field, a value of the wrong shape.",
        ),
        Code(
            "E1002",
            "event-rejected",
            E,
            "An event's change would make the model invalid (the checker's errors, located in the event, follow).",
        ),
        Code("E1003", "store-locked", E, "Another runtime is running on this state folder (one writer at a time)."),
        Code("E1004", "store-version", E, "The store was written by another schema version and cannot be migrated."),
        Code(
            "E1005", "not-a-store", E, "The state folder holds no catrt store (run catrt init first), or it is damaged."
        ),
        Code("E1006", "store-exists", E, "catrt init on a state folder that already holds a store."),
        Code("E1007", "bad-config", E, "The runtime configuration (STATE/config.toml) is malformed."),
        Code(
            "E1008",
            "shell-not-allowed",
            E,
            "The configuration declares shell sensors but the runtime was not started with --allow-shell.",
        ),
        Code(
            "E1009", "sensor-failed", E, "A shell sensor timed out, failed, or printed something that is not a value."
        ),
        Code("E1010", "unknown-approval", E, "An approval names no pending request."),
        Code(
            "E1011", "enact-failed", E, "The enactor could not enact a generation (the deployed composition is kept)."
        ),
        Code(
            "E1012",
            "store-inconsistent",
            E,
            "verify found a problem: a failed integrity check, a gap in the journal, a replay that differs from the "
            "stored state, or an artifact whose hash differs from its manifest.",
        ),
        Code("E1013", "source-tampered", E, "A model source in the store no longer has the sha256 it was stored with."),
        Code(
            "E1014",
            "store-damaged",
            E,
            "The store is truncated, empty or fails its integrity check: nothing is written.",
        ),
        Code(
            "E1015",
            "state-read-only",
            E,
            "The state folder (or its store) is read-only: catrt cannot lock or write it.",
        ),
        Code(
            "E1016",
            "disk-full",
            E,
            "The disk is full: the event was not acknowledged (catrt run retries, backing off).",
        ),
        Code(
            "E1017",
            "decision-budget",
            E,
            "An event's decision ran past its budget ([limits] decision): undecided, the deployed composition stays.",
        ),
        # E11xx — limits (docs/limits.md)
        Code("E1101", "input-too-large", E, "An input file is larger than the input-bytes limit."),
        Code("E1102", "too-many-tokens", E, "An input file has more tokens than the tokens limit."),
        Code(
            "E1103",
            "constant-too-large",
            E,
            "A constant the checker computes has a numerator or denominator of more digits than the constant-digits "
            "limit.",
        ),
        Code("E1104", "too-many-resources", E, "A domain declares more resources than the resources limit."),
        Code("E1105", "too-many-morphisms", E, "A domain declares more morphisms than the morphisms limit."),
        Code(
            "E1106",
            "universe-too-large",
            E,
            "A symbolic sort would be grounded with more values than the universe limit (its constants and the "
            "reserve values the horizon needs).",
        ),
        Code(
            "E1107",
            "horizon-too-large",
            E,
            "A horizon (:horizon, -k, or the sum of use limits) past the horizon limit.",
        ),
        Code(
            "E1108",
            "too-many-ground-actions",
            E,
            "A PDDL export would write more ground actions than the ground-actions limit.",
        ),
        Code(
            "E1109",
            "time-limit",
            E,
            "The command reached its --timeout in a phase that has no partial answer (encoding, export); exit 3.",
        ),
        Code("E1110", "out-of-memory", E, "The command reached its memory limit (--memory); exit 3."),
        Code(
            "E1111",
            "bad-limit",
            E,
            "A --limit, --memory or CATC_LIMIT_* value is not a known limit and a whole number.",
        ),
        # E12xx — interoperability: imports from other planning tools
        Code(
            "E1201",
            "import-unsupported",
            E,
            "An imported planning problem uses something catc cannot express; the import report lists each construct and why.",
        ),
        Code(
            "E1202",
            "import-needs-extra",
            E,
            "Importing needs an optional package that is not installed (the message names the pip extra).",
        ),
        Code(
            "E1210",
            "pddl-unreadable",
            E,
            "unified-planning's PDDL reader rejects a file given to catc import pddl (at the line and column it names).",
        ),
        Code(
            "E1211",
            "import-recheck-failed",
            E,
            "The .cat files catc import wrote do not pass catc check (a bug in the import; the files are kept).",
        ),
        Code(
            "E1212",
            "import-unspellable",
            E,
            "An imported model holds something .cat text cannot spell (a name or a string); the message says what.",
        ),
        # E13xx — certificates of answers (catc certify, --certificate)
        Code(
            "E1301",
            "unreadable-certificate",
            E,
            "A certificate file given to catc certify cannot be read or is not JSON.",
        ),
        Code(
            "E1302",
            "bad-certificate",
            E,
            "A file given to catc certify is not a well-formed catc.certificate/1 document.",
        ),
        Code(
            "E1303",
            "certificate-mismatch",
            E,
            "A certificate is for another problem or domain than the model given to catc certify.",
        ),
        Code(
            "E1304",
            "not-certifiable",
            E,
            "--certificate was asked of an answer that carries no certificate (the message says why).",
        ),
        # W01xx — lints (errors under --strict)
        Code("W0101", "unused-resource", W, "A resource is declared but nothing reads or writes it."),
        Code("W0102", "unused-sort", W, "A sort is declared but never used."),
        Code("W0103", "unreachable-morphism", W, "A morphism can never apply: something it needs is never produced."),
        Code("W0104", "unwritable-goal", W, "A goal literal reads only resources that no morphism writes."),
        Code("W0105", "unbounded-parameter", W, "A real parameter has no bounds."),
        Code(
            "W0106",
            "ungrounded-morphism",
            W,
            "A morphism of a composition being grounded has no (:ground ...) annotation: nothing is written for it.",
        ),
        Code(
            "W0107",
            "unitless-resource",
            W,
            "A resource declared without :unit meets a quantity with a unit; it silently takes that unit.",
        ),
        Code(
            "W0108",
            "unexecuted-behaviour-tree",
            W,
            "A grounded composition has behaviours but the domain names no (:deployment :executor ...) image: "
            "bt.xml is written and nothing runs it.",
        ),
    )
}


UNREADABLE_FILE = "E0001"
BINARY_FILE = "E0002"
INVALID_UTF8 = "E0003"
EMPTY_FILE = "E0004"
NO_INPUT = "E0005"
SYNTAX = "E0101"
UNBALANCED_CLOSE = "E0102"
UNCLOSED_PAREN = "E0103"
TOO_DEEP = "E0104"
LITERAL_TOO_LONG = "E0105"
UNKNOWN_SECTION = "E0106"
BAD_CHARACTER = "E0107"
DUPLICATE_NAME = "E0201"
UNKNOWN_NAME = "E0202"
RESERVED_NAME = "E0203"
SHADOWING = "E0204"
DUPLICATE_OPTION = "E0205"
MISSING_OPTION = "E0206"
UNKNOWN_DOMAIN = "E0207"
UNKNOWN_IMPORT = "E0208"
CIRCULAR_IMPORT = "E0209"
DUPLICATE_DEFINITION = "E0210"
UNKNOWN_OPERATOR = "E0211"
UNKNOWN_REQUIREMENT = "E0212"
TYPE_MISMATCH = "E0301"
ARITY = "E0302"
NOT_A_SET = "E0303"
BAD_SORT = "E0304"
MISPLACED_OPERATOR = "E0305"
BAD_BOUNDS = "E0306"
BAD_VALUE = "E0307"
NOT_ASSIGNABLE = "E0308"
DIVISION_BY_ZERO = "E0310"
UNIT_MISMATCH_COMPARE = "E0311"
UNIT_MISMATCH_ARITH = "E0312"
UNIT_MISMATCH_EFFECT = "E0313"
UNKNOWN_UNIT = "E0314"
UNIT_ON_NON_NUMBER = "E0315"
MISSING_REQUIREMENT = "E0401"
CONFLICTING_EFFECTS = "E0501"
BAD_INIT = "E0502"
MISSING_INIT = "E0503"
CLOSED_SORT = "E0504"
BAD_OBJECTIVE = "E0505"
BAD_VIEW = "E0506"
AMBIGUOUS_PARAMETER = "E0507"
BAD_GROUNDING = "E0508"
BAD_TARGET_NAME = "E0509"
BAD_ARGUMENT = "E0701"
UNKNOWN_COMPONENT = "E0702"
BAD_WEIGHT = "E0703"
NOT_APPLICABLE = "E0704"
CANNOT_WRITE = "E0705"
MISSING_EXTRA = "E0706"
UNKNOWN_CODE = "E0707"
WOULD_OVERWRITE = "E0708"
PLAN_NOT_JSON = "E0801"
BAD_PLAN = "E0802"
EXPORT_UNSUPPORTED = "E0901"
EXPORT_REJECTED = "E0902"
BASELINE_UNAVAILABLE = "E0903"
BAD_EVENT = "E1001"
EVENT_REJECTED = "E1002"
STORE_LOCKED = "E1003"
STORE_VERSION = "E1004"
NOT_A_STORE = "E1005"
STORE_EXISTS = "E1006"
BAD_CONFIG = "E1007"
SHELL_NOT_ALLOWED = "E1008"
SENSOR_FAILED = "E1009"
UNKNOWN_APPROVAL = "E1010"
ENACT_FAILED = "E1011"
STORE_INCONSISTENT = "E1012"
SOURCE_TAMPERED = "E1013"
STORE_DAMAGED = "E1014"
STATE_READ_ONLY = "E1015"
DISK_FULL = "E1016"
DECISION_BUDGET = "E1017"
INPUT_TOO_LARGE = "E1101"
TOO_MANY_TOKENS = "E1102"
CONSTANT_TOO_LARGE = "E1103"
TOO_MANY_RESOURCES = "E1104"
TOO_MANY_MORPHISMS = "E1105"
UNIVERSE_TOO_LARGE = "E1106"
HORIZON_TOO_LARGE = "E1107"
TOO_MANY_GROUND_ACTIONS = "E1108"
TIME_LIMIT = "E1109"
OUT_OF_MEMORY = "E1110"
BAD_LIMIT = "E1111"
IMPORT_UNSUPPORTED = "E1201"
IMPORT_NEEDS_EXTRA = "E1202"
PDDL_UNREADABLE = "E1210"
IMPORT_RECHECK_FAILED = "E1211"
IMPORT_UNSPELLABLE = "E1212"
UNREADABLE_CERTIFICATE = "E1301"
BAD_CERTIFICATE = "E1302"
CERTIFICATE_MISMATCH = "E1303"
NOT_CERTIFIABLE = "E1304"
UNUSED_RESOURCE = "W0101"
UNUSED_SORT = "W0102"
UNREACHABLE_MORPHISM = "W0103"
UNWRITABLE_GOAL = "W0104"
UNBOUNDED_PARAMETER = "W0105"
UNGROUNDED_MORPHISM = "W0106"
UNITLESS_RESOURCE = "W0107"
UNEXECUTED_TREE = "W0108"
