"""Export a checked instance to PDDL: :func:`export_pddl` chooses the exporter of the flavour.

* :mod:`catc.targets.pddl_base`: what both flavours share (:class:`Flavor`, :class:`Export`,
  the report, the errors, names, numbers and grids);
* :mod:`catc.targets.pddl_exporter`: PDDL 2.1 numeric planning (ENHSP);
* :mod:`catc.targets.pddlplus`: PDDL+ for SMTPlan+ (processes for real θ), a subclass of it;
* :mod:`catc.targets.pddl_target`: the ``pddl`` target (``catc export pddl``, ``model.export``).
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction

from catc import ir
from catc.targets.pddl_base import (
    RESERVED,
    Export,
    ExportError,
    ExportReport,
    Flavor,
    Unsupported,
    number,
    sanitize,
    value_suffix,
)

__all__ = [
    "RESERVED",
    "Export",
    "ExportError",
    "ExportReport",
    "Flavor",
    "Unsupported",
    "export_pddl",
    "number",
    "sanitize",
    "value_suffix",
]


def export_pddl(
    inst: ir.Instance,
    *,
    grid: Mapping[str, Fraction] | None = None,
    horizon: int | None = None,
    flavor: Flavor | str = Flavor.ENHSP,
) -> Export:
    """Translate ``inst`` (view already applied) to PDDL domain and problem text.

    ``flavor="enhsp"``: PDDL 2.1 numeric planning, every real θ on a ``grid``.
    ``flavor="smtplan"``: PDDL+ for SMTPlan+ — a real θ without a grid step becomes a dial
    (a fluent raised by a process between two instantaneous actions; :mod:`catc.targets.pddlplus`).
    """
    try:
        chosen = Flavor(flavor)
    except ValueError:
        raise ExportError(f"unknown flavor {flavor!r}; expected 'enhsp' or 'smtplan'") from None
    if chosen is Flavor.SMTPLAN:
        from catc.targets.pddlplus import PlusExporter  # PDDL+ (processes) for SMTPlan+

        return PlusExporter(inst, grid or {}, horizon, chosen).run()
    from catc.targets.pddl_exporter import Exporter

    return Exporter(inst, grid or {}, horizon, chosen).run()
