"""Two fuzzers of issue 28 (run from ``benchmarks/fuzz.py --numerals N`` and ``--lsp-framing N``).

* **numerals** — every ``.cat`` seed of the repository with one ASCII number, or one letter of
  a name, replaced by a character of another script: Unicode decimal digits (Arabic-Indic,
  Extended Arabic-Indic, Devanagari, Bengali, Thai, fullwidth, mathematical), other numerals
  (superscripts, circled, Roman numerals, vulgar fractions) and confusable letters (Cyrillic and
  Greek look-alikes of Latin ones).  The oracle: such a file is never accepted — the reader
  refuses it with a located ``E01xx`` diagnostic, never a traceback, and never reads the
  character as a number (finding 5: ``(:horizon ٢)`` checked and solved).
* **lsp-framing** — one ``catc lsp`` process fed random frames: the ``Content-Length``
  header in random case and spacing, extra headers, bodies that are random JSON values, JSON
  cut short (with its true length), requests of unknown and known methods with random
  parameters.  After each frame a probe request must be answered (the server still reads its
  stream: finding 1), and at the end ``shutdown`` and ``exit`` end it with exit code 0 and no
  traceback on standard error.  (A length that does not match its body desynchronises any
  base-protocol reader for good; lengths here are true, their spelling is what varies.)
"""

from __future__ import annotations

import contextlib
import json
import random
import re
import subprocess
import sys
import threading
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

DIGITS = {
    "arabic-indic": "٠١٢٣٤٥٦٧٨٩",
    "extended-arabic-indic": "۰۱۲۳۴۵۶۷۸۹",
    "devanagari": "०१२३४५६७८९",
    "bengali": "০১২৩৪৫৬৭৮৯",
    "thai": "๐๑๒๓๔๕๖๗๘๙",
    "fullwidth": "０１２３４５６７８９",
    "mathematical-bold": "𝟎𝟏𝟐𝟑𝟒𝟓𝟔𝟕𝟖𝟗",
}
NUMERALS = "⁰¹²³⁴⁵⁶⁷⁸⁹₀₁₂①②③ⅠⅡⅢⅣ½¼〇"
CONFUSABLES = {"a": "а", "e": "е", "o": "оο", "p": "р", "c": "с", "x": "х", "i": "іι", "y": "у"}

_NUMBER = re.compile(r"(?<![\w.-])[0-9]+(?:\.[0-9]+)?(?![\w.])")
_NAME_LETTER = re.compile(r"(?<=[(\s])[a-z][a-z0-9-]*")


def seeds() -> list[Path]:
    skip = {"node_modules", ".git", "build", "dist", ".venv", "invalid", "bad", "fuzz"}
    return [p for p in sorted(ROOT.rglob("*.cat")) if not skip & set(p.relative_to(ROOT).parts)]


def mutate(text: str, rng: random.Random) -> tuple[str, str, int] | None:
    """(mutant, class, offset of the changed character) or None when the seed has no target."""
    kind = rng.choice(["digits", "digits", "numerals", "confusables"])
    if kind in ("digits", "numerals"):
        numbers = [m for m in _NUMBER.finditer(text) if not _in_comment(text, m.start())]
        if not numbers:
            return None
        m = rng.choice(numbers)
        i = m.start() + rng.randrange(len(m.group()))
        while not text[i].isdigit():
            i -= 1
        if kind == "digits":
            script = rng.choice(sorted(DIGITS))
            new = DIGITS[script][int(text[i])]
            return text[:i] + new + text[i + 1 :], f"digits/{script}", i
        return text[:i] + rng.choice(NUMERALS) + text[i + 1 :], "numerals", i
    names = [m for m in _NAME_LETTER.finditer(text) if not _in_comment(text, m.start())]
    names = [m for m in names if any(ch in CONFUSABLES for ch in m.group())]
    if not names:
        return None
    m = rng.choice(names)
    at = [m.start() + k for k, ch in enumerate(m.group()) if ch in CONFUSABLES]
    i = rng.choice(at)
    return text[:i] + rng.choice(CONFUSABLES[text[i]]) + text[i + 1 :], "confusables", i


def _in_comment(text: str, i: int) -> bool:
    line = text[text.rfind("\n", 0, i) + 1 : i]
    return ";" in line or '"' in line


def numerals(count: int, seed: int = 0) -> dict:
    """Parse ``count`` mutants in this process; every one must be refused by the reader with a
    located E01xx at the changed character's line, and none may raise."""
    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import parse_source
    from catgrammar.span import Source

    rng = random.Random(seed)
    files = [(p, p.read_text(encoding="utf-8")) for p in seeds()]
    stats: dict[str, int] = {"mutants": 0, "refused": 0, "accepted": 0, "internal errors": 0, "unlocated": 0}
    by_class: dict[str, int] = {}
    failures: list[str] = []
    while stats["mutants"] < count:
        path, text = rng.choice(files)
        made = mutate(text, rng)
        if made is None:
            continue
        mutant, klass, offset = made
        stats["mutants"] += 1
        by_class[klass] = by_class.get(klass, 0) + 1
        diags = Diagnostics()
        try:
            tree = parse_source(Source(str(path), mutant), diags)
        except Exception as exc:  # the oracle counts any exception
            stats["internal errors"] += 1
            failures.append(f"{path}: {klass}: {exc!r}")
            continue
        errors = [d for d in diags if d.severity.value == "error"]
        if tree is not None and not errors:
            stats["accepted"] += 1
            failures.append(f"{path}: {klass} at offset {offset} accepted")
            continue
        stats["refused"] += 1
        line = mutant.count("\n", 0, offset) + 1
        first = errors[0] if errors else None
        if first is None or first.span is None or not first.code.startswith("E01") or first.span.line != line:
            stats["unlocated"] += 1
            failures.append(f"{path}: {klass}: {first.code if first else '-'} at {first.span if first else '-'}")
    return {**stats, "classes": by_class, "failures": failures[:20]}


# ---------------------------------------------------------------- LSP framing

_HEADER_NAMES = [b"Content-Length", b"content-length", b"CONTENT-LENGTH", b"Content-length", b"cOnTeNt-LeNgTh"]


def _json_value(rng: random.Random, depth: int = 0) -> object:
    pick = rng.randrange(8 if depth < 3 else 5)
    if pick == 0:
        return None
    if pick == 1:
        return rng.choice([True, False])
    if pick == 2:
        return rng.choice([0, -1, 2**31, 2**63, 1.5, 1e308])
    if pick == 3:
        return rng.choice(["", "x", "file:///x/%00.cat", "untitled:Untitled-1", "٣", "\u0000"])
    if pick == 4:
        return rng.choice([[], {}])
    if pick == 5:
        return [_json_value(rng, depth + 1) for _ in range(rng.randrange(3))]
    keys = ["jsonrpc", "id", "method", "params", "textDocument", "uri", "position", "line", "character"]
    return {rng.choice(keys): _json_value(rng, depth + 1) for _ in range(rng.randrange(4))}


def _body(rng: random.Random, n: int) -> bytes:
    pick = rng.randrange(5)
    methods = ["textDocument/hover", "textDocument/definition", "workspace/executeCommand", "catc/none", "$/x"]
    if pick == 0:  # any JSON value
        return json.dumps(_json_value(rng)).encode()
    if pick == 1:  # JSON cut short
        whole = json.dumps({"jsonrpc": "2.0", "id": 10_000 + n, "method": "catc/none", "params": {}}).encode()
        return whole[: rng.randrange(1, len(whole))]
    if pick == 2:  # a notification of a known method, random parameters
        return json.dumps({"jsonrpc": "2.0", "method": rng.choice(methods), "params": _json_value(rng)}).encode()
    # a request (answered), random parameters
    return json.dumps(
        {"jsonrpc": "2.0", "id": 10_000 + n, "method": rng.choice(methods), "params": _json_value(rng)}
    ).encode()


def _frame(body: bytes, rng: random.Random) -> bytes:
    name = rng.choice(_HEADER_NAMES)
    colon = rng.choice([b": ", b":", b" : ", b":\t"])
    extra = b"Content-Type: application/vscode-jsonrpc; charset=utf-8\r\n" if rng.random() < 0.3 else b""
    head = name + colon + str(len(body)).encode() + b"\r\n"
    return (extra + head if rng.random() < 0.5 else head + extra) + b"\r\n" + body


def _read(stream) -> dict | None:  # type: ignore[no-untyped-def]
    length = None
    while (line := stream.readline()) not in (b"\r\n", b""):
        name, _, value = line.partition(b":")
        if name.strip().lower() == b"content-length":
            length = int(value)
    return None if length is None else json.loads(stream.read(length))


def lsp_framing(count: int, seed: int = 0) -> dict:
    """One server, ``count`` random frames, a probe after each (see the module's text)."""
    rng = random.Random(seed)
    proc = subprocess.Popen(
        [sys.executable, "-m", "catc", "lsp"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=ROOT,
    )
    guard = threading.Timer(120, proc.kill)  # a server that stopped reading: its probe is lost
    guard.start()
    stats = {"frames": 0, "probes answered": 0, "probes lost": 0}
    stderr: list[bytes] = []
    reader = threading.Thread(target=lambda: stderr.append(proc.stderr.read() if proc.stderr else b""))
    reader.start()
    assert proc.stdin is not None and proc.stdout is not None

    def send(message: dict | bytes) -> None:
        body = message if isinstance(message, bytes) else json.dumps(message).encode()
        try:
            proc.stdin.write(_frame(body, rng))  # type: ignore[union-attr]
            proc.stdin.flush()  # type: ignore[union-attr]
        except OSError:  # the server is gone (killed by the guard): the probes say so
            pass

    def answered(id_: int) -> bool:
        while (m := _read(proc.stdout)) is not None:
            if m.get("id") == id_ and "method" not in m:
                return True
        return False

    init = {"processId": None, "rootUri": ROOT.as_uri(), "capabilities": {}}
    send({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": init})
    alive = answered(1)
    send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
    for n in range(count if alive else 0):
        send(_body(rng, n))
        stats["frames"] += 1
        send({"jsonrpc": "2.0", "id": 100_000 + n, "method": "catc/probe", "params": {}})
        if answered(100_000 + n):
            stats["probes answered"] += 1
        else:
            stats["probes lost"] += 1
            break
    send({"jsonrpc": "2.0", "id": 2, "method": "shutdown"})
    shut = answered(2)
    send({"jsonrpc": "2.0", "method": "exit"})
    with contextlib.suppress(OSError):
        proc.stdin.close()
    code = proc.wait()
    guard.cancel()
    reader.join()
    text = b"".join(stderr).decode("utf-8", "replace")
    return {
        **stats,
        "initialized": alive,
        "shutdown answered": shut,
        "exit code": code,
        "tracebacks on stderr": text.count("Traceback"),
        "stderr tail": text[-600:],
    }


def report(name: str, result: dict) -> int:
    print(f"## {name}")
    for key, value in result.items():
        print(f"- {key}: {value}")
    bad = (
        result.get("accepted", 0) + result.get("internal errors", 0) + result.get("unlocated", 0)
        if name == "numerals"
        else result["probes lost"] + (not result["shutdown answered"]) + (result["exit code"] != 0)
    )
    return 1 if bad else 0
