"""Scene.from_dict: the TOML scene structure as a Python dict (docs/python.md).

The dict is written back as TOML text and read by the library's scene reader
(read_scene_text), so keys, checks and messages are those of a scene file. [particles] may
instead hold the particle columns of the CSV format as arrays (id, x, y, z, radius required;
vx, vy, vz, wx, wy, wz default to 0; material as names or indices).
"""
import math
import os

import numpy as np

from . import _ppohdem

_COLUMNS = ("id", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "radius", "material")


def _value(v, where):
    if isinstance(v, bool) or isinstance(v, np.bool_):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, (str, os.PathLike)):
        s = os.fspath(v)
        return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_value(x, where) for x in list(v)) + "]"
    raise _ppohdem.InputError(f"Scene.from_dict: {where}: cannot write a {type(v).__name__} as TOML")


def _is_table_list(v):
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(t, dict) for t in v)


def _table(lines, header, table, path):
    """[path] or [[path]] (header) with its keys; a list of dicts under a key of an array of
    tables is a nested array of tables, [[path.key]], written after the keys (TOML's order):
    e.g. an object's motion program, d["object"][0]["motion"] = [{...}, {...}]."""
    lines.append(header)
    nested = []
    for key, v in table.items():
        if isinstance(v, dict):
            raise _ppohdem.InputError(f"Scene.from_dict: {header} {key}: nested tables are not part of the scene format")
        if header.startswith("[[") and _is_table_list(v):
            nested.append((key, v))
            continue
        lines.append(f"{key} = {_value(v, header + ' ' + key)}")
    lines.append("")
    for key, tables in nested:
        for t in tables:
            _table(lines, f"[[{path}.{key}]]", t, f"{path}.{key}")


def to_toml(d):
    """The dict as TOML text: top-level dicts are [tables], lists of dicts [[arrays of tables]]."""
    lines = []
    for name, v in d.items():
        if isinstance(v, dict):
            _table(lines, f"[{name}]", v, name)
        elif _is_table_list(v):
            for t in v:
                _table(lines, f"[[{name}]]", t, name)
        else:
            raise _ppohdem.InputError(f"Scene.from_dict: top-level key '{name}' must be a table (dict) or a list of tables")
    return "\n".join(lines)


def _material_names(d):
    m = d.get("material")
    if isinstance(m, (list, tuple)):
        return [t.get("name") for t in m]
    if isinstance(m, dict):
        return [m.get("name", "default")]
    return []


def scene_from_dict(d, base_dir=None, name="Scene.from_dict"):
    """A Scene from the TOML structure as a dict; relative paths resolve against base_dir
    (default: the current directory). Errors name `name` and the line of the generated TOML."""
    if not isinstance(d, dict):
        raise _ppohdem.InputError("Scene.from_dict: expected a dict")
    d = dict(d)
    columns = None
    particles = d.get("particles")
    if isinstance(particles, dict) and "id" in particles:
        rest = {k: v for k, v in particles.items() if k not in _COLUMNS}
        columns = {k: np.asarray(v) for k, v in particles.items() if k in _COLUMNS}
        if "material" in columns and columns["material"].dtype.kind in "USO":
            names = _material_names(d)
            try:
                columns["material"] = np.array([names.index(str(n)) for n in columns["material"]], dtype=np.int64)
            except ValueError as e:
                raise _ppohdem.InputError(f"Scene.from_dict: particles column 'material': unknown name ({e}); "
                                          f"the scene has: {', '.join(map(str, names))}") from None
        if rest:
            d["particles"] = rest
        else:
            del d["particles"]
    base = os.fspath(base_dir) if base_dir is not None else os.getcwd()
    return _ppohdem.Scene._from_text(to_toml(d), name, base, columns)
