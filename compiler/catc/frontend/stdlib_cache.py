"""Checked standard-library domains kept between runs: a command's start-up would otherwise
parse and check the standard library a model imports on every run (``robot-base`` is five
domains, about as long to check as the rest of a small model).

A domain is stored as its checked IR (pickled) in a folder the interfaces name (the user's
cache folder; the library never caches on its own), with the key it was made under: the
size and modification time (ns) of every standard-library file and of every file (modules
and their data) of the front end, the IR and the language (``catc/frontend``, ``catc/ir``,
``catgrammar``), and the Python version.  A file is read back only when its key is the key now (compared whole,
not by a digest: the file name carries a CRC of it only to keep entries apart), so an edit
to any of them is a miss.  A file that cannot be read, written or unpickled is a miss; the
domain is then checked as usual.  Only a domain whose check reported nothing is stored, so
a hit reports nothing either.  Entries made under other keys are kept — two checkouts or
Python versions sharing the folder would otherwise replace each other's on every run — up to
:data:`KEPT` in all, the most recently written.  (No hashlib: loading OpenSSL costs a command ~3 ms.)
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import zlib
from pathlib import Path
from types import MappingProxyType
from typing import Any

from catc import ir

_CODE = [Path(__file__).resolve().parent, Path(ir.__file__).resolve().parent]
STDLIB_DIR = Path(__file__).resolve().parents[3] / "stdlib_domains"


def stdlib_dir() -> Path:
    """The folder of the standard library domains (installed or in a checkout)."""
    try:
        import stdlib_domains

        return Path(stdlib_domains.__file__).resolve().parent
    except ImportError:  # pragma: no cover - running from a bare checkout
        return STDLIB_DIR


def _code_folders() -> list[Path]:
    import catgrammar

    return [*_CODE, Path(catgrammar.__file__).resolve().parent]


def _proxy(d: dict[Any, Any]) -> MappingProxyType[Any, Any]:
    return MappingProxyType(d)


def _reduce_proxy(m: MappingProxyType[Any, Any]) -> tuple[Any, ...]:
    return (_proxy, (dict(m),))


def dump(buffer: io.BytesIO, value: object) -> None:
    """Pickle ``value`` (checked IR, whose read-only mappings pickle as mappings) into ``buffer``."""
    import copyreg
    import pickle

    pickler = pickle.Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = {**copyreg.dispatch_table, MappingProxyType: _reduce_proxy}  # this pickler only
    pickler.dump(value)


class StdlibCache:
    """The checked domains of the standard library in ``stdlib``, kept in ``folder``."""

    def __init__(self, folder: Path, stdlib: Path) -> None:
        self.folder, self.stdlib = folder, stdlib
        self._key: str | None = None

    @property
    def key(self) -> str:
        if self._key is None:
            parts = [sys.version]
            for folder, pattern in ((self.stdlib, "*.cat"), *((f, "*.*") for f in _code_folders())):
                for path in sorted(folder.glob(pattern)):  # code: the modules and their data (units.txt)
                    st = path.stat()
                    parts.append(f"{path}:{st.st_size}:{st.st_mtime_ns}")
            self._key = "\n".join(parts)
        return self._key

    def _path(self, name: str) -> Path:
        return self.folder / f"{name}-{zlib.crc32(self.key.encode()):08x}.pickle"

    def get(self, name: str) -> ir.Domain | None:
        import pickle

        try:
            key, found = pickle.loads(self._path(name).read_bytes())
        except Exception:
            return None
        return found if key == self.key and isinstance(found, ir.Domain) else None

    def put(self, name: str, domain: ir.Domain) -> None:
        import pickle

        buffer = io.BytesIO()
        try:
            dump(buffer, (self.key, domain))
            self.folder.mkdir(parents=True, exist_ok=True)
            path = self._path(name)
            part = path.with_name(f"{path.name}.{os.getpid()}.part")
            part.write_bytes(buffer.getvalue())
            os.replace(part, path)  # whole or not at all, whoever reads it at the same time
        except (OSError, pickle.PicklingError, TypeError, AttributeError, RecursionError):
            return
        # entries made under other keys stay: two checkouts (or Python versions) sharing the
        # folder would otherwise replace each other's on every run; the folder keeps at most
        # KEPT, the most recently written
        prune(self.folder, KEPT)


#: How many entries a cache folder keeps (the most recently written), as the model cache.
KEPT = 200


def prune(folder: Path, kept: int, prefix: str = "") -> None:
    """Keep at most ``kept`` finished entries (``PREFIX*.pickle``) in ``folder``, dropping the
    least recently written: nothing else ever removes an entry whose key is gone."""
    try:
        entries = [
            (e.stat().st_mtime_ns, e.path)
            for e in os.scandir(folder)
            if e.name.startswith(prefix) and e.name.endswith(".pickle")
        ]
    except OSError:
        return
    for _, path in sorted(entries)[: max(0, len(entries) - kept)]:
        with contextlib.suppress(OSError):  # another process removed it first
            os.unlink(path)
