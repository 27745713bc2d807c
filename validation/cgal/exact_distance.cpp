// Exact-constructions brute-force distance (see exact_distance.hpp).
#include "ppohdem/validation/exact_distance.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <cmath>
#include <optional>
#include <string>

#include "ppohdem/error.hpp"

namespace ppohdem::validation {

double exact_unsigned_distance(const TriangleMesh& mesh, const Vec3& point) {
  using Exact = CGAL::Exact_predicates_exact_constructions_kernel;  // "Epeck"
  if (mesh.empty()) throw InputError("exact_unsigned_distance: the mesh has no triangles");
  if (!point.allFinite()) throw InputError("exact_unsigned_distance: non-finite query point");
  const Exact::Point_3 p(point.x(), point.y(), point.z());
  std::optional<Exact::FT> best;  // exact min squared distance [world units^2]
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const auto& v = mesh.triangles[t].v;
    for (const Vec3& x : v) {
      if (!x.allFinite()) {
        throw InputError("exact_unsigned_distance: triangle " + std::to_string(t) +
                         " has a non-finite vertex coordinate");
      }
    }
    const Exact::Triangle_3 triangle(Exact::Point_3(v[0].x(), v[0].y(), v[0].z()),
                                     Exact::Point_3(v[1].x(), v[1].y(), v[1].z()),
                                     Exact::Point_3(v[2].x(), v[2].y(), v[2].z()));
    const Exact::FT d2 = CGAL::squared_distance(p, triangle);
    if (!best || d2 < *best) best = d2;
  }
  return std::sqrt(CGAL::to_double(*best));
}

}  // namespace ppohdem::validation
