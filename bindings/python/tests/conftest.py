"""Shared fixtures of the Python module's tests (run by ctest: python.test_*)."""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("PPOHDEM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[3]))
FIXTURES = SOURCE_DIR / "fixtures"


@pytest.fixture
def two_spheres_toml():
    return FIXTURES / "scenes" / "two_spheres.toml"


def small_bed(engine_steps=None):
    """A lattice of 125 spheres falling into a box of walls, with friction (dict form)."""
    return {
        "simulation": {"dt": 2.0e-6, "steps": 100, "gravity": [0.0, 0.0, -9.81]},
        "material": {"density": 2500.0, "young": 1.0e7, "poisson": 0.3, "restitution": 0.5, "friction": 0.4},
        "contact": {"model": "hertz-mindlin"},
        "particles": {"generator": "lattice", "box_min": [0.0, 0.0, 0.0], "box_max": [0.01, 0.01, 0.01],
                      "count": 125, "radius": 0.0008, "jitter": 0.2, "seed": 3, "velocity": [0.0, 0.0, -0.3]},
        "wall": [{"point": [0.0, 0.0, -0.0005], "normal": [0.0, 0.0, 1.0]},
                 {"point": [-0.001, 0.0, 0.0], "normal": [1.0, 0.0, 0.0]},
                 {"point": [0.011, 0.0, 0.0], "normal": [-1.0, 0.0, 0.0]}],
    }
