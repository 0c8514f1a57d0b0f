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

One writer at a time: the writer holds an exclusive ``flock`` on ``STATE/lock`` for its
lifetime (released by the kernel when the process dies, so a crash never leaves it
locked); a second writer is refused.  Readers (``status``, ``journal``, ``verify``) open the
database read-only and need no lock.
"""

from __future__ import annotations

import contextlib
import datetime as dt
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
    """The store cannot be used: ``code`` is the diagnostic code (E1003–E1006)."""

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
        lock_fd = _lock(folder)
        db = _connect(folder / DB_NAME)
        store = Store(folder, db, lock_fd)
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
        lock_fd = _lock(folder) if write else None
        try:
            db = _connect(path) if write else _connect_readonly(path)
            store = Store(folder, db, lock_fd)
            store._check_version(write)
        except BaseException:
            if lock_fd is not None:
                os.close(lock_fd)
            raise
        return store

    def close(self) -> None:
        self.db.close()
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None

    def _check_version(self, write: bool) -> None:
        try:
            row = self.db.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()
        except sqlite3.DatabaseError as exc:
            raise StoreError("E1005", f"{self.folder / DB_NAME} is not a catrt store: {exc}") from None
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
        """``BEGIN IMMEDIATE … COMMIT``; rolled back when the block raises."""
        self.db.execute("BEGIN IMMEDIATE")
        try:
            yield
        except BaseException:
            self.db.execute("ROLLBACK")
            raise
        self.db.execute("COMMIT")

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
    def integrity(self) -> list[str]:
        """SQLite's integrity check, the journal's numbering: the problems found."""
        problems = [r[0] for r in self.db.execute("PRAGMA integrity_check") if r[0] != "ok"]
        seqs = [r[0] for r in self.db.execute("SELECT seq FROM journal ORDER BY seq")]
        if seqs != list(range(1, len(seqs) + 1)):
            missing = sorted(set(range(1, (seqs[-1] if seqs else 0) + 1)) - set(seqs))
            problems.append(f"the journal has gaps: {missing[:10]}")
        return problems


def _connect(path: Path) -> sqlite3.Connection:
    db = sqlite3.connect(path, isolation_level=None, timeout=30)
    db.execute("PRAGMA journal_mode = WAL")
    db.execute("PRAGMA synchronous = FULL")
    db.execute("PRAGMA foreign_keys = ON")
    return db


def _connect_readonly(path: Path) -> sqlite3.Connection:
    db = sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True, isolation_level=None, timeout=30)
    return db


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
