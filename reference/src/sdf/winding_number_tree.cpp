/// \file winding_number_tree.cpp
/// Hierarchical generalized winding number: node boundaries built bottom-up, closing caps for far
/// nodes. See winding_number_tree.hpp for the formulas and the closing-cap argument.
#include "ppohdem/sdf/reference/winding_number_tree.hpp"

#include <map>
#include <numbers>
#include <utility>

#include "ppohdem/sdf/reference/winding_number.hpp"

namespace ppohdem::sdf::reference {

namespace {

using DirectedEdge = std::pair<std::size_t, std::size_t>;  ///< welded vertex ids (from, to)

/// The 1-chain `edges` with every a -> b cancelled against a b -> a, counted with multiplicity;
/// collapsed edges (a -> a, from degenerate triangles) are the zero chain and are dropped.
std::vector<DirectedEdge> cancel_opposite_edges(const std::vector<DirectedEdge>& edges) {
  std::map<DirectedEdge, long> net;  // key (low, high): uses low -> high minus uses high -> low
  for (const auto& [from, to] : edges) {
    if (from < to) ++net[{from, to}];
    if (from > to) --net[{to, from}];
  }
  std::vector<DirectedEdge> remaining;
  for (const auto& [key, count] : net) {
    for (long n = 0; n < count; ++n) remaining.push_back(key);
    for (long n = 0; n > count; --n) remaining.push_back({key.second, key.first});
  }
  return remaining;
}

bool strictly_outside(const Vec3& p, const BoundingBox& box) {
  return (p.array() < box.min.array()).any() || (p.array() > box.max.array()).any();
}

}  // namespace

WindingNumberTree::WindingNumberTree(const TriangleMesh& mesh) : bvh_(mesh) {
  // Weld bit-identical vertices (std::map compares with <, so 0.0 and -0.0 are one vertex).
  std::map<std::array<double, 3>, std::size_t> vertex_id;
  std::vector<Vec3> vertices;
  std::vector<std::array<std::size_t, 3>> corner_ids(mesh.size());
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (std::size_t corner = 0; corner < 3; ++corner) {
      const Vec3& v = mesh.triangles[t].v[corner];
      const auto [it, inserted] = vertex_id.try_emplace({v.x(), v.y(), v.z()}, vertices.size());
      if (inserted) vertices.push_back(v);
      corner_ids[t][corner] = it->second;
    }
  }

  // Boundaries bottom-up: children have larger indices than their parent, so a reverse scan sees
  // both children before the parent. d(S_left + S_right) = dS_left + dS_right, then cancel pairs.
  const std::vector<TriangleBvh::Node>& tree = bvh_.nodes();
  const std::vector<std::size_t>& order = bvh_.triangle_order();
  nodes_.resize(tree.size());
  std::vector<std::vector<DirectedEdge>> boundary(tree.size());
  for (std::size_t n = tree.size(); n-- > 0;) {
    const TriangleBvh::Node& node = tree[n];
    NodeCap& cap = nodes_[n];
    std::vector<DirectedEdge> edges;
    if (node.leaf()) {
      cap.triangle_count = node.count;
      for (std::size_t k = node.first; k < node.first + node.count; ++k) {
        const auto& id = corner_ids[order[k]];
        edges.insert(edges.end(), {{id[0], id[1]}, {id[1], id[2]}, {id[2], id[0]}});
      }
    } else {
      cap.triangle_count = nodes_[node.left].triangle_count + nodes_[node.right].triangle_count;
      edges = std::move(boundary[node.left]);
      edges.insert(edges.end(), boundary[node.right].begin(), boundary[node.right].end());
      boundary[node.left] = {};  // the children's boundaries are no longer needed: free as we go up
      boundary[node.right] = {};
    }
    boundary[n] = cancel_opposite_edges(edges);

    const double margin = kFarMargin * node.box.extent().norm();
    cap.far_box = node.box;
    cap.far_box.min.array() -= margin;
    cap.far_box.max.array() += margin;
    cap.centre = node.box.centre();
    cap.boundary_edges = boundary[n].size();
    cap.use_cap = cap.boundary_edges <= cap.triangle_count;
    if (cap.use_cap) {
      cap.first_cap_edge = cap_edges_.size();
      for (const auto& [from, to] : boundary[n]) cap_edges_.push_back({vertices[from], vertices[to]});
    }
  }
}

WindingNumberTree::Evaluation WindingNumberTree::evaluate(const Vec3& p) const {
  double total = 0.0;  // sum of solid angles [sr]
  std::size_t terms = 0;
  sum_solid_angles(0, p, total, terms);
  return Evaluation{total / (4.0 * std::numbers::pi), terms};
}

void WindingNumberTree::sum_solid_angles(std::size_t n, const Vec3& p, double& total, std::size_t& terms) const {
  const TriangleBvh::Node& node = bvh_.nodes()[n];
  const NodeCap& cap = nodes_[n];
  const bool far = strictly_outside(p, cap.far_box);
  if (far && cap.use_cap) {  // w_S(p) = w_cap(p); a closed node (no edges) adds nothing
    for (std::size_t e = cap.first_cap_edge; e < cap.first_cap_edge + cap.boundary_edges; ++e) {
      total += solid_angle(p, cap.centre, cap_edges_[e][0], cap_edges_[e][1]);
    }
    terms += cap.boundary_edges;
  } else if (far || node.leaf()) {  // the cap would cost more, or p is near a leaf: its triangles
    sum_triangles(n, p, total, terms);
  } else {
    sum_solid_angles(node.left, p, total, terms);
    sum_solid_angles(node.right, p, total, terms);
  }
}

void WindingNumberTree::sum_triangles(std::size_t n, const Vec3& p, double& total, std::size_t& terms) const {
  const std::size_t first = bvh_.nodes()[n].first;
  const std::size_t count = nodes_[n].triangle_count;
  for (std::size_t k = first; k < first + count; ++k) {
    const auto& v = bvh_.triangle(bvh_.triangle_order()[k]);
    total += solid_angle(p, v[0], v[1], v[2]);
  }
  terms += count;
}

}  // namespace ppohdem::sdf::reference
