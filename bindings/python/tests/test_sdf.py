"""SDF builders from Python: the same file as `ppohdem voxelize` byte for byte, the node view,
trilinear queries, and the teaching stages (docs/python.md "Signed distance fields")."""
import os
import subprocess

import numpy as np
import pytest

import ppohdem as pd
from conftest import FIXTURES

BOX = FIXTURES / "meshes" / "box.stl"  # [-1, 1] x [-0.5, 0.5] x [-0.25, 0.25]
CELLS = (17, 9, 7)
GRID_BOX = (-1.5, -1.0, -0.75, 1.5, 1.0, 0.75)


def box_sdf(p):
    """Analytic signed distance of the box fixture (negative inside)."""
    half = np.array([1.0, 0.5, 0.25])
    q = np.abs(p) - half
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
    inside = np.minimum(np.max(q, axis=-1), 0.0)
    return outside + inside


def cli_voxelize(out, method, band=None):
    exe = os.environ["PPOHDEM_EXE"]
    cmd = [exe, "voxelize", "--mesh", str(BOX), "--cells", *map(str, CELLS), "--box", *map(str, GRID_BOX),
           "--method", method, "--threads", "1", "--out", str(out), "--quiet"]
    if band is not None:
        cmd += ["--band", str(band)]
    subprocess.run(cmd, check=True, capture_output=True)
    return out.read_bytes()


@pytest.mark.parametrize("method,band", [("fast", 0.0), ("fast", 2.0), ("exact", 0.0), ("seed", 0.0)])
def test_build_equals_the_cli_file_byte_for_byte(tmp_path, method, band):
    cli = cli_voxelize(tmp_path / "cli.vtk", method, band if band else None)
    field = pd.sdf.build(str(BOX), cells=CELLS, box=GRID_BOX, method=method, band=band, threads=1)
    # The title line is the run header, which ends with the time of day: give Python the CLI's.
    title = cli.split(b"\n")[1].decode()
    field.save_vtk(tmp_path / "py.vtk", header=title)
    assert (tmp_path / "py.vtk").read_bytes() == cli
    # With its own header only the time stamp (after the last "; ") may differ.
    field.save_vtk(tmp_path / "own.vtk")
    own = (tmp_path / "own.vtk").read_bytes().split(b"\n")
    theirs = cli.split(b"\n")
    assert own[0] == theirs[0] and own[2:] == theirs[2:]
    assert own[1].rsplit(b"; ", 1)[0] == theirs[1].rsplit(b"; ", 1)[0]


def test_values_view_grid_and_exactness_on_the_box():
    field = pd.sdf.build(BOX, cells=CELLS, box=GRID_BOX, method="exact")
    assert field.shape == CELLS
    assert field.origin == (-1.5, -1.0, -0.75)
    assert field.spacing == pytest.approx((3.0 / 16, 2.0 / 8, 1.5 / 6), rel=1e-15)
    v = field.values
    assert v.shape == CELLS and not v.flags.writeable and np.shares_memory(v, field.values)
    i, j, k = np.meshgrid(*[np.arange(n) for n in CELLS], indexing="ij")
    nodes = np.stack([field.origin[a] + np.array([i, j, k][a]) * field.spacing[a] for a in range(3)], axis=-1)
    # The exact builder is exact to rounding of coordinates ~1 (1e-14 leaves 100 ulps).
    assert np.max(np.abs(v - box_sdf(nodes))) < 1e-14
    assert v[8, 4, 3] == pytest.approx(-0.25, abs=1e-15)  # the centre node, 0.25 from the z faces


def test_query_is_trilinear_and_exact_on_linear_fields():
    n = (5, 4, 3)
    origin, spacing = (0.5, -1.0, 2.0), (0.25, 0.5, 1.0)
    i, j, k = np.meshgrid(*[np.arange(m) for m in n], indexing="ij")
    x, y, z = (origin[0] + i * spacing[0], origin[1] + j * spacing[1], origin[2] + k * spacing[2])
    f = pd.sdf.Field.from_array(2.0 * x - 3.0 * y + 0.5 * z + 1.0, origin, spacing)
    rng = np.random.default_rng(5)
    p = np.column_stack([rng.uniform(0.5, 1.5, 50), rng.uniform(-1.0, 0.5, 50), rng.uniform(2.0, 4.0, 50)])
    phi, grad = f.query(p)
    assert phi.shape == (50,) and grad.shape == (50, 3)
    # A linear field is reproduced exactly by trilinear interpolation (to rounding: 1e-13).
    assert np.allclose(phi, 2.0 * p[:, 0] - 3.0 * p[:, 1] + 0.5 * p[:, 2] + 1.0, rtol=0, atol=1e-13)
    assert np.allclose(grad, [2.0, -3.0, 0.5], rtol=0, atol=1e-12)
    phi, grad = f.query([[10.0, 0.0, 0.0]])
    assert np.isnan(phi[0]) and np.isnan(grad).all()  # outside the grid


def test_bad_arguments_raise():
    with pytest.raises(pd.InputError, match="cells"):
        pd.sdf.build(BOX, cells=(1, 9, 9), box=GRID_BOX)
    with pytest.raises(pd.InputError, match="box"):
        pd.sdf.build(BOX, cells=CELLS, box=(0, 0, 0, -1, 1, 1))
    with pytest.raises(pd.InputError):
        pd.sdf.build(BOX, cells=CELLS, box=GRID_BOX, method="magic")
    with pytest.raises(pd.InputError, match="band"):
        pd.sdf.build(BOX, cells=CELLS, box=GRID_BOX, method="exact", band=2.0)
    with pytest.raises(pd.InputError):
        pd.sdf.build("/nonexistent.stl", cells=CELLS, box=GRID_BOX)


def test_teaching_stages_on_the_box():
    inside = pd.sdf.inside_by_ray_parity(BOX, CELLS, GRID_BOX)
    field = pd.sdf.build(BOX, cells=CELLS, box=GRID_BOX, method="exact")
    strictly = field.values < 0
    assert inside.shape == CELLS and (inside[strictly]).all()
    z = pd.sdf.column_crossings(BOX, CELLS, GRID_BOX, 8, 4)  # the column x = 0, y = 0
    assert z == [-0.25, 0.25]
    w = pd.sdf.winding_number(BOX, [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    assert w[0] == pytest.approx(1.0, abs=1e-12) and w[1] == pytest.approx(0.0, abs=1e-12)
    mesh = pd.sdf.Mesh.load(BOX)
    assert len(mesh) == 12 and mesh.triangles.shape == (12, 3, 3)
