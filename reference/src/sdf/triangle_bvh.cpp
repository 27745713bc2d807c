/// \file triangle_bvh.cpp
/// Median-split bounding-volume hierarchy and branch-and-bound nearest-triangle query.
/// See triangle_bvh.hpp for the formulas.
#include "ppohdem/sdf/reference/triangle_bvh.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/reference/closest_point_triangle.hpp"

namespace ppohdem::sdf::reference {

double squared_distance_to_box(const Vec3& p, const BoundingBox& box) {
  const Vec3 below = (box.min - p).cwiseMax(0.0);
  const Vec3 above = (p - box.max).cwiseMax(0.0);
  return (below + above).squaredNorm();  // at most one of the two is non-zero per axis
}

TriangleBvh::TriangleBvh(const TriangleMesh& mesh) {
  if (mesh.empty()) throw InputError("TriangleBvh: expected a mesh with at least one triangle, found none");
  triangles_.reserve(mesh.size());
  centroids_.reserve(mesh.size());
  for (const Triangle& t : mesh.triangles) {
    triangles_.push_back(t.v);
    centroids_.push_back((t.v[0] + t.v[1] + t.v[2]) / 3.0);
  }
  order_.resize(mesh.size());
  std::iota(order_.begin(), order_.end(), std::size_t{0});
  nodes_.reserve(2 * mesh.size() / kMaxLeafSize + 1);
  build_node(0, mesh.size());
}

std::size_t TriangleBvh::build_node(std::size_t first, std::size_t count) {
  const std::size_t index = nodes_.size();
  nodes_.push_back(Node{});

  BoundingBox box;
  BoundingBox centroid_box;
  for (std::size_t n = first; n < first + count; ++n) {
    for (const Vec3& v : triangles_[order_[n]]) box.expand(v);
    centroid_box.expand(centroids_[order_[n]]);
  }
  // Inflate by a few ulps of the coordinates: the closest point q computed in floating point may
  // lie that far outside the exact triangle, and the box must still contain it for the bound.
  const double ulps = 16.0 * std::numeric_limits<double>::epsilon() *
                      std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  box.min.array() -= ulps;
  box.max.array() += ulps;
  nodes_[index].box = box;
  nodes_[index].first = first;

  if (count <= kMaxLeafSize) {
    nodes_[index].count = count;
    return index;
  }

  // Split at the median centroid along the longest axis of the centroid box.
  Eigen::Index axis = 0;
  centroid_box.extent().maxCoeff(&axis);
  const auto begin = order_.begin() + static_cast<std::ptrdiff_t>(first);
  const auto middle = begin + static_cast<std::ptrdiff_t>(count / 2);
  const auto end = begin + static_cast<std::ptrdiff_t>(count);
  std::nth_element(begin, middle, end, [&](std::size_t s, std::size_t t) {
    return centroids_[s][axis] < centroids_[t][axis];
  });

  const std::size_t left = build_node(first, count / 2);
  const std::size_t right = build_node(first + count / 2, count - count / 2);
  nodes_[index].left = left;  // nodes_ may have reallocated: index, not reference
  nodes_[index].right = right;
  return index;
}

NearestTriangle TriangleBvh::nearest(const Vec3& p) const {
  NearestTriangle best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  search(0, p, best);
  return best;
}

void TriangleBvh::search(std::size_t node_index, const Vec3& p, NearestTriangle& best) const {
  const Node& node = nodes_[node_index];
  if (node.count > 0) {  // leaf: look at each triangle
    for (std::size_t n = node.first; n < node.first + node.count; ++n) {
      const std::size_t t = order_[n];
      const auto& v = triangles_[t];
      const Vec3 q = closest_point_on_triangle(p, v[0], v[1], v[2]);
      const double d2 = (q - p).squaredNorm();
      // Ties go to the lower triangle index, as in the brute-force scan.
      if (d2 < best.squared_distance || (d2 == best.squared_distance && t < best.triangle)) {
        best = NearestTriangle{t, q, d2};
      }
    }
    return;
  }
  const double left_bound = squared_distance_to_box(p, nodes_[node.left].box);
  const double right_bound = squared_distance_to_box(p, nodes_[node.right].box);
  const bool left_first = left_bound <= right_bound;
  const std::size_t near_child = left_first ? node.left : node.right;
  const std::size_t far_child = left_first ? node.right : node.left;
  const double near_bound = left_first ? left_bound : right_bound;
  const double far_bound = left_first ? right_bound : left_bound;
  // Visit unless the box is certainly farther than the best so far. "<=" because a box at exactly
  // the best distance may hold a tie with a lower index; the relative slack of 1e-12 covers the
  // rounding of the two squared distances (each within a few eps), so pruning never changes the
  // answer and the result equals the brute-force minimum bit for bit.
  const double cutoff = best.squared_distance * (1.0 + 1e-12);
  if (near_bound <= cutoff) search(near_child, p, best);
  if (far_bound <= cutoff) search(far_child, p, best);
}

NearestTriangle nearest_triangle_brute_force(const TriangleMesh& mesh, const Vec3& p) {
  NearestTriangle best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const auto& v = mesh.triangles[t].v;
    const Vec3 q = closest_point_on_triangle(p, v[0], v[1], v[2]);
    const double d2 = (q - p).squaredNorm();
    if (d2 < best.squared_distance) best = NearestTriangle{t, q, d2};
  }
  return best;
}

}  // namespace ppohdem::sdf::reference
