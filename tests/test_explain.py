"""``catc explain CODE`` says what every code means and how to fix it (issue 29: it printed
only the one-line summary for 45 of the 96 codes, E0311 among them).

Each code of ``catgrammar.codes.CODES`` has a ``### `CODE``` subsection in docs/errors.md,
in the section whose table lists it; ``catc explain`` prints it after the summary."""

from __future__ import annotations

import re

import pytest
from conftest import ROOT, run_catc

from catgrammar.codes import CODES

ERRORS_MD = (ROOT / "docs" / "errors.md").read_text(encoding="utf-8")


def _subsections() -> dict[str, tuple[str, str]]:
    """Read by hand, not with docgen: ``{code: (the title of the ## section it is under, its text)}``."""
    out: dict[str, tuple[str, str]] = {}
    for section in re.split(r"^## ", ERRORS_MD, flags=re.M)[1:]:
        title = section.partition("\n")[0]
        for block in re.split(r"^### ", section, flags=re.M)[1:]:
            head, _, body = block.partition("\n")
            m = re.fullmatch(r"`([EW]\d{4})`", head.strip())
            if m:
                assert m.group(1) not in out, f"{m.group(1)} is explained twice"
                out[m.group(1)] = (title, body.strip())
    return out


def _section_listing(code: str) -> str:
    """The title of the ## section whose table has ``code``'s row."""
    for section in re.split(r"^## ", ERRORS_MD, flags=re.M)[1:]:
        if re.search(rf"^\| `{code}` \|", section, flags=re.M):
            return section.partition("\n")[0]
    raise AssertionError(f"{code} has no row in docs/errors.md")


SUBSECTIONS = _subsections()


def test_every_code_has_an_explanation_in_its_section():
    missing = [code for code in CODES if code not in SUBSECTIONS]
    assert not missing, f"docs/errors.md has no ### subsection for {len(missing)} codes: {missing}"
    misplaced = [code for code, (title, _) in SUBSECTIONS.items() if title != _section_listing(code)]
    assert not misplaced, f"explained outside the section that lists them: {misplaced}"
    assert set(SUBSECTIONS) <= set(CODES), set(SUBSECTIONS) - set(CODES)


@pytest.mark.parametrize("code", list(CODES))
def test_an_explanation_is_short_and_shows_an_example(code):
    _, text = SUBSECTIONS.get(code, ("", ""))
    lines = text.splitlines()
    assert 3 <= len(lines) <= 8, f"{code}: {len(lines)} lines; an explanation is 3 to 8 lines"
    assert "`" in text, f"{code}: quotes no fragment, command or message"
    assert text.strip() != CODES[code].summary


@pytest.mark.parametrize("code", list(CODES))
def test_catc_explain_prints_more_than_the_summary(code):
    res = run_catc("explain", code)
    assert res.exit_code == 0, res.output
    info = CODES[code]
    shown = res.stdout.splitlines()
    assert shown[0].startswith(f"{code} ({info.name}, ")
    assert shown[2] == info.summary
    # what is printed besides the header, the summary and the closing pointer to docs/errors.md
    rest = [line for line in shown[3:] if line.strip() and not line.startswith("Every code: docs/errors.md")]
    assert rest, f"catc explain {code} prints only the one-line summary"
    _, text = SUBSECTIONS.get(code, ("", ""))
    assert text and text in res.stdout, f"catc explain {code} does not print its explanation"


def test_e0311_says_what_it_means_and_how_to_fix_it():
    """The code issue 29 names: the explanation relates the comparison, the dimensions and the fix."""
    out = run_catc("explain", "unit-mismatch-compare").stdout
    assert "(>= ram budget)" in out and "dimension" in out and ":unit" in out
