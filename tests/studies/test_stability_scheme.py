"""The stability page's statements from the scheme: the 1967 scheme's one-step matrix on an
undamped spring, its determinant and eigenvalues (algebra, not the implementation's output)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from deck_emulator.studies.stability import one_step_matrix, scheme_growth


@settings(max_examples=80, deadline=None)
@given(h_omega=st.floats(1e-4, 20.0), omega=st.floats(0.1, 1e4),
       x=st.floats(-10, 10, allow_subnormal=False), v=st.floats(-10, 10, allow_subnormal=False))
def test_the_matrix_is_one_step_of_the_scheme(h_omega, omega, x, v):
    # no subnormal state: its scaled tolerance would underflow to 0 (v = 5e-324 gave 1.5e-323
    # against 1e-323, one unit in the last place of a subnormal)
    # the scheme as the page states it: Euler velocity, then the trapezoid of the velocities
    h = h_omega / omega
    v1 = v - h * omega**2 * x
    x1 = x + h * (v + v1) / 2
    np.testing.assert_allclose(one_step_matrix(h_omega, omega) @ [x, v], [x1, v1],
                               rtol=1e-9, atol=1e-9 * (abs(x) + abs(v)) * (1 + h_omega**2) * omega)


@settings(max_examples=80, deadline=None)
@given(h_omega=st.floats(1e-3, 20.0))
def test_no_step_is_stable_and_below_four_the_growth_is_the_determinant(h_omega):
    # det [[1 - z/2, h], [-h w^2, 1]] = 1 - z/2 + z = 1 + z/2 with z = (h w)^2 (algebra);
    # trace^2 - 4 det = z (z - 16) / 4 < 0 for h w < 4: a complex pair of modulus sqrt(det)
    g = scheme_growth(h_omega)
    z = h_omega**2
    assert g["det"] == pytest.approx(1 + z / 2, rel=1e-9)
    assert g["modulus"] > 1.0
    if h_omega < 3.9:
        assert np.abs(g["eigenvalues"]) == pytest.approx([math.sqrt(1 + z / 2)] * 2, rel=1e-7)
        assert g["energy_per_step"] == pytest.approx(1 + z / 2, rel=1e-7)
    if h_omega > 4.1:
        assert np.all(np.abs(g["eigenvalues"].imag) < 1e-9)
