"""``catc.api.loads(..., cache=text_cache())``: a model checked again with only its problem
changed (the runtime's step) parses and checks only the problem; a changed domain is
parsed and checked anew, and the answers equal those of a check without the cache."""

from __future__ import annotations

import pytest
from shop_models import SHOP

import catgrammar.parser
from catc.api import CatError, loads, text_cache
from catc.frontend import workspace

DOMAIN, PROBLEM = SHOP.split("\n\n(define (problem")
PROBLEM = "(define (problem" + PROBLEM


def files(domain: str = DOMAIN, problem: str = PROBLEM) -> dict[str, str]:
    return {"m/domain.cat": domain, "m/problem.cat": problem}


@pytest.fixture
def parsed(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The paths parsed, in order."""
    seen: list[str] = []
    real = catgrammar.parser.parse_source

    def counting(src, diags, cancelled=None):
        seen.append(src.path)
        return real(src, diags, cancelled)

    monkeypatch.setattr(workspace, "parse_source", counting)
    return seen


def test_a_changed_problem_reuses_the_parsed_and_checked_domain(parsed: list[str]):
    cache = text_cache()
    first = loads(files(), "m/problem.cat", cache=cache).instance
    assert parsed == ["m/domain.cat", "m/problem.cat"]
    parsed.clear()
    second = loads(files(problem=PROBLEM.replace("(= power 20)", "(= power 25)")), "m/problem.cat", cache=cache)
    assert parsed == ["m/problem.cat"]  # the domain's text is unchanged
    assert second.instance.domain is first.domain
    assert second.instance.problem.init["power"].value.value == 25


def test_a_changed_domain_is_checked_anew(parsed: list[str]):
    cache = text_cache()
    loads(files(), "m/problem.cat", cache=cache)
    parsed.clear()
    cheaper = DOMAIN.replace("(>= budget 1000)", "(>= budget 800)")
    inst = loads(files(domain=cheaper), "m/problem.cat", cache=cache).instance
    assert parsed == ["m/domain.cat"]  # the problem's text is unchanged: parsed once, checked again
    (pre,) = inst.morphisms["buy-lamp"].pre
    assert "800" in str(pre.expr)


def test_errors_are_reported_with_the_cache_as_without(parsed: list[str]):
    cache = text_cache()
    loads(files(), "m/problem.cat", cache=cache)
    bad = files(problem=PROBLEM.replace("(= power 20)", "(= powr 20)"))
    with pytest.raises(CatError) as cached:
        loads(bad, "m/problem.cat", cache=cache)
    with pytest.raises(CatError) as plain:
        loads(bad, "m/problem.cat")
    assert str(cached.value) == str(plain.value) and "powr" in str(plain.value)


def test_the_cache_keeps_one_version_of_each_file():
    """A long-running runtime checks a new problem text at each step: the cache holds the
    latest of each path, not every text it has seen."""
    cache = text_cache()
    for power in range(20, 30):
        loads(files(problem=PROBLEM.replace("(= power 20)", f"(= power {power})")), "m/problem.cat", cache=cache)
    assert sorted(path.rsplit("/", 2)[-1] for path in cache.files) == ["domain.cat", "problem.cat"]
    assert len(cache.domains) == 1
    loads(files(domain=DOMAIN.replace("(>= budget 1000)", "(>= budget 800)")), "m/problem.cat", cache=cache)
    assert len(cache.domains) == 1  # the replaced file's domain went with it
