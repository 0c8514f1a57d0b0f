"""The runtime's import contract is an allow-list: of catc, catrt imports only ``catc.api``,
the IR (``catc.ir``) and plans (``catc.semantics.plan``); of the language only its
diagnostics (and their spans), codes, terminal text and limits (it parses no ``.cat`` text itself: ``catc.api.outline``
and ``catc.api.tokens`` do).

import-linter states contracts as forbidden lists, so pyproject.toml forbids the complement;
these tests say the complement is complete (a module added to catc or catgrammar is forbidden
until it is allowed here) and that catrt's own imports — read from its source, ``TYPE_CHECKING``
and function-local ones included — are all allowed."""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONTRACT = "the runtime imports of catc only catc.api, catc.ir and catc.semantics.plan"

#: What catrt may import of catc and catgrammar (a package: with its submodules).
ALLOWED = {"catc", "catc.api", "catc.ir", "catc.semantics", "catc.semantics.plan",
           "catgrammar", "catgrammar.diagnostics", "catgrammar.codes", "catgrammar.terminal", "catgrammar.span",
           "catgrammar.limits", "catgrammar.deadlines"}  # fmt: skip
PACKAGES = {"catc.ir"}  # allowed with everything below them


def allowed(module: str) -> bool:
    return module in ALLOWED or any(module.startswith(p + ".") for p in PACKAGES)


def modules(root: Path, package: str) -> set[str]:
    """Every module and package below ``root`` (the folder of ``package``)."""
    out = set()
    for path in root.rglob("*.py"):
        parts = path.relative_to(root).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out.add(".".join((package, *parts)))
    return out


def contract() -> dict:
    doc = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    found = [c for c in doc["tool"]["importlinter"]["contracts"] if c["name"].startswith(CONTRACT)]
    assert len(found) == 1
    return found[0]


def test_the_contract_forbids_everything_not_allowed():
    c = contract()
    assert c["source_modules"] == ["catrt"] and c["type"] == "forbidden"
    forbidden = set(c["forbidden_modules"])
    everything = modules(ROOT / "compiler" / "catc", "catc") | modules(ROOT / "catgrammar", "catgrammar")
    for module in sorted(everything):
        covered = any(module == f or module.startswith(f + ".") for f in forbidden)
        assert covered != allowed(module), f"{module}: {'allowed and forbidden' if covered else 'neither'}"


def test_catrt_imports_only_what_is_allowed():
    everything = modules(ROOT / "compiler" / "catc", "catc") | modules(ROOT / "catgrammar", "catgrammar")
    seen: dict[str, list[str]] = {}
    for path in sorted((ROOT / "runtime" / "catrt").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names: list[str] = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                # ``from catc import ir`` imports the module catc.ir (``__version__`` is a name)
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names
                                         if f"{node.module}.{a.name}" in everything]  # fmt: skip
            for name in names:
                if name.split(".")[0] in ("catc", "catgrammar"):
                    seen.setdefault(name, []).append(path.name)
    assert seen, "no import of catc found: the test reads the wrong files"
    assert {m: where for m, where in seen.items() if not allowed(m)} == {}
