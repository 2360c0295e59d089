"""External fields: one-body energies ``U(r, ν)`` acting on every body that reads them.

A field is a registry entry (:class:`~poissonkit.plugin.ExternalField`, hook
``poissonkit_fields``) that builds a :class:`CompiledField`: an SI kernel returning ``U`` and
its partials in ``r`` and ``ν``, and its data. The N-body numerics add, for every moving body
with the attribute the field reads (``mass``, ``moment``, ...), the force ``−∂U/∂r`` and the
torque ``ṁ = ∂U/∂ν × ν`` to those of the pair potentials, in the same kick, so the kick stays
the exact potential flow (``r``, ``ν`` fixed; torques ⟂ ``ν``) and the energy reported
everywhere includes the fields.

Modules, one job each:

* :mod:`~poissonkit.numerics.fields.base` — the built field, the request it is built for,
  and :func:`field`, the user's way to name one;
* :mod:`~poissonkit.numerics.fields.magnetic` — a magnet's ``−c ν·B`` from a compiled ``B``;
* :mod:`~poissonkit.numerics.fields.tricubic` — tricubic Hermite tables of a vector field;
* :mod:`~poissonkit.numerics.fields.tabulated` — a table chosen from a tolerance, its error;
* :mod:`~poissonkit.numerics.fields.compose` — the system's kernels with the field terms;
* :mod:`~poissonkit.numerics.fields.hooks` — the built-in ``gravity`` and ``uniform``.
"""

from __future__ import annotations

from poissonkit.numerics.fields.base import (CompiledField, FieldRequest, FieldSpec, compile_fields,
                                             field)

__all__ = ["CompiledField", "FieldRequest", "FieldSpec", "compile_fields", "field"]
