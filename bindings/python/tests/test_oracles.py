"""The oracles from Python: the analytic Hertz pair, CGAL's distance, the Lipschitz check."""
import math

import numpy as np
import pytest

import ppohdem as pd
from conftest import FIXTURES

ICOSPHERE = FIXTURES / "meshes" / "icosphere.stl"  # radius 1, centre 0


def test_hertz_force_and_impact_closed_forms():
    r_eff, e_star = 2.5e-4, 1.0e7 / (2 * (1 - 0.3 ** 2)) / 2  # two equal spheres: E* = E / (2 (1 - nu^2))
    delta = np.array([0.0, 1e-6, 4e-6])
    f = pd.oracles.hertz_force(delta, r_eff, e_star)
    assert f[0] == 0.0
    assert f[2] / f[1] == pytest.approx(8.0, rel=1e-14)  # delta^1.5: 4^1.5 = 8
    h = pd.oracles.hertz_impact(m_eff=6.545e-7, r_eff=r_eff, e_star=e_star, v=0.1)
    assert h["max_force"] == pytest.approx(pd.oracles.hertz_force(h["max_overlap"], r_eff, e_star), rel=1e-15)


def test_oblique_impact_restitution_is_the_input():
    r = pd.oracles.oblique_impact(mass=1.3e-6, radius=5e-4, e_star=5.5e6, g_star=2.1e6, v_n=0.1, restitution=0.5)
    # alpha(e) is found by bisection to 1e-10 and the impact integrated with 100,000 RK4 steps:
    # the restitution agrees to 1e-5 (hertz_damping.hpp: step halving changes e by < 1e-6).
    assert r["restitution"] == pytest.approx(0.5, abs=1e-5)


def test_lipschitz_ratio_of_exact_and_broken_fields():
    field = pd.sdf.build(ICOSPHERE, cells=(12, 12, 12), box=(-1.5, -1.5, -1.5, 1.5, 1.5, 1.5), method="exact")
    assert pd.oracles.lipschitz_ratio(field) <= 1.0 + 1e-12  # a true distance is 1-Lipschitz
    broken = field.values.copy()
    broken[6, 6, 6] += 0.5
    bad = pd.sdf.Field.from_array(broken, field.origin, field.spacing)
    assert pd.oracles.lipschitz_ratio(bad) > 1.5


@pytest.mark.skipif(not pd.oracles.has_cgal, reason="built without CGAL")
def test_cgal_signed_distance_agrees_with_the_exact_builder():
    cells, box = (9, 9, 9), (-1.5, -1.5, -1.5, 1.5, 1.5, 1.5)
    field = pd.sdf.build(ICOSPHERE, cells=cells, box=box, method="exact")
    oracle = pd.oracles.signed_distance_field(ICOSPHERE, cells, box)
    c = pd.sdf.compare(field, oracle)
    assert c["sign_mismatches"] == 0 and c["max_error_h"] < 1e-12
    p = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    phi = pd.oracles.signed_distance(ICOSPHERE, p)
    # The icosphere's vertices lie on the unit sphere, its faces inside it by at most the chord
    # error 1 - cos(edge/...) < 2e-3: phi(0) is about -1, phi at 2 about +1.
    assert phi[0] == pytest.approx(-1.0, abs=2e-3) and phi[1] == pytest.approx(1.0, abs=2e-3)
    assert pd.oracles.exact_distance(ICOSPHERE, p[1:])[0] == pytest.approx(phi[1], abs=1e-15)
