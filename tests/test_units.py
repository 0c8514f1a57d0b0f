"""Units and dimensions (docs/language.md §Units): exact conversions, the checker's rules, the
encoding of literals with units, and the answers' units.

Expected factors are computed by hand from the SI and IEC definitions (1 GB = 10^9 B,
1 GiB = 2^30 B, 1 Wh = 3600 J, 1 mile = 1609.344 m), never read from pint.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import ROOT, run_catc

from catc.api import loads
from catc.frontend import units
from catc.frontend.formatter import format_text

DOMAIN = """\
(define (domain u)
  (:requirements :numeric :free-parameters)
  (:resources
    (ram real :unit GB :bounds (0 *))
    (disk real :unit MB :bounds (0 *))
    (battery real :unit Wh :bounds (0 *))
    (budget real :unit USD))
  (:morphism load
    :uses 1
    :parameters ((need real :unit MiB :bounds (0 4096)))
    :precondition (and (>= ram RAM-NEED) (>= budget 10))
    :effect (and (decrease ram need) (decrease battery 1500 mWh) (decrease budget 250 US_cent))))
"""

PROBLEM = """\
(define (problem p) (:domain u)
  (:init (= ram 16) (= disk 2 GiB) (= battery 100) (= budget 30))
  (:goal (= ram 15)))
"""


@pytest.mark.parametrize(
    ("source", "target", "factor"),
    [
        ("MB", "GB", Fraction(1, 1000)),
        ("GB", "MB", Fraction(1000)),
        ("GiB", "GB", Fraction(2**30, 10**9)),
        ("MiB", "GB", Fraction(2**20, 10**9)),
        ("KiB", "B", Fraction(1024)),
        ("kB", "B", Fraction(1000)),
        ("byte", "bit", Fraction(8)),
        ("Wh", "J", Fraction(3600)),
        ("mWh", "Wh", Fraction(1, 1000)),
        ("kWh", "Wh", Fraction(1000)),
        ("mAh", "A*s", Fraction(36, 10)),
        ("mi", "m", Fraction(1609344, 1000)),
        ("km/h", "m/s", Fraction(1000, 3600)),
        ("ms", "s", Fraction(1, 1000)),
        ("h", "min", Fraction(60)),
        ("US_cent", "USD", Fraction(1, 100)),
        ("euro_cent", "EUR", Fraction(1, 100)),
        ("percent", "dimensionless", Fraction(1, 100)),
        ("MP", "px", Fraction(10**6)),
        ("TFLOPS", "FLOPS", Fraction(10**12)),
        ("W*h", "Wh", Fraction(1)),
    ],
)
def test_conversion_factors_are_exact_rationals(source, target, factor):
    got = units.factor(units.parse(source), units.parse(target))
    assert type(got) is Fraction and got == factor


def test_gb_is_decimal_and_gib_binary():
    assert units.factor(units.parse("GB"), units.parse("B")) == 10**9
    assert units.factor(units.parse("GiB"), units.parse("B")) == 2**30
    # 512 MB is exactly half of 1.024 GB, and 512 MiB exactly half of 1 GiB
    assert Fraction(512) * units.factor(units.parse("MB"), units.parse("GB")) == Fraction(64, 125)
    assert Fraction(512) * units.factor(units.parse("MiB"), units.parse("GiB")) == Fraction(1, 2)


@pytest.mark.parametrize(
    ("text", "dimension"),
    [
        ("GB", "information"),
        ("USD", "currency"),
        ("EUR", "currency EUR"),
        ("Wh", "energy"),
        ("W", "power"),
        ("m/s", "velocity"),
        ("Hz", "frequency"),
        ("px", "image"),
        ("fps", "frames/time"),
        ("count", "dimensionless"),
        ("m", "length"),
    ],
)
def test_dimension_names(text, dimension):
    assert units.parse(text).dimension == dimension


def test_currencies_do_not_convert_into_each_other():
    assert not units.parse("USD").same_dimension(units.parse("EUR"))


@pytest.mark.parametrize("text", ["degC", "degF", "GBs", "parsecs_per_fortnight_x"])
def test_unknown_and_offset_units_are_refused(text):
    with pytest.raises(units.UnitError):
        units.parse(text)


def _write(tmp_path: Path, domain: str, problem: str = PROBLEM) -> tuple[Path, Path]:
    d, p = tmp_path / "d.cat", tmp_path / "p.cat"
    d.write_text(domain)
    p.write_text(problem)
    return d, p


def _smt(tmp_path: Path, domain: str) -> str:
    d, p = _write(tmp_path, domain)
    res = run_catc("compile", str(d), str(p))
    assert res.exit_code == 0, res.output
    return "\n".join(line for line in res.stdout.splitlines() if not line.startswith(";"))


def test_a_literal_with_a_unit_encodes_as_the_converted_number(tmp_path):
    """``(>= ram 512 MB)`` with ram in GB is the same SMT-LIB2 as ``(>= ram 64/125)``: the
    conversion happens at compile time, the encoding is unchanged."""
    with_unit = _smt(tmp_path, DOMAIN.replace("RAM-NEED", "512 MB"))
    by_hand = _smt(tmp_path, DOMAIN.replace("RAM-NEED", "(/ 64 125)").replace("1500 mWh", "1.5"))
    assert "(/ 64.0 125.0)" in with_unit
    by_hand = by_hand.replace("(/ (to_real 64) (to_real 125))", "(/ 64.0 125.0)")  # how a quotient prints
    assert with_unit.replace("(- |s.battery", "(- |s.battery") == by_hand or _same_up_to_quotient(with_unit, by_hand)


def _same_up_to_quotient(a: str, b: str) -> bool:
    """Equal once every numeral is read as a rational (``1.5`` and ``(/ 3.0 2.0)``)."""

    def norm(text: str) -> str:
        text = re.sub(r"\(/ (\d+)\.0 (\d+)\.0\)", lambda m: str(Fraction(int(m[1]), int(m[2]))), text)
        text = re.sub(r"(\d+\.\d+)", lambda m: str(Fraction(m[1])), text)
        return re.sub(r"\(/ \(to_real (\d+)\) \(to_real (\d+)\)\)", lambda m: str(Fraction(int(m[1]), int(m[2]))), text)

    return norm(a) == norm(b)


def test_solving_with_units_gives_values_in_the_declared_units(tmp_path):
    d, p = _write(tmp_path, DOMAIN.replace("RAM-NEED", "512 MB"))
    model = loads({str(d): d.read_text(), str(p): p.read_text()}, str(p))
    answer = model.solve()
    assert answer.status.value == "sat"
    final = answer.states[-1]
    # ram 16 GB − need = 15 GB: need = 1 GB = 10^9 / 2^20 MiB
    (step,) = answer.plan.steps
    assert step[0].params["need"] == Fraction(10**9, 2**20)
    assert final["ram"] == 15
    assert final["battery"] == Fraction(985, 10)  # 100 Wh − 1500 mWh
    assert final["budget"] == Fraction(55, 2)  # 30 USD − 250 cents
    assert final["disk"] == Fraction(2**31, 10**6)  # 2 GiB in MB, untouched
    doc = model.to_json(answer)
    assert doc["units"] == {"ram": "GB", "disk": "MB", "battery": "Wh", "budget": "USD"}
    assert doc["parameter_units"] == {"load": {"need": "MiB"}}
    res = run_catc("solve", str(d), str(p))
    assert "need = " in res.stdout and " MiB" in res.stdout and "98.5 Wh" in res.stdout


def test_resources_of_one_dimension_in_different_units_are_compared_by_value(tmp_path):
    """1 GB against 999 MB and 1001 MB: the comparison scales by the exact factor (compared
    as bare numbers, 1 >= 999 would be false)."""
    domain = DOMAIN.replace("RAM-NEED", "0")
    for disk, status in (("999", "sat"), ("1001", "unsat")):
        problem = f"(define (problem p) (:domain u) (:init (= ram 1) (= disk {disk}) (= battery 100) (= budget 30))\n  (:goal (>= ram disk)) (:horizon 0))\n"
        d, p = _write(tmp_path, domain, problem)
        assert loads({str(d): domain, str(p): problem}, str(p)).solve().status.value == status


def test_the_mismatch_is_located_and_names_both_dimensions(tmp_path):
    d, p = _write(tmp_path, DOMAIN.replace("RAM-NEED", "budget"))
    res = run_catc("check", str(d), str(p))
    assert res.exit_code == 1  # errors in the model (docs/cli.md)
    assert f"{d}:11:32: error[E0311]: cannot compare ram [GB: information] with budget [USD: currency]" in res.output


def test_declared_names_win_over_units(tmp_path):
    """A parameter named ``m`` after a number is the parameter, not the metre."""
    domain = DOMAIN.replace("RAM-NEED", "(* 2 m)").replace(
        "((need real :unit MiB :bounds (0 4096)))", "((need real :unit MiB :bounds (0 4096)) (m real :bounds (0 1)))"
    )
    d, p = _write(tmp_path, domain)
    res = run_catc("check", str(d), str(p))
    assert res.exit_code == 0, res.output


def test_the_formatter_never_separates_a_number_from_its_unit():
    long = " ".join(f"(>= battery {i}.5 Wh)" for i in range(12))
    text = f"(define (domain f) (:requirements :numeric) (:resources (battery real :unit Wh))\n  (:morphism m :precondition (and {long}) :effect (decrease battery 1.5 Wh)))\n"
    out = format_text(text)
    assert out.count("\n") > 5  # the list broke
    assert len(re.findall(r"\d\.5 Wh", out)) == 13
    assert not re.search(r"\d\s*\n\s*Wh", out)
    long_sum = "(+ " + " ".join(f"{i} Wh" for i in range(40)) + ")"
    out = format_text(text.replace("(>= battery 0.5 Wh)", f"(>= battery {long_sum})"))
    assert not re.search(r"\d\s*\n\s*Wh", out) and len(re.findall(r"(?<![\w.])\d+(?:\.\d+)? Wh\b", out)) == 40 + 11 + 1


def test_json_documents_carry_units_only_additively(tmp_path):
    d, p = _write(tmp_path, DOMAIN.replace("RAM-NEED", "512 MB"))
    doc = json.loads(run_catc("solve", str(d), str(p), "--json").stdout)
    assert doc["final_state"]["ram"] == 15 and doc["units"]["ram"] == "GB"


def test_the_index_is_what_pint_says():
    """The generated index agrees with pint for every unit in it (units.py --check)."""
    assert units.main([]) == 0
    from catc.frontend._unit_index import UNITS

    for text, (dims, scale) in UNITS.items():
        got_dims, got_scale = units.read_with_pint(text)
        assert got_dims == tuple((k, Fraction(v)) for k, v in dims) and got_scale == Fraction(scale), text


def test_only_a_unit_outside_the_index_imports_pint(tmp_path):
    """``furlong`` is pint's (660 US survey feet of 1200/3937 m each) but not in the index: pint is imported to read it;
    the example's own units (GB) are read from the index without pint."""
    folder = tmp_path / "detection"
    shutil.copytree(ROOT / "examples" / "detection", folder)
    domain = folder / "domain.cat"
    domain.write_text(domain.read_text().replace("(:resources", "(:resources\n    (odometer real :unit furlong)"))
    problem = folder / "person.cat"
    problem.write_text(problem.read_text().replace("(:init", "(:init (= odometer 0)"))
    probe = (
        "import sys\n"
        "from catc.frontend.session import check_files\n"
        "from catgrammar.diagnostics import Diagnostics\n"
        "d = Diagnostics()\n"
        "check_files([sys.argv[1]], d)\n"
        "print(len(d.errors), 'pint' in sys.modules)\n"
    )
    for path, pint_loaded in ((ROOT / "examples/detection/person.cat", "False"), (folder / "person.cat", "True")):
        proc = subprocess.run([sys.executable, "-c", probe, str(path)], cwd=ROOT, capture_output=True, text=True)
        assert proc.stdout.split() == ["0", pint_loaded], proc.stderr
    assert units.factor(units.parse("furlong"), units.parse("m")) == 660 * Fraction(1200, 3937)


def test_without_pint_the_usual_units_work_and_others_name_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pint", None)  # `import pint` raises ImportError
    units.registry.cache_clear()
    units.parse.cache_clear()
    try:
        assert units.factor(units.parse("MB"), units.parse("GB")) == Fraction(1, 1000)
        with pytest.raises(units.UnitError, match=r"pip install 'catc-lang\[units\]'"):
            units.parse("furlong")
    finally:
        units.registry.cache_clear()
        units.parse.cache_clear()


def test_a_relaxed_initial_value_carries_its_unit():
    """examples/lifelong/budget-cut: the budget (USD) is raised by 19860 (docs/cli.md)."""
    doc = json.loads(run_catc("relax", str(ROOT / "examples/lifelong/budget-cut.cat"), "--json").stdout)
    (budget,) = [r for r in doc["relaxations"] if r["label"] == "init/budget"]
    assert budget["unit"] == "USD" and budget["delta"] == 19860


def test_costs_in_one_dimension_add_up_in_the_first_costs_unit(tmp_path):
    """3 USD + 250 cents = 5.5 USD: the second cost is converted before (total-cost) adds."""
    path = tmp_path / "cost.cat"
    path.write_text(
        "(define (domain c) (:requirements :numeric :optimization)\n"
        "  (:resources (n int :unit count))\n"
        "  (:morphism a :uses 1 :cost (* 3 USD) :effect (increase n 1))\n"
        "  (:morphism b :uses 1 :cost (* 250 US_cent) :effect (increase n 1)))\n"
        "(define (problem p) (:domain c) (:init (= n 0)) (:goal (>= n 2)) (:metric minimize (total-cost)))\n"
    )
    doc = json.loads(run_catc("optimize", str(path), "--json").stdout)
    assert doc["objectives"][0]["value"] == "11/2"


@pytest.mark.parametrize("cache", ["off", "fresh folder", "same folder again"])
def test_pint_reads_information_units_however_its_registry_was_built(monkeypatch, tmp_path_factory, cache):
    """Issue 28: pint's registry built from its definitions (no disk cache, or an empty one)
    kept `bit` dimensionless after units.txt made it information, so kB → bit failed; it
    passed only with an entry in ~/.cache/pint (shared by every process).  1 kB = 8000 bit
    (decimal prefix, 8 bits a byte), whatever the cache."""
    folder = tmp_path_factory.getbasetemp() / "pint-cache"
    folder.mkdir(exist_ok=True)
    monkeypatch.setenv("CATC_PINT_CACHE", "off" if cache == "off" else str(folder))
    units.registry.cache_clear()
    try:
        assert units.read_with_pint("kB") == ((("[information]", Fraction(1)),), Fraction(8000))
        assert units.read_with_pint("MiB") == ((("[information]", Fraction(1)),), Fraction(8 * 2**20))
    finally:
        units.registry.cache_clear()
