"""Shared models of the relaxation tests: a hall lit by a lamp that needs 30 W (there are
20) or by one bought for 1,000 USD (there are 900) — two resources of unlike units, used by
``catc relax`` (tests/test_relax_fixed.py, tests/test_relax_units.py) and by the runtime's
``[relax]`` policy (tests/test_runtime_rate.py)."""

from __future__ import annotations

SHOP = """\
(define (domain shop)
  (:requirements :numeric :sets)
  (:sorts room - symbol)
  (:constants hall - room)
  (:resources
    (power real :unit W :bounds (0 *))
    (budget real :unit USD :bounds (0 *))
    (lit (set room)))
  (:morphism lamp :kind software :uses 1
    :precondition (>= power 30)
    :effect (add lit hall))
  (:morphism buy-lamp :kind software :uses 1
    :precondition (>= budget 1000)
    :effect (add lit hall)))

(define (problem light)
  (:domain shop)
  (:init (= power 20) (= budget 900))
  (:goal (member hall lit))
  (:horizon 1))
"""


def shop(power: str = "20", budget: str = "900", power_bounds: str = "(0 *)", need: str | None = None) -> str:
    """SHOP with other initial values or bounds of power; ``need``: the lamp needs the W of a
    resource ``need`` (initial value ``need``) instead of the constant 30 W."""
    text = (
        SHOP.replace("(= power 20)", f"(= power {power})")
        .replace("(= budget 900)", f"(= budget {budget})")
        .replace("(power real :unit W :bounds (0 *))", f"(power real :unit W :bounds {power_bounds})")
    )
    if need is not None:
        text = text.replace("(budget real", "(need real :unit W :bounds (0 *))\n    (budget real")
        text = text.replace("(>= power 30)", "(>= power need)").replace("(:init ", f"(:init (= need {need}) ")
    return text
