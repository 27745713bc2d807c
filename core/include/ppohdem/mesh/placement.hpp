#pragma once
/// \file placement.hpp
/// Placing a mesh in the data space, as the seed's input_constants_voxelizer.dat asks:
/// scale it to `sizeX_sizeY_sizeZ` and centre it at `posX_posY_posZ`. The seed is ambiguous
/// about uniform vs per-axis scaling; docs/formats.md says how each mode reads it:
///
///  - kUniformFit (default): one scale s = min_a(size_a / extent_a) so the mesh keeps its shape
///    and fits in the size box, touching it on the limiting axis; bounding-box centre -> pos.
///  - kPerAxis: each axis scaled to its own size (shape distorted); bounding box == size box.
///  - kPpohdem10: the original program's formula, per axis a:
///        v'_a = (v_a - min_a) / R * size_L + pos_a - 0.5 size_a,
///    R = the largest bounding-box extent, size_L = the size entry of that axis. Uniform
///    scale; the box's *minimum* corner goes to pos - size/2 (centred only if the scaled extent
///    equals size on that axis). On ties L is the first of x, y, z (the original's tie rule
///    is not documented; it only matters when the size entries differ).
/// place_mesh evaluates each mode in the form given in placement.cpp (kPpohdem10 in the
/// original's exact order, so it reproduces the original's object_mesh.stl bit for bit);
/// placement_map gives the same map as scale .* v + offset, equal up to rounding.
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem {

enum class PlacementMode { kUniformFit, kPerAxis, kPpohdem10 };

struct Placement {
  Vec3 size = Vec3::Ones();      ///< requested object size [m]
  Vec3 position = Vec3::Zero();  ///< requested object centre [m]
  PlacementMode mode = PlacementMode::kUniformFit;
};

/// v' = scale .* v + offset (component-wise).
struct AxisAlignedMap {
  Vec3 scale = Vec3::Ones();
  Vec3 offset = Vec3::Zero();
  Vec3 apply(const Vec3& v) const { return scale.cwiseProduct(v) + offset; }
};

/// The map that places a mesh with bounding box `box`. Throws InputError for a non-positive
/// size or an empty/flat box where the mode needs a positive extent.
AxisAlignedMap placement_map(const BoundingBox& box, const Placement& placement);

/// The placed copy of `mesh` (file normals kept, as the original writes them).
TriangleMesh place_mesh(const TriangleMesh& mesh, const Placement& placement);

}  // namespace ppohdem
