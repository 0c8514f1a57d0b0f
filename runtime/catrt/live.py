"""The live view of ``catrt run`` on a terminal: the state, the deployed generation, the last
events with their decisions and timings, and the requests waiting for a person, redrawn after
every event (rich's ``Live``).  Off a terminal, and with ``--json``, ``run`` prints one line
(or one JSON document) per outcome instead."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import Any

from rich.console import Console, Group
from rich.live import Live
from rich.panel import Panel
from rich.table import Table
from rich.text import Text

from catgrammar.terminal import printable
from catrt.runtime import Outcome, Runtime, Status
from catrt.store import Verdict

STYLE = {Status.ACCEPTED: "green", Status.REJECTED: "red", Status.DUPLICATE: "dim"}


class LiveView:
    def __init__(self, console: Console, rows: int = 12) -> None:
        self.console = console
        self.outcomes: deque[Outcome] = deque(maxlen=rows)
        self.runtime: Runtime | None = None
        self.live = Live(console=console, auto_refresh=False, transient=False)

    def __enter__(self) -> LiveView:
        self.live.start()
        return self

    def __exit__(self, *_: object) -> None:
        self.live.stop()

    def say(self, outcome: Outcome) -> None:
        self.outcomes.append(outcome)
        self.live.update(self.render(), refresh=True)

    def asking(self, ask: Callable[[dict[str, Any]], bool]) -> Callable[[dict[str, Any]], bool]:
        """``ask`` with the live display paused while the person answers."""

        def paused(request: dict[str, Any]) -> bool:
            self.live.stop()
            try:
                return ask(request)
            finally:
                self.live.start()

        return paused

    def render(self) -> Group:
        table = Table(expand=True, show_edge=False, pad_edge=False)
        for name, style, justify in (("where", "cyan", "left"), ("event", "", "left"), ("decision", "bold", "left"),
                                     ("s", "", "right"), ("says", "", "left")):  # fmt: skip
            table.add_column(name, justify=justify, style=style or None, overflow="fold",  # type: ignore[arg-type]
                             ratio=4 if name == "says" else None)  # fmt: skip
        for o in self.outcomes:
            took = sum(o.timings.values()) if o.timings else None
            action = o.decision.action if o.decision is not None else o.status
            table.add_row(Text(printable(o.where)), Text(printable(o.event_id if o.event_id != o.where else "")),
                          Text(str(action), style=STYLE.get(o.status, "")), f"{took:.2f}" if took is not None else "",
                          Text(printable(o.message)))  # fmt: skip
        return Group(Panel(table, title=self._title(), title_align="left"), self._pending())

    def _title(self) -> str:
        rt = self.runtime
        if rt is None:
            return "catrt"
        incumbent = rt.incumbent
        deployed = f"generation {incumbent['generation']}" if incumbent else "nothing deployed"
        problem = rt.state.problem
        return printable(f"catrt {rt.folder} — problem {problem.name} — {deployed}").replace("[", "\\[")

    def _pending(self) -> Text:
        rt = self.runtime
        pending = rt.store.approvals(Verdict.PENDING) if rt is not None else []
        if not pending:
            return Text("no request waits", style="dim")
        lines = []
        for p in pending:
            said = ", ".join(f"{k} → {v}" for k, v in p["proposal"].get("set", {}).items())
            lines.append(f"request {p['id']} waits: {said} (catrt approve {rt.folder if rt else 'STATE'} {p['id']})")
        return Text(printable("\n".join(lines)), style="yellow")
