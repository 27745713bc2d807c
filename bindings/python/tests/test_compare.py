"""pd.compare of the reference and fast engines: the same bits (docs/dem.md "Optimized engine"),
and a difference is seen when there is one."""
import pytest

import ppohdem as pd
from conftest import small_bed


@pytest.mark.parametrize("threads", [1, 2])
def test_reference_and_fast_give_the_same_bits(threads):
    scene = pd.Scene.from_dict(small_bed())
    ref = pd.Engine(scene, engine="reference")
    fast = pd.Engine(scene, engine="fast", threads=threads)
    ref.run(1500)
    fast.run(1500)
    assert ref.contact_counts()["particle_boundary"] > 0  # the test passes through contacts
    assert ref.contact_counts() == fast.contact_counts()
    d = pd.compare(ref, fast)
    assert d["bitwise"] is True
    assert set(d) == {"positions", "velocities", "angular_velocities", "forces", "torques", "radii", "bitwise"}
    assert all(d[k] == 0.0 for k in d if k != "bitwise")


def test_compare_sees_a_difference():
    a = pd.Engine(pd.Scene.from_dict(small_bed()), engine="fast")
    d = small_bed()
    d["particles"]["velocity"] = [0.0, 0.0, -0.31]  # 0.01 m/s faster: positions differ by 0.01 m/s * t
    b = pd.Engine(pd.Scene.from_dict(d), engine="fast")
    a.run(10)
    b.run(10)
    r = pd.compare(a, b)
    assert r["bitwise"] is False
    # Before any contact (10 steps, 20 us) the position difference is 0.01 m/s x 20 us.
    assert r["positions"] == pytest.approx(0.01 * 10 * 2.0e-6, rel=1e-6)


def test_compare_needs_the_same_step():
    a = pd.Engine(pd.Scene.from_dict(small_bed()))
    b = pd.Engine(pd.Scene.from_dict(small_bed()))
    b.run(1)
    with pytest.raises(pd.InputError, match="different steps"):
        pd.compare(a, b)
