/// \file winding_number.cpp
/// Generalized winding number (Jacobson et al. 2013) with Van Oosterom & Strackee's (1983) solid
/// angle. See winding_number.hpp for the formulas; the grid classification uses the hierarchical
/// evaluation of winding_number_tree.hpp.
#include "ppohdem/sdf/reference/winding_number.hpp"

#include <cmath>
#include <numbers>

#include "ppohdem/sdf/reference/winding_number_tree.hpp"

namespace ppohdem::sdf::reference {

double solid_angle(const Vec3& p, const Vec3& a_vertex, const Vec3& b_vertex, const Vec3& c_vertex) {
  const Vec3 a = a_vertex - p;
  const Vec3 b = b_vertex - p;
  const Vec3 c = c_vertex - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

double winding_number(const TriangleMesh& mesh, const Vec3& p) {
  double total = 0.0;
  for (const Triangle& t : mesh.triangles) total += solid_angle(p, t.v[0], t.v[1], t.v[2]);
  return total / (4.0 * std::numbers::pi);
}

std::vector<bool> inside_by_winding_number(const TriangleMesh& mesh, const GridSpec& grid) {
  std::vector<bool> inside(grid.node_count(), false);
  if (mesh.empty()) return inside;
  const WindingNumberTree tree(mesh);
  for (int k = 0; k < grid.nodes[2]; ++k) {
    for (int j = 0; j < grid.nodes[1]; ++j) {
      for (int i = 0; i < grid.nodes[0]; ++i) {
        inside[grid.index(i, j, k)] = tree.winding_number(grid.position(i, j, k)) > 0.5;
      }
    }
  }
  return inside;
}

}  // namespace ppohdem::sdf::reference
