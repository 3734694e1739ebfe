"""The post-assembly builder against closed forms and against the report's steel deck."""

import math

import numpy as np
import pytest

from deck_emulator.core.assembly import (
    G_FT_S2,
    Arm,
    Assembly,
    Shaft,
    arm_properties,
    assembly_names,
    inferred_geometry,
    load_assembly,
    mass_properties,
    point_tensor,
    principal_axes,
    rod_tensor,
    scene_runs_on_listing,
    steel_deck_residuals,
    tube_properties,
)
from deck_emulator.engine.assemblies import to_deck_text, to_deck_values, to_scene
from deck_emulator.legacy.deck import parse_deck
from deck_emulator.studies.report_tables import REPORT_ALL

STEEL = 490.0


def test_uniform_thin_tube_closed_form():
    """Db = Dt: m = rho pi Dm t L, I_axis = m r^2, I_transverse(centre) = m r^2/2 + m L^2/12."""
    sh = Shaft(STEEL, 6.0, 6.0, 20.0, wall_in=0.25)
    a = Assembly("tube", sh)
    mp = mass_properties(a)
    Dm = (6.0 - 0.25) / 12
    r = Dm / 2
    m = STEEL / G_FT_S2 * math.pi * Dm * (0.25 / 12) * 20.0
    assert mp.mass_slug == pytest.approx(m, rel=1e-12)
    assert mp.cm_height_ft == pytest.approx(10.0, rel=1e-12)
    assert mp.C == pytest.approx(m * r * r, rel=1e-10)
    assert mp.A == pytest.approx(m * r * r / 2 + m * 400 / 12, rel=1e-10)
    assert mp.B == pytest.approx(mp.A, rel=1e-12)
    assert mp.delta_rad == 0.0


def test_tapered_tube_mass_centre_closed_form():
    """Thin wall, mass per length proportional to Dm: s_c = L (Dm_b + 2 Dm_t) / (3 (Dm_b + Dm_t))."""
    sh = Shaft(STEEL, 9.5, 4.0, 36.708, wall_in=0.12)
    m, sc, _ = tube_properties(sh, 0.12)
    db, dt = (9.5 - 0.12) / 12, (4.0 - 0.12) / 12
    assert sc == pytest.approx(36.708 * (db + 2 * dt) / (3 * (db + dt)), rel=1e-12)
    assert m == pytest.approx(STEEL / G_FT_S2 * math.pi * 0.01 * 36.708 * (db + dt) / 2, rel=1e-12)


def test_wall_solved_from_total_weight():
    a = Assembly("w", Shaft(STEEL, 9.5, 4.0, 36.708), total_weight_lb=300.0)
    mp = mass_properties(a)
    assert mp.weight_lb == pytest.approx(300.0, rel=1e-9)
    assert 0.05 < mp.wall_in < 0.2


def test_uniform_rod_closed_form():
    """A straight arm of mass m, length l: m l^2/12 about its centre, m l^2/3 about its end."""
    arm = Arm(reach_ft=8.0, rise_ft=0.0, weight_lb=G_FT_S2 * 2.0, luminaire_weight_lb=0.0)
    m, first, I = arm_properties(arm, top_ft=0.0, n=7)
    assert m == pytest.approx(2.0)
    assert first == pytest.approx([0.0, -8.0, 0.0])  # centre at y = -4
    assert I[0, 0] == pytest.approx(2.0 * 64 / 3, rel=1e-12)  # about x through the end
    assert I[2, 2] == pytest.approx(2.0 * 64 / 3, rel=1e-12)
    assert I[1, 1] == pytest.approx(0.0, abs=1e-12)  # slender: nothing about its own axis
    own, c = rod_tensor(2.0, (0, 0, 0), (0, 8, 0))
    centred = own - point_tensor(2.0, c)
    assert centred[0, 0] == pytest.approx(2.0 * 64 / 12, rel=1e-12)


def test_parallel_axis_theorem_against_point_cloud():
    """A rod tensor about the origin equals the sum over many point masses along it."""
    a, b, m = np.array([0.3, -1.0, 2.0]), np.array([1.0, 4.0, -0.5]), 3.0
    I, c = rod_tensor(m, a, b)
    n = 20000
    s = (np.arange(n) + 0.5) / n
    pts = a + s[:, None] * (b - a)
    cloud = sum(point_tensor(m / n, p) for p in pts[::1])
    assert np.allclose(I, cloud, rtol=1e-7, atol=1e-9)
    assert np.allclose(c, pts.mean(axis=0))


def test_point_mass_on_an_arm():
    """A uniform tube with a luminaire (point mass) on a massless arm: the mass centre and
    the tensor about it by hand (parallel-axis theorem, product of inertia)."""
    sh = Shaft(STEEL, 6.0, 6.0, 20.0, wall_in=0.25)
    arm = Arm(reach_ft=10.0, rise_ft=2.0, weight_lb=0.0, luminaire_weight_lb=G_FT_S2 * 1.5)
    mp = mass_properties(Assembly("pm", sh, arms=(arm,)))
    mt, _, _ = tube_properties(sh, 0.25)
    r = (6.0 - 0.25) / 24
    ml = 1.5
    M = mt + ml
    yc, zc = ml * -10.0 / M, (mt * 10.0 + ml * 22.0) / M
    assert mp.cm_offset_ft == pytest.approx(yc, rel=1e-12)
    assert mp.cm_height_ft == pytest.approx(zc, rel=1e-12)
    # in-plane tensor about the mass centre
    it = mt * r * r / 2 + mt * 400 / 12
    Iyy = it + mt * (10.0 - zc) ** 2 + ml * (22.0 - zc) ** 2
    Izz = mt * r * r + mt * yc**2 + ml * (-10.0 - yc) ** 2
    Iyz = -(mt * (0 - yc) * (10.0 - zc) + ml * (-10.0 - yc) * (22.0 - zc))
    T = np.array([[Iyy, Iyz], [Iyz, Izz]])
    vals = np.linalg.eigvalsh(T)
    assert mp.A == pytest.approx(Iyy + Izz - mt * r * r, rel=1e-10)  # about XX
    assert sorted([mp.B, mp.C]) == pytest.approx(sorted(vals), rel=1e-10)
    # delta: axis 3 = (0, -sin d, cos d) is the eigenvector of the small moment
    e = np.array([-math.sin(mp.delta_rad), math.cos(mp.delta_rad)])
    assert T @ e == pytest.approx(mp.C * e, rel=1e-9)


def test_principal_axes_of_a_known_tensor():
    d = 0.3
    R = np.array([[1, 0, 0], [0, math.cos(d), -math.sin(d)], [0, math.sin(d), math.cos(d)]])
    I = R @ np.diag([500.0, 450.0, 20.0]) @ R.T
    A, B, C, axes, delta = principal_axes(I)
    assert (A, B, C) == pytest.approx((500.0, 450.0, 20.0), rel=1e-12)
    assert delta == pytest.approx(d, rel=1e-12)  # axis 3 = R e_z = (0, -sin d, cos d)
    assert np.allclose(axes @ np.diag([A, B, C]) @ axes.T, I)


def _straight_steel_by_hand(total_lb, od_base_in, od_top_in, length_ft, reach_ft, rise_ft,
                            arm_lb, lum_lb, density=STEEL, g=G_FT_S2, slices=20000):
    """The uncalibrated steel post computed another way than the builder: the wall from the
    closed form of a thin tapered tube's weight (quadratic in the wall), the tube as thin
    rings summed over ``slices`` slices, the straight arm by the slender-rod formula, the
    luminaire a point at R; in the YY-ZZ plane, the principal axes of a 2 x 2 tensor.
    Returns (mass-centre height ft, A, B, C slug ft^2, delta rad)."""
    # weight of the tube: rho pi t L (Dbar - t) with Dbar the mean outside diameter
    dbar = (od_base_in + od_top_in) / 2 / 12
    shaft_lb = total_lb - arm_lb - lum_lb
    t = (dbar - math.sqrt(dbar**2 - 4 * shaft_lb / (density * math.pi * length_ft))) / 2
    s = (np.arange(slices) + 0.5) * length_ft / slices
    dm = (od_base_in + (od_top_in - od_base_in) * s / length_ft) / 12 - t
    ring = density / g * math.pi * dm * t * length_ft / slices  # slug per slice
    r2 = (dm / 2) ** 2
    # about Q, in the YY-ZZ plane: (m, first moments, Iyy, Izz, Iyz) with Iyy about YY etc.
    m_t, z_t = ring.sum(), (ring * s).sum()
    iyy_t, izz_t = (ring * (r2 / 2 + s * s)).sum(), (ring * r2).sum()
    ixx_t = iyy_t
    m_a = arm_lb / g
    y0, z0, y1, z1 = 0.0, length_ft, -reach_ft, length_ft + rise_ft
    yc, zc = (y0 + y1) / 2, (z0 + z1) / 2
    l2 = (y1 - y0) ** 2 + (z1 - z0) ** 2
    # slender rod: about its centre, m l^2/12 across the rod; then the parallel axes
    uy, uz = (y1 - y0) / math.sqrt(l2), (z1 - z0) / math.sqrt(l2)
    rod = m_a * l2 / 12
    iyy_a = rod * (1 - uy * uy) + m_a * zc * zc  # about YY: distances in ZZ (and XX = 0)
    izz_a = rod * (1 - uz * uz) + m_a * yc * yc
    iyz_a = -rod * uy * uz - m_a * yc * zc  # product of inertia, tensor sign
    ixx_a = rod + m_a * (yc * yc + zc * zc)
    m_l = lum_lb / g
    iyy_l, izz_l, iyz_l, ixx_l = m_l * z1 * z1, m_l * y1 * y1, -m_l * y1 * z1, m_l * (y1**2 + z1**2)
    m = m_t + m_a + m_l
    cy, cz = (m_a * yc + m_l * y1) / m, (z_t + m_a * zc + m_l * z1) / m
    ixx = ixx_t + ixx_a + ixx_l - m * (cy * cy + cz * cz)
    T = np.array([[iyy_t + iyy_a + iyy_l - m * cz * cz, iyz_a + iyz_l + m * cy * cz],
                  [iyz_a + iyz_l + m * cy * cz, izz_t + izz_a + izz_l - m * cy * cy]])
    vals, vecs = np.linalg.eigh(T)
    e = vecs[:, 0] * math.copysign(1.0, vecs[1, 0])  # the small moment's axis, ZZ up
    return cz, ixx, vals[1], vals[0], math.atan2(-e[0], e[1])


def test_steel_uncalibrated_as_stated():
    """Uniform-wall tube and straight arm, no base mass: the builder equals a computation by
    hand (another method, above), and what docs/report_full.md states for it (mass centre
    21.705 ft above Q; A, B, C and their residuals against the report's deck; delta 9.39
    deg) is what the hand computation gives."""
    a = Assembly("steel", Shaft(STEEL, 9.5, 4.0, 36.708),
                 arms=(Arm(10.0, 5.0, 83.5, 35.0),), total_weight_lb=485.07)
    mp = mass_properties(a)
    zc, A, B, C, delta = _straight_steel_by_hand(485.07, 9.5, 4.0, 36.708, 10.0, 5.0, 83.5, 35.0)
    assert mp.cm_height_ft == pytest.approx(zc, rel=1e-7)
    assert (mp.A, mp.B, mp.C) == pytest.approx((A, B, C), rel=1e-6)
    assert mp.delta_rad == pytest.approx(delta, rel=1e-6)
    # the docs' numbers, from the hand computation against the report's deck (card 2: A, B, C)
    assert round(zc, 3) == 21.705
    assert round(100 * (A / 3351.41 - 1), 1) == -10.6
    assert round(100 * (C / 69.68 - 1), 1) == 19.4
    assert round(100 * (B / 3282.6 - 1), 1) == -11.3
    assert round(math.degrees(delta), 2) == 9.39
    assert (round(A, 1), round(B, 1), round(C, 2)) == (2995.5, 2913.3, 83.23)


def test_steel_calibrated_residuals():
    """The shipped steel description (base 61 lb, calibrated arm): the residuals against the
    deck that docs/report_full.md states."""
    a, _, _ = load_assembly("steel")
    r = steel_deck_residuals(mass_properties(a))
    assert abs(r["cm_height_ft"]) < 0.01
    assert abs(r["cm_offset_ft"]) < 0.04
    assert 0.06 < r["A"] < 0.08 and 0.06 < r["B"] < 0.08  # the tube model's misfit
    assert 0.16 < r["C"] < 0.18
    assert abs(math.degrees(r["DELTA"])) < 0.1


def test_shipped_descriptions_build():
    assert set(assembly_names()) >= {"steel", "aluminium", "twin", "crash_test"}
    for name in ("steel", "aluminium", "twin"):
        a, _, _ = load_assembly(name)
        mp = mass_properties(a)
        assert mp.weight_lb == pytest.approx(a.total_weight_lb, rel=1e-9)
        assert math.dist(mp.points["P"], mp.points["Q"]) == pytest.approx(a.shaft.length_ft)


def test_deck_of_the_aluminium_post_reads_back():
    a, _, _ = load_assembly("aluminium")
    v = to_deck_values(a, template="steel40")
    text = to_deck_text(v)
    lines = text.splitlines()
    assert len(lines) == 9 and all(len(x) == 80 for x in lines)
    deck = parse_deck(text)
    for k in ("A", "B", "C", "DELTA", "ZZPO", "ZZRO", "FNA", "HEIGHT"):
        assert deck[k] == pytest.approx(v[k], abs=5e-5)  # at least 4 decimals
    # the car meets every post at the same heights above the ground
    assert deck["HHV"] + deck["HEIGHT"] == pytest.approx(-16.27 + 20.27, abs=1e-4)


def test_twin_is_refused_by_the_listing_in_one_line():
    a, _, _ = load_assembly("twin")
    with pytest.raises(ValueError):
        to_deck_values(a)
    reason = scene_runs_on_listing(to_scene(a))
    assert reason is not None and "\n" not in reason
    al, _, _ = load_assembly("aluminium")
    assert scene_runs_on_listing(to_scene(al)) is None


def test_steel_columns_imply_the_deck_length():
    cells = {p: [tuple(REPORT_ALL[c][f"{ax}{p}L"] for ax in "XYZ")
                 for c in REPORT_ALL if c.startswith("steel")] for p in "PQR"}
    g = inferred_geometry(cells)
    assert g["PQ"]["mean"] == pytest.approx(36.708, abs=0.01)
    assert g["PQ"]["sd"] < 0.01
    assert g["reach_ft"] == pytest.approx(10.0, abs=0.1)
    assert g["rise_ft"] == pytest.approx(5.0, abs=0.1)


@pytest.mark.parametrize("name", ["steel", "aluminium", "twin"])
def test_an_assembly_is_one_post_for_both_engines(name):
    """The deck the listing reads (the deck text, F10.5 columns) and the scene the core runs
    carry the same value in every field, for every shipped assembly, at any car speed and
    angle: the deck the listing read builds the very scene the core runs (the twin's one-arm
    deck; its second luminaire U, which no card carries, to the deck's own precision)."""
    import dataclasses

    from hypothesis import given, settings, strategies as st

    from deck_emulator.engine.assemblies import punched
    from deck_emulator.vocabulary.scene import Scene

    a, _, _ = load_assembly(name)
    mp = mass_properties(a)
    one = dataclasses.replace(a, arms=a.arms[:1])
    one_mp = dataclasses.replace(mp, points={k: p for k, p in mp.points.items() if k != "U"})

    @settings(max_examples=25, deadline=None)
    @given(template=st.sampled_from(["steel20", "steel40", "steel40_a15", "steel20_a30"]),
           speed=st.one_of(st.none(), st.floats(1.0, 300.0)),
           alpha=st.one_of(st.none(), st.floats(0.0, 0.6)))
    def check(template, speed, alpha):
        car = dict(template=template, speed_ft_s=speed, alpha_rad=alpha)
        scene = to_scene(a, mp, **car)
        deck = parse_deck(to_deck_text(to_deck_values(one, one_mp, **car)))
        read = Scene.from_deck(deck, name=a.name)
        assert scene.deck_values() == read.deck_values()  # every field the scene carries
        assert scene.initial == read.initial  # and the start values
        if "U" in mp.points:
            u = scene.post.second_luminaire_end
            assert (u.xx_ft, u.yy_ft, u.zz_ft) == tuple(punched(x) for x in mp.points["U"])
            assert dataclasses.replace(scene.post, second_luminaire_end=None) == read.post
        else:
            assert scene == read

    check()
