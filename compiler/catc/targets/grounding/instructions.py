"""instructions.md: what a person does to the robot, one numbered step per hardware action.

Markdown is prose, not a structured format: it is written as text, with the solved θ
already in the sentences.  Model text is escaped where Markdown would read it as markup.
"""

from __future__ import annotations

import re

from catc.targets.grounding.resolve import Grounded

_MARKUP = re.compile(r"([\\`*_{}\[\]<>#|!])")


def _md(text: str) -> str:
    """Text as Markdown shows it literally (one line: newlines become spaces)."""
    return _MARKUP.sub(r"\\\1", " ".join(text.split()))


def instructions_md(grounded: Grounded) -> str:
    lines = [f"# Hardware for {_md(grounded.project)}", ""]
    if not grounded.hardware:
        lines += ["No hardware changes: this composition mounts and connects nothing.", ""]
        return "\n".join(lines)
    lines += [f"{len(grounded.hardware)} step{'s' if len(grounded.hardware) != 1 else ''}, in this order.", ""]
    for n, step in enumerate(grounded.hardware, 1):
        lines.append(f"{n}. **{_md(step.morphism)}** (composition step {step.step}): {_md(step.instruction)}")
        if step.parts:
            lines.append(f"   - parts: {', '.join(_md(p) for p in step.parts)}")
        if step.check:
            lines.append(f"   - check: {_md(step.check)}")
    lines.append("")
    return "\n".join(lines)
