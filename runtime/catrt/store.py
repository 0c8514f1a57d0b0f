"""The store: one SQLite database in the state folder, the runtime's memory across power cuts.

SQLite in WAL mode with ``synchronous=FULL``: a transaction that committed is on disk, one
that did not is not there at all (SQLite's atomic commit, which rosbag2 and MLflow rely on
too).  Every event is one ``BEGIN IMMEDIATE … COMMIT``; Python's implicit transactions are
off (``isolation_level=None``).  The tables:

* ``meta`` — the schema version, the catc version that made the store, when;
* ``sources`` — the model's files as they were given to ``catrt init``, with their sha256;
* ``state`` — the current model (``catrt.model/1``), the deployed composition A₀ and its
  generation, an enactment in progress, the counters;
* ``journal`` — append-only (triggers refuse UPDATE and DELETE): every event, rejection,
  decision, approval, enactment and sensor run, numbered 1, 2, 3, … without gaps, an
  accepted event's id unique;
* ``approvals`` — requests waiting for a person, and what became of them.

One writer at a time: the writer holds an exclusive ``flock`` on the database file itself
(and on ``STATE/lock``, which names its pid) for its lifetime, released by the kernel when the
process dies, so a crash never leaves it locked and deleting ``STATE/lock`` lets no second
writer in.  Readers (``status``, ``journal``, ``verify``) open the database read-only and need
no lock.

Faults (docs/runtime.md "Faults and what catrt does"): the store is opened ``mode=rw``, so a
missing or 0-byte file is never turned into a new empty database; one that is truncated,
empty or fails SQLite's ``quick_check`` (or holds a journal entry that is not UTF-8 JSON) is
refused for writing (E1014); a read-only folder is said to be one (E1015); a full disk
(SQLITE_FULL, ENOSPC) rolls the transaction back and raises E1016.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import errno
import fcntl
import json
import os
import sqlite3
from collections.abc import Iterator, Mapping
from enum import StrEnum
from pathlib import Path
from typing import Any

SCHEMA_VERSION = 1
DB_NAME = "catrt.sqlite"
LOCK_NAME = "lock"

_SCHEMA = (
    "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
    "CREATE TABLE sources (name TEXT PRIMARY KEY, text TEXT NOT NULL, sha256 TEXT NOT NULL)",
    "CREATE TABLE state (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
    "CREATE TABLE journal (seq INTEGER PRIMARY KEY, at TEXT NOT NULL, kind TEXT NOT NULL, event_id TEXT,"
    " data TEXT NOT NULL)",
    "CREATE UNIQUE INDEX journal_accepted_event ON journal(event_id) WHERE kind = 'event'",
    "CREATE TABLE approvals (id TEXT PRIMARY KEY, seq INTEGER NOT NULL, status TEXT NOT NULL"
    " CHECK (status IN ('pending', 'approved', 'rejected', 'superseded')), proposal TEXT NOT NULL)",
    "CREATE TRIGGER journal_no_update BEFORE UPDATE ON journal"
    " BEGIN SELECT RAISE(ABORT, 'the journal is append-only'); END",
    "CREATE TRIGGER journal_no_delete BEFORE DELETE ON journal"
    " BEGIN SELECT RAISE(ABORT, 'the journal is append-only'); END",
)

#: Migrations from an older schema version: version → the statements that bring it to version + 1.
MIGRATIONS: dict[int, tuple[str, ...]] = {}


class Verdict(StrEnum):
    """Where a request for approval stands (its value is what the store and the journal keep)."""

    PENDING = "pending"  # waits for approve or reject
    APPROVED = "approved"
    REJECTED = "rejected"
    SUPERSEDED = "superseded"  # a later decision replaced it before anyone answered


class StoreError(RuntimeError):
    """The store cannot be used: ``code`` is the diagnostic code (E1003–E1006, E1013–E1016)."""

    def __init__(self, code: str, message: str) -> None:
        super().__init__(message)
        self.code = code


def now() -> str:
    return dt.datetime.now(dt.UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")


def dumps(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False)


class Store:
    """An open store.  ``writer`` stores hold the lock; all writes go through
    :meth:`transaction`."""

    def __init__(self, folder: Path, db: sqlite3.Connection, lock_fd: int | None) -> None:
        self.folder, self.db, self._lock_fd = folder, db, lock_fd

    # ------------------------------------------------------------ opening
    @staticmethod
    def create(folder: Path, sources: Mapping[str, str], state: Mapping[str, Any], catc_version: str) -> Store:
        """A new store in ``folder`` (created; it must not hold one already)."""
        from catrt.model import sha256_text

        folder.mkdir(parents=True, exist_ok=True)
        if (folder / DB_NAME).exists():
            raise StoreError("E1006", f"{folder} already holds a catrt store; use another folder, or delete it first")
        _writable(folder)
        lock_fd = _lock(folder)
        (folder / DB_NAME).touch()
        db_lock = _lock_db(folder)
        db = _connect(folder / DB_NAME)
        store = Store(folder, db, lock_fd)
        store._db_lock = db_lock
        with store.transaction():
            for statement in _SCHEMA:
                db.execute(statement)
            for key, value in (("schema_version", str(SCHEMA_VERSION)), ("catc_version", catc_version),
                               ("created", now())):  # fmt: skip
                db.execute("INSERT INTO meta VALUES (?, ?)", (key, value))
            for name, text in sources.items():
                db.execute("INSERT INTO sources VALUES (?, ?, ?)", (name, text, sha256_text(text)))
            for key, value in state.items():
                store.put(key, value)
        return store

    @staticmethod
    def open(folder: Path, *, write: bool) -> Store:
        """The store in ``folder``: for writing (locked, migrated), or read-only."""
        path = folder / DB_NAME
        if not path.is_file():
            raise StoreError("E1005", f"{folder} holds no catrt store (run 'catrt init {folder} DOMAIN PROBLEM' first)")
        _check_header(path)
        if write:
            _writable(folder)
        lock_fd = _lock(folder) if write else None
        db_lock = None
        store = None
        try:
            db_lock = _lock_db(folder) if write else None
            try:
                db = _connect(path) if write else _connect_readonly(path)
            except sqlite3.DatabaseError as exc:
                raise _store_error(exc, folder) from None
            store = Store(folder, db, lock_fd)
            store._db_lock = db_lock
            store._check_version(write)
            if write:
                problems = store.integrity(quick=True)
                if problems:
                    raise StoreError(
                        "E1014",
                        f"{path} fails its integrity check ({problems[0]}): catrt appends nothing to a damaged store; "
                        f"see 'catrt verify {folder}', restore the folder from a backup or start a new one",
                    )
        except BaseException:
            if store is not None:
                store.db.close()
            for fd in (lock_fd, db_lock):
                if fd is not None:
                    os.close(fd)
            raise
        return store

    _db_lock: int | None = None

    def close(self) -> None:
        self.db.close()
        for name in ("_lock_fd", "_db_lock"):
            fd = getattr(self, name)
            if fd is not None:
                os.close(fd)
                setattr(self, name, None)

    def check_sources(self) -> None:
        """StoreError E1013 naming the first source whose text no longer has its stored sha256."""
        from catrt.model import sha256_text

        for name, text, digest in self.db.execute("SELECT name, text, sha256 FROM sources ORDER BY name"):
            if sha256_text(text) != digest:
                raise StoreError(
                    "E1013",
                    f"the stored model source '{name}' does not have the sha256 it was stored with "
                    f"({digest[:12]}…): it was changed outside catrt; nothing is decided on it",
                )

    def _check_version(self, write: bool) -> None:
        try:
            row = self.db.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()
        except sqlite3.DatabaseError as exc:
            if "no such table" in str(exc):
                raise StoreError("E1005", f"{self.folder / DB_NAME} is not a catrt store: {exc}") from None
            raise _store_error(exc, self.folder) from None
        version = int(row[0]) if row and str(row[0]).isdigit() else None
        if version == SCHEMA_VERSION:
            return
        if (
            version is None
            or version > SCHEMA_VERSION
            or any(v not in MIGRATIONS for v in range(version, SCHEMA_VERSION))
        ):
            raise StoreError(
                "E1004",
                f"the store has schema version {row[0] if row else 'none'}; this catrt reads version {SCHEMA_VERSION}"
                + (" (it was made by a newer catrt: upgrade catrt)" if version and version > SCHEMA_VERSION else ""),
            )
        if not write:
            raise StoreError(
                "E1004", f"the store has schema version {version}: open it for writing (catrt run) to migrate it"
            )
        with self.transaction():
            for v in range(version, SCHEMA_VERSION):
                for statement in MIGRATIONS[v]:
                    self.db.execute(statement)
            self.db.execute("UPDATE meta SET value = ? WHERE key = 'schema_version'", (str(SCHEMA_VERSION),))
            self.journal("migrated", {"from": version, "to": SCHEMA_VERSION})

    # ------------------------------------------------------------ transactions
    @contextlib.contextmanager
    def transaction(self) -> Iterator[None]:
        """``BEGIN IMMEDIATE … COMMIT``; rolled back when the block (or the commit) raises; a
        full disk is StoreError E1016."""
        try:
            self.db.execute("BEGIN IMMEDIATE")
            try:
                yield
                self.db.execute("COMMIT")
            except BaseException:
                if self.db.in_transaction:
                    self.db.execute("ROLLBACK")
                raise
        except (sqlite3.OperationalError, OSError) as exc:
            if _disk_full(exc):
                raise StoreError("E1016", f"{self.folder}: the disk is full: {exc}; nothing was written") from None
            raise

    def journal(self, kind: str, data: Mapping[str, Any], event_id: str | None = None) -> int:
        """Append an entry (inside a transaction); its sequence number."""
        (seq,) = self.db.execute("SELECT COALESCE(MAX(seq), 0) + 1 FROM journal").fetchone()
        self.db.execute(
            "INSERT INTO journal (seq, at, kind, event_id, data) VALUES (?, ?, ?, ?, ?)",
            (seq, now(), kind, event_id, dumps(data)),
        )
        return int(seq)

    def put(self, key: str, value: Any) -> None:
        self.db.execute("INSERT OR REPLACE INTO state VALUES (?, ?)", (key, dumps(value)))

    # ------------------------------------------------------------ reading
    def get(self, key: str, default: Any = None) -> Any:
        row = self.db.execute("SELECT value FROM state WHERE key = ?", (key,)).fetchone()
        return json.loads(row[0]) if row else default

    def state(self) -> dict[str, Any]:
        return {k: json.loads(v) for k, v in self.db.execute("SELECT key, value FROM state ORDER BY key")}

    def sources(self) -> dict[str, str]:
        return dict(self.db.execute("SELECT name, text FROM sources ORDER BY name"))

    def meta(self) -> dict[str, str]:
        return dict(self.db.execute("SELECT key, value FROM meta"))

    def accepted(self, event_id: str) -> bool:
        row = self.db.execute("SELECT 1 FROM journal WHERE kind = 'event' AND event_id = ?", (event_id,)).fetchone()
        return row is not None

    def entries(self, after: int = 0, kinds: tuple[str, ...] = ()) -> Iterator[dict[str, Any]]:
        query = "SELECT seq, at, kind, event_id, data FROM journal WHERE seq > ?"
        args: list[Any] = [after]
        if kinds:
            query += f" AND kind IN ({','.join('?' * len(kinds))})"
            args += kinds
        for seq, at, kind, event_id, data in self.db.execute(query + " ORDER BY seq", args):
            yield {"seq": seq, "at": at, "kind": kind, "event_id": event_id, "data": json.loads(data)}

    def last_seq(self) -> int:
        return int(self.db.execute("SELECT COALESCE(MAX(seq), 0) FROM journal").fetchone()[0])

    # ------------------------------------------------------------ approvals
    def add_approval(self, approval_id: str, seq: int, proposal: Mapping[str, Any]) -> None:
        self.db.execute(
            "INSERT INTO approvals VALUES (?, ?, ?, ?)", (approval_id, seq, Verdict.PENDING, dumps(proposal))
        )

    def approvals(self, status: Verdict | None = None) -> list[dict[str, Any]]:
        query = "SELECT id, seq, status, proposal FROM approvals" + (" WHERE status = ?" if status else "")
        rows = self.db.execute(query + " ORDER BY seq", (status,) if status else ())
        return [{"id": i, "seq": s, "status": st, "proposal": json.loads(p)} for i, s, st, p in rows]

    def settle_approval(self, approval_id: str, status: Verdict) -> None:
        self.db.execute("UPDATE approvals SET status = ? WHERE id = ?", (status, approval_id))

    # ------------------------------------------------------------ checks
    def integrity(self, quick: bool = False) -> list[str]:
        """SQLite's integrity check (``quick_check`` when ``quick``), every journal entry
        UTF-8 JSON, the journal's numbering: the problems found."""
        try:
            pragma = "quick_check" if quick else "integrity_check"
            problems = [r[0] for r in self.db.execute(f"PRAGMA {pragma}") if r[0] != "ok"]
            if problems:
                return problems
            cursor = self.db.cursor()
            cursor.row_factory = None
            for seq, data in cursor.execute("SELECT seq, CAST(data AS BLOB) FROM journal ORDER BY seq"):
                try:
                    json.loads(bytes(data).decode("utf-8"))
                except (UnicodeDecodeError, ValueError) as exc:
                    problems.append(f"journal entry {seq} is garbled: {type(exc).__name__}: {str(exc)[:120]}")
            seqs = [r[0] for r in self.db.execute("SELECT seq FROM journal ORDER BY seq")]
        except sqlite3.DatabaseError as exc:
            return [f"SQLite cannot read the store: {exc}"]
        if seqs != list(range(1, len(seqs) + 1)):
            missing = sorted(set(range(1, (seqs[-1] if seqs else 0) + 1)) - set(seqs))
            problems.append(f"the journal has gaps: {missing[:10]}")
        return problems


def _connect(path: Path) -> sqlite3.Connection:
    # mode=rw: a missing file is an error, never a new empty database
    db = sqlite3.connect(f"{path.resolve().as_uri()}?mode=rw", uri=True, isolation_level=None, timeout=30)
    db.execute("PRAGMA journal_mode = WAL")
    db.execute("PRAGMA synchronous = FULL")
    db.execute("PRAGMA foreign_keys = ON")
    return db


def _connect_readonly(path: Path) -> sqlite3.Connection:
    db = sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True, isolation_level=None, timeout=30)
    return db


SQLITE_HEADER = b"SQLite format 3\x00"


def _check_header(path: Path) -> None:
    """StoreError E1014 when ``path`` is empty, shorter than a page or than its header says; E1005
    when it is no SQLite file at all."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(512)
        size = path.stat().st_size
    except PermissionError as exc:
        raise StoreError("E1015", f"{path}: cannot read the store: {exc.strerror}") from None
    if size == 0:
        raise StoreError("E1014", f"{path} is empty (0 bytes): the store was truncated; catrt does not rewrite it")
    if not head.startswith(SQLITE_HEADER[: len(head)]):
        raise StoreError("E1005", f"{path} is not an SQLite database: the folder holds no catrt store")
    if size < 512:
        raise StoreError("E1014", f"{path} is not a whole SQLite database ({size} bytes): the store is damaged")
    page_size = int.from_bytes(head[16:18], "big")
    page_size = 65536 if page_size == 1 else page_size
    pages = int.from_bytes(head[28:32], "big")
    wal = path.with_name(path.name + "-wal")
    settled = not wal.exists() or wal.stat().st_size == 0  # else a checkpoint may be growing the file
    if settled and pages and size < pages * page_size:
        raise StoreError(
            "E1014",
            f"{path} is truncated: {size} bytes of the {pages * page_size} its header names; the store is damaged",
        )


def _writable(folder: Path) -> None:
    """StoreError E1015 when catrt cannot create files in ``folder`` (a read-only folder,
    file system or mount: the lock, the WAL and its index live there)."""
    probe = folder / f".catrt-write-test-{os.getpid()}"
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:
        return
    except OSError as exc:
        if exc.errno in (errno.EROFS, errno.EACCES, errno.EPERM):
            raise StoreError(
                "E1015", f"the state folder {folder} is read-only ({exc.strerror}): catrt cannot lock or write it"
            ) from None
        if exc.errno == errno.ENOSPC:
            raise StoreError("E1016", f"{folder}: the disk is full: {exc.strerror}") from None
        raise
    os.close(fd)
    os.unlink(probe)


def _disk_full(exc: BaseException) -> bool:
    if isinstance(exc, OSError) and not isinstance(exc, sqlite3.Error):
        return exc.errno == errno.ENOSPC
    return getattr(exc, "sqlite_errorcode", None) == 13 or "database or disk is full" in str(exc)  # SQLITE_FULL


def _store_error(exc: sqlite3.DatabaseError, folder: Path) -> StoreError:
    """A DatabaseError met while opening the store, as a StoreError with its own code."""
    text = str(exc)
    if _disk_full(exc):
        return StoreError("E1016", f"{folder}: the disk is full: {text}")
    if "readonly" in text or ("unable to open" in text and not os.access(folder, os.W_OK)):
        return StoreError("E1015", f"the state folder {folder} is read-only: {text}")
    return StoreError("E1014", f"{folder / DB_NAME} is damaged ({text}): restore the folder from a backup")


def _lock_db(folder: Path) -> int:
    """An exclusive ``flock`` on the database file itself: whatever happens to ``STATE/lock``,
    a second writer finds the database locked (SQLite's own locks are POSIX ``fcntl`` locks,
    which ``flock`` does not touch)."""
    fd = os.open(folder / DB_NAME, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise StoreError(
            "E1003", f"another catrt is running on {folder} (its database is locked): one writer at a time"
        ) from None
    return fd


def _lock(folder: Path) -> int:
    """An exclusive lock on ``folder/lock`` for this process, or StoreError naming the holder."""
    path = folder / LOCK_NAME
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        holder = ""
        with contextlib.suppress(OSError, ValueError):
            holder = f" (pid {int(os.pread(fd, 32, 0).decode().strip())})"
        os.close(fd)
        raise StoreError("E1003", f"another catrt is running on {folder}{holder}: one writer at a time") from None
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
    os.fsync(fd)
    return fd
