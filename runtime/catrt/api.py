"""The runtime from Python: the third source of events, beside standard input and the spool
folder.

    from catrt.api import init, connect

    init("state", "examples/detection/person.cat")
    with connect("state", approve="never") as rt:   # the single writer of the store
        outcome = rt.submit({"id": "e1", "set": {"ram": "1"}})
        print(outcome.status, outcome.message)     # accepted, restore ... request r1 waits
        rt.submit({"approve": "r1"})

``submit`` takes an event as the JSON lines carry it (a mapping, or the line itself) and
answers the event's :class:`~catrt.runtime.Outcome` after the step is committed and enacted.
Errors of the store are :class:`~catrt.store.StoreError` (``code`` E1003–E1006), of the
configuration :class:`~catrt.config.ConfigError` (E1007)."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from catrt.config import load_config
from catrt.create import create
from catrt.runtime import Outcome, Runtime
from catrt.store import Store

__all__ = ["Connection", "Outcome", "Runtime", "connect", "init", "submit"]


def init(
    state: str | Path,
    problem: str,
    domain: str | None = None,
    *,
    problem_name: str | None = None,
    search_paths: Iterable[str] = (),
    config_text: str | None = None,
) -> None:
    """``catrt init``: a new state folder for the model (CatError when it does not check)."""
    create(Path(state), problem, domain, problem_name=problem_name, search_paths=search_paths,
           config_text=config_text).close()  # fmt: skip


class Connection:
    """An open runtime: the store's single writer until :meth:`close` (or the ``with`` block
    ends)."""

    def __init__(self, runtime: Runtime) -> None:
        self.runtime = runtime
        self.started = runtime.start()

    def submit(self, event: Mapping[str, Any] | str, where: str = "api") -> Outcome:
        line = event if isinstance(event, str) else json.dumps(dict(event))
        return self.runtime.handle_line(line, where)

    def status(self) -> dict[str, Any]:
        from catrt.views import status_document

        return status_document(self.runtime.store, self.runtime.folder)

    def close(self) -> None:
        self.runtime.close()

    def __enter__(self) -> Connection:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


def connect(
    state: str | Path,
    *,
    approve: str = "never",
    enactor: str | None = None,
    say: Callable[[Outcome], None] | None = None,
) -> Connection:
    """Open the store for writing (refused with E1003 while another runtime holds it), finish
    an interrupted enactment, compose when nothing is deployed, and return the connection."""
    folder = Path(state)
    store = Store.open(folder, write=True)
    try:
        config = load_config(folder)
        runtime = Runtime(folder, store, config, enactor=enactor, approve=approve, say=say)
    except BaseException:
        store.close()
        raise
    return Connection(runtime)


def submit(state: str | Path, events: Iterable[Mapping[str, Any]], **options: Any) -> list[Outcome]:
    """Open, hand each event to the loop in order, close; the outcomes."""
    with connect(state, **options) as rt:
        return [rt.submit(e) for e in events]
