"""A scene's ``[[fields]]`` attached to its built system."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.numerics.fields.base import FieldSpec
from poissonkit.numerics.fields.solids import check_outside, field_solids
from poissonkit.scene.bodies import BodyModel
from poissonkit.scene.schema import FieldDecl

if TYPE_CHECKING:
    from poissonkit.numerics.fields.contact import SolidContact
    from poissonkit.numerics.nbody import NBodySystem
    from poissonkit.numerics.unitsystem import UnitSystem


def with_scene_fields(system: NBodySystem, y0: np.ndarray, bodies: Sequence[BodyModel],
                      fields: Sequence[FieldDecl], units: UnitSystem | None = None
                      ) -> NBodySystem:
    """``system`` with the scene's fields; every body's ``moment`` (and any other attribute a
    field reads) is passed to the numerics, and tabulated fields cover the bodies' initial
    positions unless given a region.

    Raises
    ------
    InputError
        If a moving body starts inside a field source's solid or on its wire (positions in
        the scene's length unit ``units.length``).
    """
    from poissonkit.plugin.registry import external_field

    reads = {external_field(f.source).reads for f in fields} - {"mass"}
    attributes = {}
    for b in bodies:
        values = {a: b.attr(a) for a in reads}
        attributes[b.name] = {a: float(v) for a, v in values.items() if isinstance(v, float)}
    specs = [FieldSpec(f.source, dict(f.params)) for f in fields]
    built = system.with_fields(specs, y=y0, attributes=attributes)
    solids = field_solids(built.fields)
    if solids:  # a field is valid only outside its magnets, and singular on its wires
        r = np.asarray(built.unpack(y0, si=True)["r"], dtype=float).reshape(-1, 3)
        names = [b.name for b in built.bodies]
        moving = [k for k, b in enumerate(built.bodies) if not b.fixed]
        if len(r) == len(names):
            unit, scale = ("m", 1.0) if units is None else (units.length,
                                                           units.to_si(1.0, "length"))
            check_outside(solids, [names[k] for k in moving], r[moving], unit, scale)
    return built


def field_contact_events(system: NBodySystem, bodies: Sequence[BodyModel],
                         length_unit: float = 1.0) -> tuple[SolidContact, ...]:
    """The contact of the scene's moving bodies with its fields' solids
    (:class:`~poissonkit.numerics.fields.contact.SolidContact`): finite-size bodies by their
    shape (as :func:`~poissonkit.scene.build.contact_events`), the others as points; ``()``
    when no field has a shape."""
    from poissonkit.numerics.events import BodyShape
    from poissonkit.numerics.fields.contact import solid_contact

    moving = {b.name for b in system.bodies if not b.fixed}
    shapes = [BodyShape(b.name, float(b.magnet.get("radius", 0.0)) / length_unit,
                        float(b.magnet.get("half_length", 0.0)) / length_unit)
              for b in bodies if b.name in moving]
    event = solid_contact(system, shapes)
    return () if event is None else (event,)
