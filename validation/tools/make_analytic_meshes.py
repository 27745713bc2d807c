#!/usr/bin/python3
"""Write the analytic-SDF fixture meshes (ASCII STL, outward counter-clockwise triangles).

  fixtures/meshes/box.stl       axis-aligned box [-1, 1] x [-0.5, 0.5] x [-0.25, 0.25], 12 triangles;
                                its SDF is known in closed form (exact comparison).
  fixtures/meshes/icosphere.stl unit icosphere (icosahedron subdivided 4 times, vertices projected
                                to the sphere), 5120 triangles, centre 0, radius 1; the distance to
                                it differs from |p| - 1 by at most the chord error (<= 1 - cos of the
                                largest vertex-to-centroid angle, printed below).

Usage: /usr/bin/python3 validation/tools/make_analytic_meshes.py [OUTPUT_DIR]
Only the standard library is needed; the output is deterministic.
"""
import math
import os
import sys


def write_ascii_stl(path, name, triangles):
    with open(path + ".tmp", "w") as f:
        f.write(f"solid {name}\n")
        for a, b, c in triangles:
            u = [b[i] - a[i] for i in range(3)]
            v = [c[i] - a[i] for i in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            ln = math.sqrt(sum(x * x for x in n)) or 1.0
            f.write("  facet normal %.9g %.9g %.9g\n    outer loop\n" % tuple(x / ln for x in n))
            for p in (a, b, c):
                f.write("      vertex %.17g %.17g %.17g\n" % tuple(p))
            f.write("    endloop\n  endfacet\n")
        f.write(f"endsolid {name}\n")
    os.replace(path + ".tmp", path)


def box_triangles(lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    p = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3)]
    tris = []
    for a, b, c, d in quads:  # each quad counter-clockwise seen from outside
        tris.append((p[a], p[b], p[c]))
        tris.append((p[a], p[c], p[d]))
    return tris


def icosphere(levels):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]

    def unit(v):
        n = math.sqrt(sum(x * x for x in v))
        return tuple(x / n for x in v)

    verts = [unit(v) for v in verts]
    for _ in range(levels):
        cache = {}

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in cache:
                verts.append(unit(tuple((verts[i][k] + verts[j][k]) / 2 for k in range(3))))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return [(verts[a], verts[b], verts[c]) for a, b, c in faces]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "fixtures", "meshes")
    write_ascii_stl(os.path.join(out, "box.stl"), "box", box_triangles((-1, -0.5, -0.25), (1, 0.5, 0.25)))
    tris = icosphere(4)
    write_ascii_stl(os.path.join(out, "icosphere.stl"), "icosphere", tris)
    # Chord error: the sphere bulges above each flat triangle by at most 1 - |closest point|,
    # which for a triangle inscribed in the unit sphere is 1 - distance(origin, plane).
    sag = 0.0
    for a, b, c in tris:
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        ln = math.sqrt(sum(x * x for x in n))
        d = abs(sum(n[i] * a[i] for i in range(3))) / ln
        sag = max(sag, 1.0 - d)
    print(f"icosphere: {len(tris)} triangles, max chord error (sagitta) {sag:.6e}")


if __name__ == "__main__":
    main()
