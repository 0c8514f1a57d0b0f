"""``workspace/executeCommand``: ``catc.<query>`` answers a query of
:mod:`catc.queries.registry`, ``catc.export.<target>`` exports to a target of
:mod:`catc.targets.registry`, both for the saved file."""

from __future__ import annotations

from typing import Any

from catc.interfaces.lsp.analysis import uri_to_path


def run_query_on_file(name: str, uri: str, options: dict[str, Any] | None = None) -> dict:
    """Answer the query ``name`` for the problem saved in the file at ``uri``: the query's
    ``--json`` document, or a ``catc.error/1`` document for input errors."""
    from catc.interfaces.api import CatError, load
    from catc.queries import registry
    from catc.queries.base import InputError, Kind

    query = registry.get(name)
    try:
        model = load(uri_to_path(uri))
        values = {**query.defaults(), **(options or {})}
        for option in query.options:
            if option.kind is Kind.PLAN_FILE and values.get(option.name) is None:
                raise InputError(f"catc.{name} needs '{option.name}': a catc.plan/1 document")
        why = query.check(model.instance, values) if query.check is not None else None
        if why is not None:
            raise InputError(why)
        result = model.query(name, **query.run_options(values))
    except CatError as exc:
        return _error([d.to_json() for d in exc.diagnostics])
    except (InputError, ValueError) as exc:
        return _error([{"message": str(exc)}])
    return query.to_json(model.instance, result)


def run_target_on_file(name: str, uri: str, options: dict[str, Any] | None = None) -> dict:
    """Export the problem saved in the file at ``uri`` to the target ``name``: the target's
    JSON document, or a ``catc.error/1`` document for input errors."""
    from catc.interfaces.api import CatError, load
    from catc.queries.base import InputError
    from catc.targets import registry as targets

    target = targets.get(name)
    try:
        model = load(uri_to_path(uri))
        values = {**target.defaults(), **(options or {})}
        if target.prepare is not None:
            target.prepare(values)
        artifact = model.export(name, **target.run_options(values))
    except CatError as exc:
        return _error([d.to_json() for d in exc.diagnostics])
    except (InputError, ValueError) as exc:
        return _error([{"message": str(exc)}])
    return target.to_json(model.instance, artifact)


def _error(diagnostics: list[dict]) -> dict:
    """The ``catc.error/1`` document a command answers instead of its own."""
    return {"schema": "catc.error/1", "status": "error", "diagnostics": diagnostics}


def _unreadable(ls: Any, uri: object) -> dict | None:
    """A ``catc.error/1`` document when ``uri`` is not a ``file:`` URI of an open document or
    of the workspace (issue 28: a command never reads any other file), else None."""
    from catc.interfaces.lsp.analysis import uri_to_path
    from catc.interfaces.lsp_framing import readable_path

    known = set(ls.workspace.text_documents)
    roots = [uri_to_path(f.uri) for f in ls.workspace.folders.values()] + [ls.workspace.root_path or ""]
    if readable_path(uri, known, roots) is not None:
        return None
    return _error([{"message": f"not a file: URI of an open document or of the workspace: {uri!r}"}])


def register_commands(server: Any, types: Any) -> None:
    """``catc.<query>`` commands: arguments ``[uri]`` or ``[uri, {option: value}]``; they
    answer for the saved file, as the command line would."""
    from catc.queries import registry

    def command_for(name: str) -> Any:
        def handler(ls: Any, *args: Any) -> dict:
            uri, options = (args[0] if args else None), (args[1] if len(args) > 1 else None)
            refused = _unreadable(ls, uri)
            return refused if refused is not None else run_query_on_file(name, str(uri), options)

        return handler

    for name in registry.names():  # in pygls's threads: a long query never blocks the server
        server.command(f"catc.{name}")(server.thread()(command_for(name)))

    from catc.targets import registry as targets

    def export_for(name: str) -> Any:
        def handler(ls: Any, *args: Any) -> dict:
            uri, options = (args[0] if args else None), (args[1] if len(args) > 1 else None)
            refused = _unreadable(ls, uri)
            return refused if refused is not None else run_target_on_file(name, str(uri), options)

        return handler

    for name in targets.names():  # ``catc.export.<target>``: [uri] or [uri, {option: value}]
        server.command(f"catc.export.{name}")(server.thread()(export_for(name)))
