"""``catrt serve``: the operator console in the browser (docs/runtime.md, The console).

The web app (:mod:`catrt.console.app`, on Starlette, the ``console`` extra) reads the store as
``catrt status`` does and writes only as ``catrt approve`` does: a line in the spool folder,
which the running loop takes in (the store's single writer stays the loop).  The token that
guards it (:mod:`catrt.console.token`) needs no extra.
"""
