"""``catc relax``'s default never adds unlike units at weight 1 (issue 26): requirements of
different units are weighed by their relative change, and with no scale to take one of,
the answer says so and asks for ``--weights``.  The model: tests/shop_models.py (20 W of the
30 W a lamp needs, 900 USD of the 1,000 USD another costs); every figure is derived by hand."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

from click.testing import CliRunner
from shop_models import SHOP, shop

from catc.api import loads, relax_weights
from catc.interfaces.cli import main


def relax(tmp_path: Path, text: str, *args: str):
    path = tmp_path / "shop.cat"
    path.write_text(text, encoding="utf-8")
    return CliRunner().invoke(main, ["relax", str(path), *args], catch_exceptions=False)


def answer(tmp_path: Path, text: str, *args: str) -> dict:
    res = relax(tmp_path, text, *args, "--json")
    assert res.exit_code == 0, res.output
    return json.loads(res.output)


def test_unlike_units_are_weighed_by_relative_change(tmp_path: Path):
    # power: +10 W (or the lamp's (>= power 30) weakened by 10), scale 20 W: 1/2;
    # budget: +100 USD (or (>= budget 1000) weakened by 100), scale 900 USD: 1/9 — the least
    doc = answer(tmp_path, SHOP)
    assert Fraction(doc["cost"]) == Fraction(1, 9)
    (only,) = doc["relaxations"]
    assert only["label"] in ("init/budget", "buy-lamp/pre/1") and Fraction(only["weight"]) == Fraction(1, 900)


def test_the_weights_of_the_default_per_requirement():
    inst = loads({"shop.cat": SHOP}, "shop.cat").instance
    weights, why = relax_weights(inst)
    assert why is None
    assert weights["init/power"] == Fraction(1, 20) and weights["init/budget"] == Fraction(1, 900)
    pre = {label: w for label, w in weights.items() if not label.startswith("init/")}
    assert sorted(pre.values()) == [Fraction(1, 900), Fraction(1, 20)]  # each precondition: its resource's scale


def test_given_weights_are_kept_and_one_unit_left_weighs_1(tmp_path: Path):
    # both said: 1 W counts as 1 USD, so +10 W (10) beats +100 USD (100), as before the default
    doc = answer(tmp_path, SHOP, "--only", "init/", "--weights", "power=1", "--weights", "budget=1")
    assert Fraction(doc["cost"]) == 10 and doc["relaxations"][0]["label"] == "init/power"
    # power said (1/100 per W); budget, the one unit left, 1 per USD: 10 × 1/100 = 1/10 < 100
    doc = answer(tmp_path, SHOP, "--only", "init/", "--weights", "power=1/100")
    assert Fraction(doc["cost"]) == Fraction(1, 10) and doc["relaxations"][0]["label"] == "init/power"


def test_a_zero_initial_value_is_scaled_by_its_bounds(tmp_path: Path):
    # 0 W of at most 50 W: +30 W weighs 30/50 = 3/5 > +100 USD at 1/9
    doc = answer(tmp_path, shop(power="0", power_bounds="(0 50)"), "--only", "init/")
    assert Fraction(doc["cost"]) == Fraction(1, 9) and doc["relaxations"][0]["label"] == "init/budget"
    # with 100 USD: +900 USD weighs 900/100 = 9 > +30 W at 3/5
    doc = answer(tmp_path, shop(power="0", power_bounds="(0 50)", budget="100"), "--only", "init/")
    assert Fraction(doc["cost"]) == Fraction(3, 5) and doc["relaxations"][0]["label"] == "init/power"


def test_a_zero_initial_value_is_scaled_by_the_constant_it_is_compared_with(tmp_path: Path):
    # 0 W, unbounded above, compared with 30 W: +30 W weighs 30/30 = 1 > +100 USD at 1/9
    inst = loads({"shop.cat": shop(power="0")}, "shop.cat").instance
    weights, why = relax_weights(inst, ["init/"])
    assert why is None and weights == {"init/power": Fraction(1, 30), "init/budget": Fraction(1, 900)}


def test_no_scale_is_an_input_error_asking_for_weights(tmp_path: Path):
    # 0 W, unbounded, compared only with the resource need (30 W): no relative change of power
    text = shop(power="0", need="30")
    res = relax(tmp_path, text, "--only", "init/")
    assert res.exit_code == 2
    assert "different units (USD, W)" in res.output and "init/power has no scale" in res.output
    assert "--weights" in res.output
    # power weighed 1/30 per W: +30 W is 1; need −30 W of 30 is 1; +100 USD of 900 is 1/9: the least
    doc = answer(tmp_path, text, "--only", "init/", "--weights", "power=1/30")
    assert Fraction(doc["cost"]) == Fraction(1, 9) and doc["relaxations"][0]["label"] == "init/budget"
    # with the budget fixed: 1 for either W, never 30 USD-equivalents
    doc = answer(tmp_path, text, "--only", "init/", "--weights", "power=1/30", "--fixed", "budget")
    assert Fraction(doc["cost"]) == 1


def test_one_unit_keeps_weight_1(tmp_path: Path):
    both_w = SHOP.replace(":unit USD", ":unit W")  # one unit: no conversion needed
    inst = loads({"shop.cat": both_w}, "shop.cat").instance
    weights, why = relax_weights(inst)
    assert why is None and weights == {}


def test_the_coarse_battery_is_raised_by_its_relative_change():
    """examples/navigation/coarse.cat: Wh (battery 22.7, reserve 10) and m (travelled 0, goal
    9.65).  One move of 9.65 m needs 5 + 0.8 × 9.65 = 12.72 Wh above the reserve: 1/50 Wh
    short.  Raising the battery by 1/50 weighs (1/50)/22.7 = 1/1135; lowering the reserve
    (1/50)/10 = 1/500; the goal is 9.65 − 7.7/0.8 = 1/40 m short, (1/40)/9.65 = 1/386.
    (At weight 1 for every unit, the answer was the reserve −1/50 Wh.)"""
    coarse = Path(__file__).resolve().parent.parent / "examples" / "navigation" / "coarse.cat"
    res = CliRunner().invoke(main, ["relax", str(coarse), "--json"], catch_exceptions=False)
    doc = json.loads(res.output)
    assert res.exit_code == 0 and Fraction(doc["cost"]) == Fraction(1, 1135)
