"""Checked user models kept between runs of the command line: a query's start-up would
otherwise parse and check the user's model on every run (for a small model, as long as the
solver's own work; docs/benchmarks.md, "Start-up of every query").

An entry is one command line's model — the problem file, the domain file, ``--view``,
``--problem``, the search path and the folder it runs in — stored as its checked instance
(pickled) together with everything the check read:

* the whole text of every file the workspace read (the files it parsed and those it only
  scanned for a domain's header), compared byte for byte — not by size and time, which a
  quick edit of the same length can leave unchanged;
* the ``.cat`` names of every folder a domain could have been looked for in (the folders of
  those files, ``--path`` and ``CATC_PATH``), so a file added beside the model or removed
  from it is a miss;
* the key of :class:`~catc.frontend.stdlib_cache.StdlibCache` (the standard library's files
  and catc's front end, IR and language code, the Python version), and the limits in force.

Only a check that reported nothing at all is stored, so a hit reports nothing either.  A file
that cannot be read, written or unpickled is a miss, and the model is then checked as usual.
Like the standard-library cache, only the command line keeps one (in the user's cache
folder); the library never caches on its own.
"""

from __future__ import annotations

import io
import os
import pickle
import zlib
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from catc import ir
from catc.frontend.stdlib_cache import StdlibCache, dump, prune
from catgrammar import limits

if TYPE_CHECKING:
    from catc.frontend.workspace import Workspace

#: The files and folders a check read: (path, its bytes) and (folder, its .cat names or None).
Reads = tuple[tuple[tuple[str, bytes], ...], tuple[tuple[str, tuple[str, ...] | None], ...]]


def _listing(folder: str) -> tuple[str, ...] | None:
    """The ``.cat`` names of ``folder``, sorted (None: not a folder)."""
    try:
        return tuple(sorted(n for n in os.listdir(folder) if n.endswith(".cat")))
    except OSError:
        return None


def _read(path: str) -> bytes | None:
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        return None


#: How long before a check began a file or folder it read must have been changed last for the
#: check to be kept (nanoseconds): what is read afterwards is then what the check read, even
#: on file systems that keep modification times to 2 s (a racy edit is a miss, never a hit).
SETTLED_NS = 3_000_000_000

#: How many checked models the cache folder keeps (the most recently written).
KEPT = 200


def reads(ws: Workspace, began_ns: int) -> Reads | None:
    """What the check in ``ws`` (begun at ``began_ns``, :func:`time.time_ns`) read: every file
    it loaded or scanned, with its bytes, and every folder a domain could have been looked
    for in, with its ``.cat`` names; None when one of them changed too recently to be sure
    the check saw what is there now (see :data:`SETTLED_NS`) or cannot be read."""
    files = sorted({*ws.files, *ws.scanned()})
    folders = sorted({*(os.path.dirname(f) for f in files), *(os.path.abspath(p) for p in ws.search_paths)})
    for path in (*files, *folders):
        try:
            changed = os.stat(path).st_mtime_ns
        except OSError:
            if path in files:
                return None
            continue  # a folder of the search path that is not there (its listing: None)
        if changed >= began_ns - SETTLED_NS:
            return None
    texts = []
    for f in files:
        data = _read(f)
        if data is None:
            return None
        texts.append((f, data))
    return tuple(texts), tuple((d, _listing(d)) for d in folders)


def _unchanged(found: Reads) -> bool:
    files, folders = found
    return all(_read(f) == data for f, data in files) and all(_listing(d) == names for d, names in folders)


class ModelCache:
    """Checked user models, kept in ``folder``, valid while ``stdlib``'s key holds."""

    def __init__(self, folder: Path, stdlib: StdlibCache) -> None:
        self.folder, self.stdlib = folder, stdlib

    @staticmethod
    def request(
        problem: str,
        domain: str | None,
        view: str | None,
        problem_name: str | None,
        search_paths: Iterable[str],
    ) -> tuple[Any, ...]:
        """What a command line asks for, as far as the checked model depends on it."""
        now = limits.current()
        return (
            os.getcwd(),
            problem,
            domain,
            view,
            problem_name,
            tuple(search_paths),
            tuple(getattr(now, name) for name in limits.Limits.__slots__),
        )

    def _path(self, request: tuple[Any, ...]) -> Path:
        return self.folder / f"model-{zlib.crc32(repr(request).encode()):08x}.pickle"

    def get(self, request: tuple[Any, ...]) -> ir.Instance | None:
        """The instance kept for ``request``, if nothing it was checked from has changed."""
        try:
            key, asked, found, inst = pickle.loads(self._path(request).read_bytes())
        except Exception:
            return None
        if key != self.stdlib.key or asked != request or not isinstance(inst, ir.Instance):
            return None
        return inst if _unchanged(found) else None

    def put(self, request: tuple[Any, ...], found: Reads, inst: ir.Instance) -> None:
        """Keep ``inst``, checked without a word from what ``found`` holds."""
        buffer = io.BytesIO()
        try:
            dump(buffer, (self.stdlib.key, request, found, inst))
            self.folder.mkdir(parents=True, exist_ok=True)
            path = self._path(request)
            part = path.with_name(f"{path.name}.{os.getpid()}.part")
            part.write_bytes(buffer.getvalue())
            os.replace(part, path)  # whole or not at all, whoever reads it at the same time
        except (OSError, pickle.PicklingError, TypeError, AttributeError, RecursionError):
            return
        self._prune()

    def _prune(self) -> None:
        """Keep at most :data:`KEPT` entries, dropping the least recently written: every folder
        a user runs catc in adds its own, and nothing else would ever remove them."""
        prune(self.folder, KEPT, "model-")
