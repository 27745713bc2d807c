/// \file placement.cpp
/// Scale and centre a mesh as input_constants_voxelizer.dat asks (modes in placement.hpp).
///
/// With bounding box [m, M], extent e = M - m, centre c = (m + M)/2, requested size S and
/// position p (per axis a):
///   kUniformFit: s = min_{a: e_a > 0} S_a / e_a;          v' = (v - c) s + p
///   kPerAxis:    s_a = S_a / e_a;                          v' = (v - m) s_a + (p - S/2)
///   kPpohdem10:  R = max_a e_a, L = first axis with e_L = R;
///                v' = ((v - m) / R) S_L + p - S/2          (the original's order, left to right)
/// place_mesh evaluates these forms; placement_map returns the same maps as scale .* v + offset
/// (equal up to rounding, a few ulps).
#include "ppohdem/mesh/placement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {

std::string show(const Vec3& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " +
         std::to_string(v.z()) + ")";
}

void check_inputs(const BoundingBox& box, const Placement& placement) {
  if (!placement.size.allFinite() || (placement.size.array() <= 0.0).any()) {
    throw InputError("placement size: expected three positive finite numbers, found " +
                     show(placement.size));
  }
  if (!placement.position.allFinite()) {
    throw InputError("placement position: expected three finite numbers, found " +
                     show(placement.position));
  }
  if (box.empty()) throw InputError("cannot place an empty mesh: expected at least one triangle");
  if (!box.min.allFinite() || !box.max.allFinite()) {
    throw InputError("cannot place a mesh with non-finite coordinates");
  }
}

/// The axis of the largest extent (first of x, y, z on ties); the original's R and L.
int largest_axis(const Vec3& extent) {
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (extent[a] > extent[axis]) axis = a;
  }
  return axis;
}

}  // namespace

AxisAlignedMap placement_map(const BoundingBox& box, const Placement& placement) {
  check_inputs(box, placement);
  const Vec3 extent = box.extent();
  const Vec3& size = placement.size;
  const Vec3& pos = placement.position;
  AxisAlignedMap map;
  switch (placement.mode) {
    case PlacementMode::kUniformFit: {
      double s = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (extent[a] > 0.0) s = std::min(s, size[a] / extent[a]);  // flat axes do not limit
      }
      if (!std::isfinite(s)) {
        throw InputError("cannot scale a mesh that is a single point (zero extent on every axis)");
      }
      map.scale = Vec3::Constant(s);
      map.offset = pos - s * box.centre();
      break;
    }
    case PlacementMode::kPerAxis: {
      for (int a = 0; a < 3; ++a) {
        if (!(extent[a] > 0.0)) {
          throw InputError(std::string("per-axis placement needs a positive extent on every "
                                       "axis; the mesh is flat in ") + "xyz"[a]);
        }
      }
      map.scale = size.cwiseQuotient(extent);
      map.offset = pos - 0.5 * size - map.scale.cwiseProduct(box.min);
      break;
    }
    case PlacementMode::kPpohdem10: {
      const int axis = largest_axis(extent);
      const double range = extent[axis];
      if (!(range > 0.0)) {
        throw InputError("cannot scale a mesh that is a single point (zero extent on every axis)");
      }
      map.scale = Vec3::Constant(size[axis] / range);
      map.offset = pos - 0.5 * size - map.scale.cwiseProduct(box.min);
      break;
    }
  }
  return map;
}

TriangleMesh place_mesh(const TriangleMesh& mesh, const Placement& placement) {
  const BoundingBox box = bounding_box(mesh);
  const AxisAlignedMap map = placement_map(box, placement);  // validates the inputs
  const Vec3& size = placement.size;
  const Vec3& pos = placement.position;
  const Vec3 extent = box.extent();
  const int axis = largest_axis(extent);
  const Vec3 low_corner = pos - 0.5 * size;

  auto place = [&](const Vec3& v) -> Vec3 {
    Vec3 out;
    for (int a = 0; a < 3; ++a) {
      switch (placement.mode) {
        case PlacementMode::kUniformFit:
          out[a] = (v[a] - box.centre()[a]) * map.scale[a] + pos[a];
          break;
        case PlacementMode::kPerAxis:
          out[a] = (v[a] - box.min[a]) * map.scale[a] + low_corner[a];
          break;
        case PlacementMode::kPpohdem10:
          // Exactly the original's expression and evaluation order (Fortran, double).
          out[a] = (v[a] - box.min[a]) / extent[axis] * size[axis] + pos[a] - 0.5 * size[a];
          break;
      }
    }
    return out;
  };

  TriangleMesh placed = mesh;
  for (Triangle& t : placed.triangles) {
    for (Vec3& p : t.v) p = place(p);
  }
  return placed;
}

}  // namespace ppohdem
