"""The runtime's configuration: ``STATE/config.toml`` (written by ``catrt init``, edited by
hand), checked against a JSON schema so that a typo is an error, not a silent default.

    [limits]              # seconds a decision's solver queries may take
    compose = 120
    diagnose = 30
    relax = 30
    decision = 60         # all the queries of one event together (E1017 past it)

    [relax]               # restorations: weights per resource, resources never changed
    weights = { budget = 1, ram = "1/2" }
    fixed = ["battery"]

    [enactor]
    kind = "dry"          # or "compose"
    docker = "docker"     # the docker executable (compose): runs `docker compose`
    compose = "docker-compose"  # or a Compose v2 binary of its own (instead of `docker compose`)
    timeout = 600         # seconds per command
    ready = 60            # seconds for every service to run after `up`

    [[sensor]]            # shell sensors: only with `catrt run --allow-shell`
    name = "battery"
    resource = "battery"
    argv = ["/usr/bin/cat", "/sys/class/power_supply/BAT0/capacity"]
    timeout = 2.0         # seconds
    every = 10.0          # seconds between runs
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

CONFIG_NAME = "config.toml"

TEMPLATE = """# catrt configuration (docs/runtime.md).  Every key is optional.

[limits]            # seconds each solver query of a decision may take
compose = 120       # recompose / optimize / solve
diagnose = 30
relax = 30
# decision = 60     # all the queries of one event together; past it the decision is
                    # "undecided" (E1017), the event stays journaled, the loop goes on

[relax]             # how a restoration (no composition exists) weighs the values it changes
# weights = { budget = 1, ram = "1/2" }   # per unit of each resource (exact)
# fixed = ["battery"]                     # never proposed: resources nobody can change
# The rest: weight 1 when they share one unit, else their relative change (1/|value|).

[enactor]
kind = "dry"        # dry: write generations, run nothing; compose: docker compose up
docker = "docker"
timeout = 600       # seconds per command
ready = 60          # seconds for every service to be running after `up` (else E1011)

# Shell sensors (the paper's shell-evaluated conditions) run only with `catrt run --allow-shell`.
# Each is an argument list, never a shell string; its output is parsed strictly into the
# resource's sort and becomes a `set` event.
# [[sensor]]
# name = "battery"
# resource = "battery"
# argv = ["/usr/bin/cat", "/sys/class/power_supply/BAT0/capacity"]
# timeout = 2.0
# every = 10.0
"""

_NUMBER = {"type": "number", "exclusiveMinimum": 0}
_SCHEMA: dict[str, Any] = {
    "type": "object",
    "additionalProperties": False,
    "properties": {
        "limits": {
            "type": "object",
            "additionalProperties": False,
            "properties": {"compose": _NUMBER, "diagnose": _NUMBER, "relax": _NUMBER, "decision": _NUMBER},
        },
        "relax": {
            "type": "object",
            "additionalProperties": False,
            "properties": {
                "weights": {
                    "type": "object",
                    "additionalProperties": {
                        "oneOf": [
                            {"type": "number", "exclusiveMinimum": 0},
                            {"type": "string", "pattern": "^[0-9]+(\\.[0-9]+)?(/[1-9][0-9]*)?$"},
                        ]
                    },
                },
                "fixed": {"type": "array", "items": {"type": "string", "minLength": 1}},
            },
        },
        "enactor": {
            "type": "object",
            "additionalProperties": False,
            "properties": {
                "kind": {"enum": ["dry", "compose"]},
                "docker": {"type": "string", "minLength": 1},
                "compose": {
                    "oneOf": [
                        {"type": "string", "minLength": 1},
                        {"type": "array", "items": {"type": "string", "minLength": 1}, "minItems": 1},
                    ]
                },
                "timeout": _NUMBER,
                "ready": _NUMBER,
            },
        },
        "sensor": {
            "type": "array",
            "items": {
                "type": "object",
                "additionalProperties": False,
                "required": ["name", "resource", "argv"],
                "properties": {
                    "name": {"type": "string", "pattern": "^[A-Za-z0-9_.-]{1,64}$"},
                    "resource": {"type": "string", "pattern": "^[a-zA-Z_][a-zA-Z0-9_-]*$"},
                    "argv": {"type": "array", "minItems": 1, "items": {"type": "string", "minLength": 1}},
                    "timeout": {"type": "number", "exclusiveMinimum": 0, "maximum": 3600},
                    "every": {"type": "number", "minimum": 0.01},
                },
            },
        },
    },
}


class ConfigError(ValueError):
    pass


@dataclass(frozen=True)
class Sensor:
    name: str
    resource: str
    argv: tuple[str, ...]
    timeout: float = 2.0
    every: float = 10.0


@dataclass(frozen=True)
class Config:
    limits: dict[str, float] = field(default_factory=dict)
    enactor: dict[str, Any] = field(default_factory=dict)
    sensors: tuple[Sensor, ...] = ()
    #: ``[relax]``: weights per resource (exact), resources never relaxed
    relax_weights: dict[str, Fraction] = field(default_factory=dict)
    relax_fixed: frozenset[str] = frozenset()


def load_config(state: Path) -> Config:
    path = state / CONFIG_NAME
    if not path.exists():
        return Config()
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: cannot read it: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not TOML: {exc}") from None
    from jsonschema import Draft202012Validator
    from jsonschema.exceptions import best_match

    error = best_match(Draft202012Validator(_SCHEMA).iter_errors(doc))
    if error is not None:
        where = ".".join(str(p) for p in error.absolute_path) or "the file"
        raise ConfigError(f"{path}: {where}: {error.message}")
    names = [s["name"] for s in doc.get("sensor", [])]
    if len(names) != len(set(names)):
        raise ConfigError(f"{path}: two sensors share a name")
    sensors = tuple(Sensor(s["name"], s["resource"], tuple(s["argv"]), float(s.get("timeout", 2.0)),
                           float(s.get("every", 10.0))) for s in doc.get("sensor", []))  # fmt: skip
    relax = doc.get("relax", {})
    weights = {name: Fraction(str(w)) for name, w in relax.get("weights", {}).items()}  # 0.1 as written: 1/10
    if any(w <= 0 for w in weights.values()):
        raise ConfigError(f"{path}: relax.weights: a weight is more than 0")
    return Config(dict(doc.get("limits", {})), dict(doc.get("enactor", {})), sensors, weights,
                  frozenset(relax.get("fixed", [])))  # fmt: skip
