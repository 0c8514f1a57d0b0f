"""``catc relax --fixed RESOURCE`` (issue 26): a resource whose initial value nobody can change
(a drone's battery) is never part of a restoration."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from catc.interfaces.cli import main

# the hall is lit by a lamp that needs 30 W (there are 20) or one bought for 1,000 USD (900)
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


@pytest.fixture
def shop(tmp_path: Path) -> Path:
    path = tmp_path / "shop.cat"
    path.write_text(SHOP, encoding="utf-8")
    return path


def relax(*args: str):
    return CliRunner().invoke(main, ["relax", *args], catch_exceptions=False)


def test_a_fixed_resource_is_never_restored(shop: Path):
    free = relax(str(shop), "--only", "init/")
    assert free.exit_code == 0 and "power: +10 W" in free.output  # 10 < 100: the power
    held = relax(str(shop), "--only", "init/", "--fixed", "power")
    assert held.exit_code == 0 and "budget: +100 USD" in held.output and "power:" not in held.output


def test_everything_fixed_leaves_no_restoration(shop: Path):
    res = relax(str(shop), "--only", "init/", "--fixed", "power", "--fixed", "budget")
    assert res.exit_code == 1 and "UNSAT" in res.output


def test_a_fixed_name_that_is_no_resource_is_an_input_error(shop: Path):
    res = CliRunner().invoke(main, ["relax", str(shop), "--fixed", "pwr"])
    assert res.exit_code == 2 and "--fixed 'pwr'" in res.output and "did you mean 'power'" in res.output
