#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem {

BoundingBox bounding_box(const TriangleMesh& mesh) {
  BoundingBox box;  // starts empty: min = +inf, max = -inf
  for (const Triangle& t : mesh.triangles) {
    for (const Vec3& p : t.v) box.expand(p);
  }
  return box;
}

}  // namespace ppohdem
