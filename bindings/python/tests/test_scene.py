"""Scenes from TOML files and from dicts; errors carry ppohdem's messages (file, line, key)."""
import numpy as np
import pytest

import ppohdem as pd
from conftest import FIXTURES, small_bed


def test_relative_paths_resolve_against_the_file(two_spheres_toml, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the CSV is beside the scene, not in the working directory
    scene = pd.Scene.from_toml(str(two_spheres_toml))
    assert scene.particle_count == 2 and scene.steps == 40000 and scene.dt == 1.0e-7
    assert str(scene.output_dir) == str(two_spheres_toml.parent / "out")


def test_bad_scene_raises_with_file_line_and_key(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[simulation]\ndt = 1e-7\nsteps = 10\nstepz = 3\n")
    with pytest.raises(pd.InputError) as info:
        pd.Scene.from_toml(bad)
    e = info.value
    assert isinstance(e, ValueError)
    assert e.file == str(bad) and e.line == 4
    assert "unknown key 'stepz'" in str(e) and str(bad) + ":4" in str(e)


def test_missing_file_is_an_error(tmp_path):
    with pytest.raises(pd.InputError, match="does not exist"):
        pd.Scene.from_toml(tmp_path / "nope.toml")


def test_from_dict_with_arrays_runs_as_the_file(two_spheres_toml):
    d = {
        "simulation": {"dt": 1.0e-7, "steps": 40000, "gravity": [0.0, 0.0, 0.0]},
        "material": {"density": 2500.0, "young": 1.0e7, "poisson": 0.3, "restitution": 0.5, "friction": 0.5},
        "contact": {"model": "hertz-mindlin"},
        "particles": {"id": np.array([1, 2]), "x": np.array([-0.00055, 0.00055]), "y": np.zeros(2),
                      "z": np.zeros(2), "vx": np.array([0.05, -0.05]), "radius": np.full(2, 0.0005)},
        "wall": [{"point": [0.0, 0.0, -0.01], "normal": [0.0, 0.0, 1.0]}],
    }
    a = pd.Engine(pd.Scene.from_dict(d), engine="fast")
    b = pd.Engine(pd.Scene.from_toml(two_spheres_toml), engine="fast")
    a.run(11000)
    b.run(11000)
    assert pd.compare(a, b)["bitwise"]


def test_from_dict_generator_and_errors():
    scene = pd.Scene.from_dict(small_bed())
    assert scene.particle_count == 125 and scene.boundary_count == 3
    d = small_bed()
    d["contact"]["modle"] = "linear"
    with pytest.raises(pd.InputError, match="unknown key 'modle'"):
        pd.Scene.from_dict(d)
    d = small_bed()
    d["particles"] = {"id": [1, 2], "x": [0.0, 0.1], "y": [0, 0], "z": [0, 0], "radius": [0.001]}
    with pytest.raises(pd.InputError, match="'radius'"):
        pd.Scene.from_dict(d)


def test_from_dict_motion_program_is_the_scene_files(tmp_path):
    """An object's motion program as a list of dicts, d["object"][0]["motion"], gives the run of
    the same [[object.motion]] tables written by hand in a scene file (switches at steps 100
    and 200, while the scoop pushes into a bed)."""
    scoop = FIXTURES / "scenes" / "scoop" / "scoop.stl"
    d = {
        "simulation": {"dt": 1.5e-5, "steps": 300, "gravity": [0.0, 0.0, -9.81]},
        "material": {"density": 2500.0, "young": 2.0e7, "poisson": 0.3, "restitution": 0.5, "friction": 0.5},
        "contact": {"model": "hertz-mindlin"},
        "particles": {"generator": "lattice", "box_min": [0.04, 0.004, 0.036], "box_max": [0.08, 0.024, 0.046],
                      "count": 72, "radius": 0.002, "jitter": 0.1, "seed": 5},
        "wall": [{"point": [0.0, 0.0, 0.034], "normal": [0.0, 0.0, 1.0]}],
        "object": [{"name": "scoop", "mesh": str(scoop), "cells": [30, 20, 24],
                    "centroid": [0.075, 0.014, 0.045],
                    "motion": [{"start": 0.0, "type": "translate", "velocity": [0.0, 0.0, -0.5]},
                               {"start": 0.0015, "type": "rotate", "axis": [0.0, 1.0, 0.0], "omega": 5.0},
                               {"start": 0.003, "type": "vibrate_translate", "amplitude": [0.0, 0.0, 1e-4],
                                "frequency": 50.0}]}],
    }
    toml = tmp_path / "scoop.toml"
    toml.write_text(f"""
[simulation]
dt = 1.5e-5
steps = 300
gravity = [0.0, 0.0, -9.81]
[material]
density = 2500.0
young = 2.0e7
poisson = 0.3
restitution = 0.5
friction = 0.5
[contact]
model = "hertz-mindlin"
[particles]
generator = "lattice"
box_min = [0.04, 0.004, 0.036]
box_max = [0.08, 0.024, 0.046]
count = 72
radius = 0.002
jitter = 0.1
seed = 5
[[wall]]
point = [0.0, 0.0, 0.034]
normal = [0.0, 0.0, 1.0]
[[object]]
name = "scoop"
mesh = "{scoop}"
cells = [30, 20, 24]
centroid = [0.075, 0.014, 0.045]
[[object.motion]]
start = 0.0
type = "translate"
velocity = [0.0, 0.0, -0.5]
[[object.motion]]
start = 0.0015
type = "rotate"
axis = [0.0, 1.0, 0.0]
omega = 5.0
[[object.motion]]
start = 0.003
type = "vibrate_translate"
amplitude = [0.0, 0.0, 1e-4]
frequency = 50.0
""")
    a = pd.Engine(pd.Scene.from_dict(d), engine="fast")
    b = pd.Engine(pd.Scene.from_toml(toml), engine="fast")
    still = pd.Engine(pd.Scene.from_dict({k: v for k, v in d.items() if k != "object"}), engine="fast")
    for e in (a, b, still):
        e.run(300)
    assert pd.compare(a, b)["bitwise"]
    # Not vacuous: the scoop has moved particles (the run without it differs).
    assert not pd.compare(a, still)["bitwise"]
    # A segment key the type does not take is the scene reader's error, with the key named.
    d["object"][0]["motion"][0]["omega"] = 1.0
    with pytest.raises(pd.InputError, match="omega"):
        pd.Scene.from_dict(d)
