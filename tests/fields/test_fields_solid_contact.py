"""Field sources are solids: the signed distance of each kind against sampled geometry, located
contact of moving bodies with a source (free-fall and straight-line times as truth), the
scene's ``contact`` choice, and bodies inside a source refused from the Python API too."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

import poissonkit as pk
from poissonkit.cli import main as cli_main
from poissonkit.errors import CollisionError, InputError
from poissonkit.numerics.fields.contact import SolidContact, solid_contact
from poissonkit.numerics.fields.solids import Solid
from poissonkit.numerics.nbody import Body, NBodySystem
from poissonkit.scene.build import build_run
from poissonkit.scene.loader import loads_scene

G = 9.81


def _grid(n: int) -> np.ndarray:
    return np.linspace(0.0, 1.0, n)


def _surface_samples(kind: str, d: dict, n: int = 90) -> np.ndarray:
    """Dense points on the surface of a piece, from its textbook parametrisation (local)."""
    u, v = np.meshgrid(_grid(n), _grid(n), indexing="ij")
    u, v = u.ravel(), v.ravel()
    faces = []
    if kind == "cuboid":
        h = np.array([d["a"], d["b"], d["c"]]) / 2
        for ax in range(3):
            i, j = [k for k in range(3) if k != ax]
            for sgn in (-1, 1):
                p = np.zeros((u.size, 3))
                p[:, ax] = sgn * h[ax]
                p[:, i] = (2 * u - 1) * h[i]
                p[:, j] = (2 * v - 1) * h[j]
                faces.append(p)
        return np.vstack(faces)
    ri, ro = d.get("inner_radius", 0.0), d.get("outer_radius", d.get("radius"))
    half = d["height"] / 2
    p1, p2 = math.radians(d.get("phi1", 0.0)), math.radians(d.get("phi2", 360.0))
    phi = p1 + (p2 - p1) * u
    for rho in (ri, ro):  # the curved faces
        faces.append(np.c_[rho * np.cos(phi), rho * np.sin(phi), (2 * v - 1) * half])
    rho = ri + (ro - ri) * v
    for z in (-half, half):  # the flat annular faces
        faces.append(np.c_[rho * np.cos(phi), rho * np.sin(phi), np.full(u.size, z)])
    if p2 - p1 < 2 * math.pi - 1e-12:
        for a in (p1, p2):  # the end faces
            faces.append(np.c_[rho * math.cos(a), rho * math.sin(a), (2 * u - 1) * half])
    return np.vstack(faces)


PIECES = [
    Solid("cuboid", (0.01, -0.02, 0.005), (0.3, -0.2, 0.5), {"a": 0.02, "b": 0.01, "c": 0.03}),
    Solid("cylinder", (0.0, 0.01, 0.0), (0.0, 0.7, 0.0), {"radius": 0.015, "height": 0.01}),
    Solid("cylinder_segment", (0.0, 0.0, 0.01), (0.1, 0.2, 0.3),
          {"inner_radius": 0.01, "outer_radius": 0.02, "height": 0.008, "phi1": -30.0,
           "phi2": 200.0}),
    Solid("cylinder_segment", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0),
          {"inner_radius": 0.005, "outer_radius": 0.02, "height": 0.004, "phi1": 0.0,
           "phi2": 360.0}),
]


@pytest.mark.parametrize("piece", PIECES, ids=lambda s: s.kind)
def test_signed_distance_matches_the_sampled_surface(piece):
    rng = np.random.default_rng(7)
    pts = np.asarray(piece.position) + rng.uniform(-0.05, 0.05, (3000, 3))
    d = piece.signed_distance(pts)
    surf = _surface_samples(piece.kind, dict(piece.dimensions)) @ piece.rotation().T \
        + np.asarray(piece.position)
    truth, _ = cKDTree(surf).query(pts)
    spacing = 0.04 / 89  # the largest parameter step of the samples, on the largest face
    inside = piece.inside(pts)
    assert np.all(d[inside] < 0) and np.all(d[~inside] >= 0)
    assert inside.any()
    out = ~inside
    # sampling only overestimates the distance, by at most half a cell's diagonal
    assert np.all(d[out] <= truth[out] + 1e-12)
    assert np.all(truth[out] - d[out] < spacing)


def test_a_sphere_and_a_loop_by_closed_forms():
    s = Solid("sphere", (0.0, 0.0, 1.0), dimensions={"radius": 0.5})
    assert s.signed_distance([[0.0, 0.0, 3.0]])[0] == pytest.approx(1.5)
    cyl = Solid("cylinder", (0.0, 0.0, 0.0), dimensions={"radius": 1.0, "height": 0.2})
    assert cyl.signed_distance([[0.0, 0.0, 0.05]])[0] == pytest.approx(-0.05)  # on the axis
    loop = Solid("loop", (0.0, 0.0, 0.0), dimensions={"radius": 1.0, "wire_radius": 0.1})
    assert loop.signed_distance([[0.0, 0.0, 0.0]])[0] == pytest.approx(0.9)
    assert loop.signed_distance([[1.0, 0.0, 0.5]])[0] == pytest.approx(0.4)


def _drop_scene(field: str, body: str = "", contact: str = "stop") -> str:
    return f"""
name = "drop"

[[bodies]]
name = "ball"
mass = 0.01
r = [0.001, 0.002, 0.03]
{body}

[[fields]]
source = "magpylib"
{field}

[[fields]]
source = "gravity"
g = [0.0, 0.0, -{G}]

[run]
method = "splitting4"
step = 1e-3
duration = 0.2
contact = "{contact}"
"""


CUBOID = ('class = "Cuboid"\nparams = { polarization = [0.0, 0.0, 1.0], '
          'dimension = [0.02, 0.02, 0.01] }')
CYLINDER = ('class = "Cylinder"\nparams = { polarization = [0.0, 0.0, 1.0], '
            'dimension = [0.04, 0.01] }')


def _run(text: str):
    spec = build_run(loads_scene(text))
    return spec, pk.solve(spec.system, spec.y0, spec.t_end, method=spec.method, step=spec.step,
                          events=spec.events)


def test_a_point_mass_falls_onto_a_cuboid_at_the_free_fall_time():
    spec, sol = _run(_drop_scene(CUBOID))
    (ev,) = sol.events
    t = ev.time * spec.system.scales.time if spec.system.scales else ev.time
    assert ev.kind == "contact" and ev.detail["bodies"] == ["ball", "magpylib"]
    assert ev.detail["solid"]["kind"] == "cuboid"
    # a constant force: the splitting is exact, the time is 2 h/g to the bracket's width
    assert t == pytest.approx(math.sqrt(2 * (0.03 - 0.005) / G), abs=1e-10)


def test_a_ball_falls_onto_a_cylinder_magnet_by_its_radius():
    spec, sol = _run(_drop_scene(CYLINDER, "radius = 0.002\nmoment = 0.0"))
    (ev,) = sol.events
    t = ev.time * spec.system.scales.time if spec.system.scales else ev.time
    assert t == pytest.approx(math.sqrt(2 * (0.03 - 0.005 - 0.002) / G), abs=1e-10)


def test_contact_ignore_lets_the_body_through():
    spec, sol = _run(_drop_scene(CUBOID, contact="ignore"))
    assert not spec.events and not sol.events
    assert sol.y[-1][2] < -0.1  # fell through the magnet


def test_the_cli_stops_and_the_summary_names_the_field(tmp_path, capsys):
    path = tmp_path / "drop.toml"
    path.write_text(_drop_scene(CUBOID))
    out = tmp_path / "run"
    assert cli_main(["run", str(path), "--out", str(out), "--no-progress", "--no-plot"]) == 4
    summary = json.loads((out / "summary.json").read_text())
    (ev,) = summary["events"]
    assert ev["detail"]["field"] == "magpylib"
    assert ev["time_s"] == pytest.approx(math.sqrt(2 * 0.025 / G), abs=1e-10)
    said = capsys.readouterr()
    assert (f"body 'ball' touched the source of field 'magpylib' at t = {ev['time_s']:.9g} s"
            in said.err)


def _flyer(solid_field: object, speed: float, start: float) -> tuple[NBodySystem, np.ndarray]:
    s = NBodySystem([Body("p", 1.0)], fields=[solid_field])
    return s, s.pack([[start, 0.0, 0.0]], [[speed, 0.0, 0.0]])


@pytest.mark.parametrize("method", ["splitting2", "midpoint", "rk45"])
def test_a_thin_plate_is_not_skipped_between_chunks(method):
    """A point at 1 m/s toward a 1 mm plate 5 cm away, 0.1 mm per step: the compiled loop
    sees no centre distance; the chunk bounds make the driver look before it is through
    (an implicit compiled loop too; scipy locates on its dense output)."""
    plate = pk.field("magpylib", **{"class": "Cuboid", "params": {
        "polarization": [0.0, 0.0, 1.0], "dimension": [0.001, 0.05, 0.05]}})
    s, y0 = _flyer(plate, 1.0, -0.05)
    ev = solid_contact(s)
    options = {"max_step": 1e-4} if method == "rk45" else {}
    sol = pk.solve(s, y0, 0.2, method=method, step=None if method == "rk45" else 1e-4,
                   tol=1e-10 if method == "rk45" else None, events=[ev], options=options)
    (rec,) = sol.events
    assert rec.time == pytest.approx(0.05 - 0.0005, abs=1e-9)
    assert rec.detail["bodies"] == ["p", "magpylib"]  # the scipy path names them too
    if method == "rk45":  # and raises the typed error naming them (a KeyError before)
        with pytest.raises(CollisionError, match="body 'p' touched field 'magpylib'"):
            pk.solve(s, y0, 0.2, method=method, tol=1e-10, options=options,
                     events=[solid_contact(s, error=True)])


def _shaped(*solids: Solid):
    """A field with no force (gravity 0) carrying ``solids``: contact geometry alone."""
    from dataclasses import replace

    return replace(pk.field("gravity", g=(0.0, 0.0, 0.0)).compile(), solids=solids)


def test_the_open_side_of_a_ring_segment_is_open():
    """A half ring (0°–180°): a point crossing the lower half-plane passes; one going up the
    y axis from the centre touches the inner face at the straight-line time."""
    seg = Solid("cylinder_segment", (0.0, 0.0, 0.0), dimensions={
        "inner_radius": 0.01, "outer_radius": 0.02, "height": 0.01, "phi1": 0.0,
        "phi2": 180.0}, field="half_ring")
    s = NBodySystem([Body("p", 1.0)], fields=[_shaped(seg)])
    ev = solid_contact(s)
    y_low = s.pack([[-0.03, -0.005, 0.0]], [[1.0, 0.0, 0.0]])
    assert not pk.solve(s, y_low, 0.05, method="splitting2", step=1e-4, events=[ev]).events
    y_up = s.pack([[0.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    (rec,) = pk.solve(s, y_up, 0.05, method="splitting2", step=1e-4, events=[ev]).events
    assert rec.time == pytest.approx(0.01, abs=1e-9)
    assert rec.detail["bodies"] == ["p", "half_ring"]


def test_error_true_raises_a_typed_error_naming_the_field():
    plate = pk.field("cylinder", polarization=1.0, radius=0.01, length=0.002)
    s = NBodySystem([Body("p", 1.0)], fields=[plate])
    y0 = s.pack([[0.0, 0.0, 0.05]], [[0.0, 0.0, -1.0]])
    with pytest.raises(CollisionError, match="'p' touched field 'cylinder'"):
        pk.solve(s, y0, 0.1, method="splitting2", step=1e-4, events=[solid_contact(s,
                                                                                  error=True)])


@pytest.mark.parametrize("field, where, r", [
    (pk.field("cylinder", polarization=1.0, radius=0.02, length=0.01), "inside",
     [0.005, 0.0, 0.001]),
    (pk.field("current_loop", current=10.0, radius=0.03), "on the wire of",
     [0.03, 0.0, 0.0]),
    (pk.field("magpylib", **{"class": "Sphere", "params": {
        "polarization": [0.0, 0.0, 1.0], "diameter": 0.02}}), "inside", [0.0, 0.005, 0.0]),
])
def test_solve_refuses_a_body_inside_a_source(field, where, r):
    s = NBodySystem([Body("probe", 0.01, alpha=1e5, attributes={"moment": 0.1})],
                    fields=[field])
    y0 = s.pack([r], [[0.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]], [[0.0, 0.0, 0.0]], si=True)
    with pytest.raises(InputError, match=f"body 'probe' starts {where} the source") as info:
        pk.solve(s, y0, 0.01, method="splitting2", step=1e-3)
    assert "field '" in str(info.value) and str(r[0]) in str(info.value)


def test_solid_contact_validates_its_input():
    with pytest.raises(InputError):
        SolidContact((), PIECES[:1])
    from poissonkit.numerics.events import BodyShape

    with pytest.raises(InputError):
        SolidContact((BodyShape("a", -1.0),), PIECES[:1])
