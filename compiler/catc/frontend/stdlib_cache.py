"""Checked standard-library domains kept between runs: a command's start-up would otherwise
parse and check the standard library a model imports on every run (``robot-base`` is five
domains, about as long to check as the rest of a small model).

A domain is stored as its checked IR (pickled) in a folder the interfaces name (the user's
cache folder; the library never caches on its own), under a key that changes whenever
anything that made it may have: the text of every standard-library file, and the size and
modification time of every source file of the front end, the IR and the language
(``catc/frontend``, ``catc/ir``, ``catgrammar``) and the Python version.  A file that cannot
be read, written or unpickled is a miss; the domain is then checked as usual.  Only a domain
whose check reported nothing is stored, so a hit reports nothing either.
"""

from __future__ import annotations

import copyreg
import hashlib
import io
import os
import pickle
import sys
from pathlib import Path
from types import MappingProxyType
from typing import Any

from catc import ir

_CODE = [Path(__file__).resolve().parent, Path(ir.__file__).resolve().parent]


def _code_folders() -> list[Path]:
    import catgrammar

    return [*_CODE, Path(catgrammar.__file__).resolve().parent]


def _proxy(d: dict[Any, Any]) -> MappingProxyType[Any, Any]:
    return MappingProxyType(d)


def _reduce_proxy(m: MappingProxyType[Any, Any]) -> tuple[Any, ...]:
    return (_proxy, (dict(m),))


class StdlibCache:
    """The checked domains of the standard library in ``stdlib``, kept in ``folder``."""

    def __init__(self, folder: Path, stdlib: Path) -> None:
        self.folder, self.stdlib = folder, stdlib
        self._key: str | None = None

    @property
    def key(self) -> str:
        if self._key is None:
            digest = hashlib.sha256(sys.version.encode())
            for path in sorted(self.stdlib.glob("*.cat")):
                digest.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
            for folder in _code_folders():
                for path in sorted(folder.glob("*.py")):
                    st = path.stat()
                    digest.update(f"{path.name}:{st.st_size}:{st.st_mtime_ns}\0".encode())
            self._key = digest.hexdigest()[:32]
        return self._key

    def _path(self, name: str) -> Path:
        return self.folder / f"{name}-{self.key}.pickle"

    def get(self, name: str) -> ir.Domain | None:
        try:
            found = pickle.loads(self._path(name).read_bytes())
        except Exception:
            return None
        return found if isinstance(found, ir.Domain) else None

    def put(self, name: str, domain: ir.Domain) -> None:
        buffer = io.BytesIO()
        pickler = pickle.Pickler(buffer, protocol=pickle.HIGHEST_PROTOCOL)
        pickler.dispatch_table = {**copyreg.dispatch_table, MappingProxyType: _reduce_proxy}  # this pickler only
        try:
            pickler.dump(domain)
            self.folder.mkdir(parents=True, exist_ok=True)
            path = self._path(name)
            part = path.with_name(f"{path.name}.{os.getpid()}.part")
            part.write_bytes(buffer.getvalue())
            os.replace(part, path)  # whole or not at all, whoever reads it at the same time
        except (OSError, pickle.PicklingError, TypeError, AttributeError, RecursionError):
            return
