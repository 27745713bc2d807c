"""The particle arrays: read-only NumPy views without a copy, in construction order, that show
the current values after later runs and keep their engine alive (docs/python.md "Views")."""
import gc

import numpy as np
import pytest

import ppohdem as pd


@pytest.mark.parametrize("engine", ["fast", "reference"])
def test_views_share_memory_and_follow_runs(two_spheres_toml, engine):
    eng = pd.Engine(pd.Scene.from_toml(two_spheres_toml), engine=engine, threads=1)
    x = eng.positions
    assert x.shape == (2, 3) and x.dtype == np.float64
    assert np.shares_memory(x, eng.positions)  # two reads, one buffer
    for name in ("positions", "velocities", "angular_velocities", "forces", "torques", "ids", "radii"):
        a = getattr(eng, name)
        assert not a.flags.writeable
        with pytest.raises(ValueError):
            a[0] = 1.0
    # Construction order = the order of two_spheres.csv; values from the file, not the engine.
    assert list(eng.ids) == [1, 2]
    assert eng.radii.tolist() == [0.0005, 0.0005]
    assert x[0].tolist() == [-0.00055, 0.0, 0.0]
    v = eng.velocities
    eng.run(100)  # free flight: x = x0 + v t exactly up to rounding, no contact yet
    assert eng.step_count == 100
    assert x[0, 0] == pytest.approx(-0.00055 + 0.05 * 100 * 1.0e-7, rel=1e-12)
    assert v[1, 0] == -0.05
    assert np.shares_memory(x, eng.positions)


def test_views_keep_the_engine_alive(two_spheres_toml):
    eng = pd.Engine(pd.Scene.from_toml(two_spheres_toml), engine="fast", threads=1)
    x, ids = eng.positions, eng.ids
    expected = x.copy()
    del eng
    gc.collect()
    assert x.base is not None
    assert np.array_equal(x, expected) and list(ids) == [1, 2]  # memory still owned


def test_snapshot_is_a_copy(two_spheres_toml):
    eng = pd.Engine(pd.Scene.from_toml(two_spheres_toml), engine="reference")
    before = eng.positions.copy()
    eng.run(10)
    assert not np.shares_memory(before, eng.positions)
    assert before[0, 0] < eng.positions[0, 0]


def test_energies_and_counts_have_the_energy_csv_columns(two_spheres_toml):
    eng = pd.Engine(pd.Scene.from_toml(two_spheres_toml), engine="fast")
    e = eng.energies()
    assert list(e) == ["step", "time", "kinetic", "rotational", "gravitational", "elastic", "dissipated",
                       "boundary_work"]
    # 1/2 m v^2 for two spheres of radius 0.5 mm, 2500 kg/m^3, at 0.05 m/s
    m = 2500.0 * 4.0 / 3.0 * np.pi * 0.0005 ** 3
    assert e["kinetic"] == pytest.approx(2 * 0.5 * m * 0.05 ** 2, rel=1e-14)
    assert eng.contact_counts() == {"particle_pairs": 0, "particle_boundary": 0}
    eng.run(10500)  # contact starts when the 0.1 mm gap closes at 0.1 m/s: t = 1e-3 s = 10000 steps
    assert eng.contact_counts()["particle_pairs"] == 1
    assert eng.time == pytest.approx(10500 * 1.0e-7, rel=1e-15)


def test_run_rejects_negative_steps(two_spheres_toml):
    eng = pd.Engine(pd.Scene.from_toml(two_spheres_toml))
    with pytest.raises(pd.InputError):
        eng.run(-1)


def test_run_releases_the_gil(two_spheres_toml):
    """While one thread runs the engine, another keeps running Python code."""
    import threading
    import time
    eng = pd.Engine(pd.Scene.from_toml(two_spheres_toml), engine="reference")
    worker = threading.Thread(target=eng.run, args=(500000,))
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
    worker.join()
    assert eng.step_count == 500000
    duration = ticks[-1] - ticks[0]
    longest_gap = max(b - a for a, b in zip(ticks, ticks[1:]))
    # Held by the worker, the GIL would stop this loop for the whole run: one gap as long as
    # the run. Released, the loop only pauses for the scheduler (milliseconds); half the run
    # leaves room for a loaded machine.
    assert duration > 0.1 and longest_gap < 0.5 * duration, (duration, longest_gap)
