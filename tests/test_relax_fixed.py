"""``catc relax --fixed RESOURCE`` (issue 26): a resource whose initial value nobody can change
(a drone's battery) is never part of a restoration."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner
from shop_models import SHOP

from catc.interfaces.cli import main


@pytest.fixture
def shop(tmp_path: Path) -> Path:
    path = tmp_path / "shop.cat"
    path.write_text(SHOP, encoding="utf-8")
    return path


def relax(*args: str):
    return CliRunner().invoke(main, ["relax", *args], catch_exceptions=False)


def test_a_fixed_resource_is_never_restored(shop: Path):
    # W and USD weigh by relative change: +10 W of 20 is 1/2, +100 USD of 900 is 1/9
    free = relax(str(shop), "--only", "init/")
    assert free.exit_code == 0 and "budget: +100 USD" in free.output and "power:" not in free.output
    held = relax(str(shop), "--only", "init/", "--fixed", "budget")
    assert held.exit_code == 0 and "power: +10 W" in held.output and "budget:" not in held.output


def test_everything_fixed_leaves_no_restoration(shop: Path):
    res = relax(str(shop), "--only", "init/", "--fixed", "power", "--fixed", "budget")
    assert res.exit_code == 1 and "UNSAT" in res.output


def test_a_fixed_name_that_is_no_resource_is_an_input_error(shop: Path):
    res = CliRunner().invoke(main, ["relax", str(shop), "--fixed", "pwr"])
    assert res.exit_code == 2 and "--fixed 'pwr'" in res.output and "did you mean 'power'" in res.output
