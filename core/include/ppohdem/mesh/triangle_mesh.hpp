#pragma once
/// \file triangle_mesh.hpp
/// A triangle soup as STL stores it: three vertices per facet plus the facet normal written in
/// the file (kept only so a placed mesh can be written back as the original program does;
/// geometry code recomputes normals from the vertices, counter-clockwise = outward).
#include <limits>
#include <string>
#include <vector>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem {

struct Triangle {
  std::array<Vec3, 3> v;         ///< vertices in world units, counter-clockwise seen from outside
  Vec3 file_normal = Vec3::Zero();  ///< the facet normal as read from the file (may be zero)

  /// (v1 - v0) x (v2 - v0): twice the area times the unit normal.
  Vec3 area_vector() const { return (v[1] - v[0]).cross(v[2] - v[0]); }
};

struct TriangleMesh {
  std::vector<Triangle> triangles;
  std::string name;  ///< the STL solid name (ASCII) or header text (binary), informational

  std::size_t size() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }
};

/// Axis-aligned box [min, max] in world units.
struct BoundingBox {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (min.array() > max.array()).any(); }
  Vec3 extent() const { return max - min; }
  Vec3 centre() const { return 0.5 * (min + max); }
  void expand(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  bool contains(const BoundingBox& other) const {
    return (other.min.array() >= min.array()).all() && (other.max.array() <= max.array()).all();
  }
};

BoundingBox bounding_box(const TriangleMesh& mesh);

}  // namespace ppohdem
