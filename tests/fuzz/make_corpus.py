#!/usr/bin/env python3
"""Writes the seed corpora tests/fuzz/corpus/<target>/ from fixtures/ (run from anywhere).

Every seed is a valid or near-valid input taken or derived from fixtures/, so libFuzzer starts
from inputs that reach deep into each reader. Small on purpose (< 100 kB in all): large seeds
slow every mutation. Derived files say below how they were made; rerunning this script
reproduces the committed corpus byte for byte.
"""
import pathlib
import struct

ROOT = pathlib.Path(__file__).resolve().parents[2]
FIX = ROOT / "fixtures"
OUT = ROOT / "tests" / "fuzz" / "corpus"


def put(target, name, data):
    d = OUT / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data if isinstance(data, bytes) else data.encode())


def read(rel):
    return (FIX / rel).read_bytes()


# ---- STL ASCII: small fixture meshes, as they are ------------------------------------------
for rel in ["meshes/box.stl", "ppohdem-1.0/test-cube.stl", "seed/list_1_1.stl"]:
    put("stl_ascii", pathlib.Path(rel).name, read(rel))

# ---- STL binary: the target's input is <mode byte><records> (even mode: count from the size)
# or <odd mode byte><uint32 count><records> (see fuzz_stl_binary.cpp).
binary = read("mesh-cases/binary_header_solid.stl")
records = binary[84:]
put("stl_binary", "header_solid_records", b"\x00" + records)
put("stl_binary", "header_solid_raw_count", b"\x01" + binary[80:84] + records)


def ascii_to_binary_records(text):
    """Records (50 bytes each) of an ASCII STL with the usual one-vertex-per-line layout."""
    out = b""
    normal, verts = None, []
    for line in text.decode().splitlines():
        w = line.split()
        if w[:2] == ["facet", "normal"]:
            normal, verts = [float(x) for x in w[2:5]], []
        elif w[:1] == ["vertex"]:
            verts.append([float(x) for x in w[1:4]])
        elif w[:1] == ["endfacet"]:
            out += struct.pack("<12fH", *normal, *verts[0], *verts[1], *verts[2], 0)
    return out


put("stl_binary", "box_records", b"\x00" + ascii_to_binary_records(read("meshes/box.stl")))

# ---- legacy control files: the seed files and the hand-made good/bad cases -----------------
put("voxelizer_input", "seed.dat", read("seed/input_constants_voxelizer.dat"))
put("update_params_input", "seed.dat", read("seed/input_params_update.dat"))
for f in sorted((FIX / "legacy-cases").glob("*.dat")):
    if f.name.startswith("voxelizer_"):
        put("voxelizer_input", f.name, f.read_bytes())
    elif f.name.startswith("params_"):
        put("update_params_input", f.name, f.read_bytes())

# ---- legacy VTK: a 3 x 2 x 2 field in the three encodings the reader accepts --------------
values = [0.5 * i - 1.25 for i in range(12)]
header = ("# vtk DataFile Version 3.0\nppohdem fuzz seed\n{enc}\nDATASET STRUCTURED_POINTS\n"
          "DIMENSIONS 3 2 2\nORIGIN 0 0 0\nSPACING 0.5 0.5 0.25\nPOINT_DATA 12\n"
          "SCALARS distance {type} 1\nLOOKUP_TABLE default\n")
put("vtk", "binary_double.vtk",
    header.format(enc="BINARY", type="double").encode() + struct.pack(">12d", *values) + b"\n")
put("vtk", "binary_float.vtk",
    header.format(enc="BINARY", type="float").encode() + struct.pack(">12f", *values) + b"\n")
put("vtk", "ascii_double.vtk",
    header.format(enc="ASCII", type="double") + " ".join(repr(v) for v in values) + "\n")

# ---- distance_NNNN.dat: rank files joined by NUL bytes (see fuzz_distance_dat.cpp) ---------


def fortran_e20_8(d):
    """E20.8 as gfortran writes it, 0.dddddddd E+xx (exponents below 100 only)."""
    if d == 0.0:
        return "0.00000000E+00"
    m, e = ("%.7e" % d).split("e")
    digits = m.replace("-", "").replace(".", "")
    return "%s0.%sE%+03d" % ("-" if d < 0 else "", digits, int(e) + 1)


def distance_files(nodes, nprocs):
    nx, ny, nz = nodes
    files = []
    for rank in range(nprocs):
        base, extra = divmod(nx, nprocs)
        count = base + (1 if rank < extra else 0)
        first = rank * base + min(rank, extra)
        text = "%8d%8d%8d%8d\n" % (nx, ny, nz, nprocs) if rank == 0 else ""
        for k in range(nz):
            for j in range(ny):
                for i in range(first, first + count):
                    d = 0.25 * (i + j + k) - 1.0
                    text += "%8d%8d%8d%20s\n" % (i + 1, j + 1, k + 1, fortran_e20_8(d))
        files.append(text)
    return "\0".join(files)


put("distance_dat", "one_rank_4x2x2", distance_files((4, 2, 2), 1))
put("distance_dat", "three_ranks_5x2x1", distance_files((5, 2, 1), 3))

# ---- scenes: the fixture scenes, the lattice one shrunk to 8 particles (fast runs). The target
# skips inputs containing '/' (see fuzz_scene_toml.cpp): units in comments become "per".
def scene(rel):
    return read(rel).decode().replace("/", " per ")


put("scene_toml", "two_spheres.toml", scene("scenes/two_spheres.toml"))
settling = scene("scenes/settling_10k.toml").replace("count = 10000", "count = 8")
put("scene_toml", "settling_8.toml", settling)
linear = (settling.replace('model = "hertz-mindlin"', 'model = "linear"\ncollision_time = 1.0e-4')
          .replace('generator = "lattice"', 'generator = "random"\nradius_max = 1.5e-3'))
put("scene_toml", "linear_random_8.toml", linear)
# two materials (docs/dem.md): [[material]] entries, a pair override, generator materials
soft = settling.split("[material]")[1].split("\n[")[0]
two = (settling.replace("[material]" + soft, "[[material]]\nname = \"soft\"" + soft
                         + "\n[[material]]\nname = \"stiff\"" + soft.replace("young = 1.0e7", "young = 1.0e11")
                         + "\n[[material_pair]]\nmaterials = [\"soft\", \"stiff\"]\nrestitution = 0.3\n")
       .replace('generator = "lattice"', 'generator = "lattice"\nmaterial = ["soft", "stiff"]'))
put("scene_toml", "two_materials_8.toml", two)

# ---- particle CSV: the fixture and a commented variant as ppohdem writes it -----------------
csv = read("scenes/two_spheres.csv")
put("particle_csv", "two_spheres.csv", csv)
put("particle_csv", "with_material.csv",
    csv.replace(b"radius\n", b"radius,material\n").replace(b"0.0005\n", b"0.0005,glass\n"))
put("particle_csv", "commented.csv", b"# ppohdem run header\n\n" + csv.replace(b",0,0,0,", b", 1e-3 ,0,0,"))
