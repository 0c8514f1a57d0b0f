"""The kinds of change an event carries (one module each; :mod:`catrt.changes.registry`)."""
