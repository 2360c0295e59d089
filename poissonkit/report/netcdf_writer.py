"""A dataset described as plain data, and its NetCDF 3 file written without xarray.

:class:`DatasetDescription` holds the variables, coordinates and attributes of a dataset as
``(dims, array, attrs)`` triples: :meth:`~DatasetDescription.to_xarray` makes the
:class:`xarray.Dataset` of it, :func:`write_netcdf` the file that
``dataset.to_netcdf(path, engine="scipy")`` would write (byte for byte), with
:class:`scipy.io.netcdf_file` alone. Writing ``trajectory.nc`` this way spares ``poissonkit
run`` importing xarray, which pulls pandas and, through its chunk managers, dask (about a
second of start-up per run).

The encoding is xarray's for NetCDF 3 (``NETCDF3_64BIT``, scipy's ``version=2``), as far as the
types of a description go:

* float variables get ``_FillValue = NaN`` (the data is written as it is, bit for bit);
* a non-dimension coordinate is named in the ``coordinates`` attribute of every variable whose
  dimensions hold its own (or in the global ``coordinates`` attribute when there is none);
* text arrays are written as UTF-8 characters with a last dimension ``string<N>`` (N: the
  longest name in bytes) and ``_Encoding = "utf-8"``;
* 64-bit integers become 32-bit ones (refused when a value does not fit), booleans 8-bit ones;
* attributes: text as bytes, numbers as one-element arrays (float64 stays float64).

Variables are declared in the dataset's order (data variables, then coordinates), dimensions in
the order they first appear, attributes in the order given, so the header is the one xarray
writes. ``tests/report/test_netcdf_writer.py`` checks the files against xarray's.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from poissonkit.errors import MissingDependencyError

if TYPE_CHECKING:
    import xarray as xr

#: An attribute value of a description.
AttrValue: TypeAlias = "str | int | float"
#: One variable: ``(dims, values, attrs)``.
VariableSpec: TypeAlias = "tuple[tuple[str, ...], np.ndarray, Mapping[str, AttrValue]]"
#: NetCDF 3 has no 64-bit or unsigned integers (xarray's coercions).
_NC3_COERCIONS = {"int64": "int32", "uint64": "int32", "uint32": "int32", "uint16": "int16",
                  "uint8": "int8", "bool": "int8"}


def _xarray() -> ModuleType:
    try:
        import xarray as xr
    except ImportError:
        raise MissingDependencyError(
            "the trajectory dataset needs xarray: pip install xarray") from None
    return xr


@dataclass(frozen=True)
class DatasetDescription:
    """A dataset as plain data: ``{name: (dims, values, attrs)}`` for the data variables and
    the coordinates, and the dataset's attributes (all in the order they are written)."""

    data_vars: dict[str, VariableSpec] = field(default_factory=dict)
    coords: dict[str, VariableSpec] = field(default_factory=dict)
    attrs: dict[str, AttrValue] = field(default_factory=dict)

    def to_xarray(self) -> xr.Dataset:
        """The :class:`xarray.Dataset` of this description.

        Raises
        ------
        MissingDependencyError
            If xarray is not installed.
        """
        xarray = _xarray()

        def variables(specs: dict[str, VariableSpec]) -> dict[str, xr.Variable]:
            return {name: xarray.Variable(dims, values, attrs=dict(attrs))
                    for name, (dims, values, attrs) in specs.items()}

        return xarray.Dataset(variables(self.data_vars), coords=variables(self.coords),
                              attrs=dict(self.attrs))


def _coerce(values: np.ndarray) -> np.ndarray:
    """``values`` in a NetCDF 3 type (xarray's ``coerce_nc3_dtype``)."""
    target = _NC3_COERCIONS.get(str(values.dtype))
    if target is None:
        return values
    cast = values.astype(target)
    if not (cast == values).all():
        raise ValueError(f"values of type {values.dtype} do not fit in {target} (NetCDF 3)")
    return cast


def _attr(value: AttrValue | np.ndarray) -> bytes | np.ndarray:
    """An attribute value as xarray hands it to scipy (``encode_nc3_attr_value``)."""
    if isinstance(value, str):
        return value.encode("utf-8")
    return _coerce(np.atleast_1d(value))


def _encoded(dims: tuple[str, ...], values: np.ndarray, attrs: dict[str, object]
             ) -> tuple[tuple[str, ...], np.ndarray, dict[str, object]]:
    """A variable as xarray's CF and NetCDF 3 encoders leave it (text as characters)."""
    values = np.asarray(values)
    if values.dtype.kind == "f" and "_FillValue" not in attrs:
        attrs["_FillValue"] = values.dtype.type(np.nan)
    if values.dtype.kind == "U":
        attrs["_Encoding"] = "utf-8"
        encoded = np.array([s.encode("utf-8") for s in values.ravel()], dtype=bytes)
        values = encoded.reshape(values.shape)
    if values.dtype.kind == "S":
        dims = (*dims, f"string{values.dtype.itemsize}")
        values = values.reshape((*values.shape, 1)).view("S1")
    elif values.dtype.kind not in "fiub":
        raise TypeError(f"no NetCDF 3 encoding for values of type {values.dtype}")
    return dims, _coerce(values), attrs


def _with_coordinates(description: DatasetDescription
                      ) -> tuple[dict[str, VariableSpec], dict[str, AttrValue]]:
    """All variables (data, then coordinates) with the ``coordinates`` attributes that name
    the non-dimension coordinates, and the dataset attributes (xarray's rules)."""
    variables = {**description.data_vars, **description.coords}
    extra = {name for name, (dims, _, _) in description.coords.items() if dims != (name,)}
    named: set[str] = set()
    out: dict[str, VariableSpec] = {}
    for name, (dims, values, attrs) in variables.items():
        attrs = dict(attrs)
        if name not in extra and "coordinates" not in attrs:
            mine = sorted(c for c in extra if name not in dims
                          and set(variables[c][0]) <= set(dims))
            if mine:
                attrs["coordinates"] = " ".join(mine)
        named.update(str(attrs.get("coordinates", "")).split())
        out[name] = (dims, values, attrs)
    global_attrs = dict(description.attrs)
    if extra - named:
        global_attrs["coordinates"] = " ".join(sorted(extra - named))
    return out, global_attrs


def write_netcdf(path: str | Path, description: DatasetDescription) -> Path:
    """Write ``description`` as the NetCDF 3 (64-bit offset) file xarray's scipy engine writes.

    Parameters
    ----------
    path
        The file to write (replaced if present; not atomic: see
        :func:`poissonkit.files.atomic.atomic_path`).
    description
        The dataset.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        A variable whose values have no NetCDF 3 type (objects, complex numbers, dates).
    ValueError
        Integers that do not fit in 32 bits.
    """
    from scipy.io import netcdf_file

    variables, global_attrs = _with_coordinates(description)
    encoded = {name: _encoded(dims, values, dict(attrs))
               for name, (dims, values, attrs) in variables.items()}
    sizes: dict[str, int] = {}
    for dims, values, _ in encoded.values():
        for dim, n in zip(dims, values.shape, strict=True):
            sizes.setdefault(dim, n)
    with netcdf_file(str(path), mode="w", mmap=False, version=2) as f:
        for key, value in global_attrs.items():
            setattr(f, key, _attr(value))
        for dim, n in sizes.items():
            f.createDimension(dim, n)
        for name, (dims, values, attrs) in encoded.items():
            var = f.createVariable(name, values.dtype, dims)
            for key, item in attrs.items():
                setattr(var, key, _attr(item))  # type: ignore[arg-type]
            try:
                var[...] = values
            except TypeError:  # a zero-length dimension is scipy's record dimension, which
                var[:] = values  # takes no Ellipsis (scipy/scipy#6880; xarray does the same)
    return Path(path)
