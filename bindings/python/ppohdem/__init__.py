"""ppohdem: DEM engines, signed distance fields and their oracles from Python.

    import ppohdem as pd
    scene = pd.Scene.from_toml("scene.toml")
    eng = pd.Engine(scene, engine="fast", threads=2)
    eng.run(1000)
    eng.positions            # (N, 3) float64, a read-only view without a copy

The API and the lifetime of the views are documented in docs/python.md.
"""
from . import _ppohdem
from ._ppohdem import Engine, InputError, Scene, compare, oracles, provenance, sdf
from ._scene_dict import scene_from_dict as _scene_from_dict

Scene.from_dict = staticmethod(_scene_from_dict)

__all__ = ["Engine", "InputError", "Scene", "compare", "oracles", "provenance", "sdf"]
