/// \file mesh_closure.cpp
/// Weld bit-identical vertices, count the uses of every edge. See mesh_closure.hpp.
#include "ppohdem/sdf/reference/mesh_closure.hpp"

#include <array>
#include <map>
#include <utility>

namespace ppohdem::sdf::reference {

namespace {

/// How often an undirected edge {low, high} (low < high) is used in each direction.
struct EdgeUse {
  std::size_t low_to_high = 0;
  std::size_t high_to_low = 0;
};

}  // namespace

MeshClosure check_mesh_closure(const TriangleMesh& mesh) {
  // Weld: std::map compares coordinates with <, so 0.0 and -0.0 are the same key.
  std::map<std::array<double, 3>, std::size_t> vertex_id;
  auto id_of = [&](const Vec3& v) {
    const auto [it, inserted] = vertex_id.try_emplace({v.x(), v.y(), v.z()}, vertex_id.size());
    return it->second;
  };

  std::map<std::pair<std::size_t, std::size_t>, EdgeUse> edges;
  for (const Triangle& t : mesh.triangles) {
    const std::array<std::size_t, 3> id = {id_of(t.v[0]), id_of(t.v[1]), id_of(t.v[2])};
    for (int corner = 0; corner < 3; ++corner) {
      const std::size_t from = id[static_cast<std::size_t>(corner)];
      const std::size_t to = id[static_cast<std::size_t>((corner + 1) % 3)];
      if (from == to) continue;  // a collapsed edge of a degenerate triangle
      EdgeUse& use = edges[{std::min(from, to), std::max(from, to)}];
      (from < to ? use.low_to_high : use.high_to_low) += 1;
    }
  }

  MeshClosure result;
  result.welded_vertices = vertex_id.size();
  result.edges = edges.size();
  for (const auto& [key, use] : edges) {
    const std::size_t uses = use.low_to_high + use.high_to_low;
    if (uses == 1) ++result.boundary_edges;
    if (uses >= 3) ++result.non_manifold_edges;
    if (uses == 2 && use.low_to_high != 1) ++result.misoriented_edges;
  }
  return result;
}

}  // namespace ppohdem::sdf::reference
