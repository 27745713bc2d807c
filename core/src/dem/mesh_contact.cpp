// Exact sphere-mesh contacts (formulas and rules in mesh_contact.hpp; docs/objects.md
// "Exact contacts for mesh objects").
#include "ppohdem/dem/mesh_contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"

namespace ppohdem::dem {

// Ericson, Real-Time Collision Detection (2005), sec. 5.1.5, with the region reported; the
// interior point is the foot of the perpendicular (exactly along the normal).
TriangleClosest closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleClosest r;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, TriangleRegion::kVertex, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, TriangleRegion::kVertex, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {a + (d1 / (d1 - d3)) * ab, TriangleRegion::kEdge, 0};
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, TriangleRegion::kVertex, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {a + (d2 / (d2 - d6)) * ac, TriangleRegion::kEdge, 2};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return {b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), TriangleRegion::kEdge, 1};
  }
  const Vec3 n = ab.cross(ac).normalized();
  r.point = p - n.dot(ap) * n;
  r.region = TriangleRegion::kInterior;
  return r;
}

namespace {

// Union-find over triangles (flat faces).
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// CSR lists from (key, triangle) pairs in triangle order.
void build_csr(std::size_t keys, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
               std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& items) {
  first.assign(keys + 1, 0);
  for (const auto& [k, t] : pairs) ++first[k + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  items.resize(pairs.size());
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (const auto& [k, t] : pairs) items[fill[k]++] = t;
}

}  // namespace

MeshContactGeometry::MeshContactGeometry(const TriangleMesh& mesh) {
  // Weld bit-identical vertices, number the edges, in order of first appearance.
  std::map<std::array<double, 3>, std::uint32_t> vertex_ids;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_ids;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_pairs, vertex_pairs;
  TriangleMesh kept;  // non-degenerate triangles, for the tree (indices = triangles_)
  for (const Triangle& tri : mesh.triangles) {
    TriangleTopology t{};
    const Vec3 area = tri.area_vector();
    t.degenerate = !(area.norm() > 0.0);
    if (t.degenerate) continue;
    t.unit_normal = area.normalized();
    const auto index = static_cast<std::uint32_t>(triangles_.size());
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = tri.v[k];
      coordinate_scale_ = std::max(coordinate_scale_, v.cwiseAbs().maxCoeff());
      const auto [it, added] =
          vertex_ids.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, static_cast<std::uint32_t>(vertices_.size()));
      if (added) vertices_.push_back(v);
      t.vertex[k] = it->second;
      vertex_pairs.emplace_back(t.vertex[k], index);
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = t.vertex[k], w = t.vertex[(k + 1) % 3];
      const auto [it, added] = edge_ids.emplace(std::minmax(u, w), static_cast<std::uint32_t>(edge_ids.size()));
      t.edge[k] = it->second;
      edge_pairs.emplace_back(t.edge[k], index);
    }
    triangles_.push_back(t);
    kept.triangles.push_back(tri);
  }
  if (triangles_.empty()) throw InputError("mesh contact: the mesh has no triangle of non-zero area");
  edge_count_ = edge_ids.size();
  build_csr(edge_count_, edge_pairs, edge_first_, edge_triangles_);
  build_csr(vertices_.size(), vertex_pairs, vertex_first_, vertex_triangles_);

  // Flat faces: triangles joined across an edge where their normals differ by < kFlatAngle.
  std::vector<std::uint32_t> parent(triangles_.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::size_t e = 0; e < edge_count_; ++e) {
    for (std::uint32_t i = edge_first_[e]; i < edge_first_[e + 1]; ++i) {
      for (std::uint32_t j = i + 1; j < edge_first_[e + 1]; ++j) {
        const Vec3& n1 = triangles_[edge_triangles_[i]].unit_normal;
        const Vec3& n2 = triangles_[edge_triangles_[j]].unit_normal;
        if (n1.dot(n2) > 0.0 && n1.cross(n2).norm() < kFlatAngle) {
          parent[find_root(parent, edge_triangles_[i])] = find_root(parent, edge_triangles_[j]);
        }
      }
    }
  }
  std::vector<std::int64_t> face_of_root(triangles_.size(), -1);
  for (std::uint32_t t = 0; t < triangles_.size(); ++t) {
    std::int64_t& f = face_of_root[find_root(parent, t)];
    if (f < 0) f = static_cast<std::int64_t>(face_count_++);
    triangles_[t].face = static_cast<std::uint32_t>(f);
  }
  // An edge inside one face (two or more triangles, all of that face) is part of the face.
  edge_face_.assign(edge_count_, -1);
  for (std::size_t e = 0; e < edge_count_; ++e) {
    const std::uint32_t b = edge_first_[e], end = edge_first_[e + 1];
    if (end - b < 2) continue;  // an open border
    bool one = true;
    for (std::uint32_t i = b + 1; i < end; ++i) one = one && triangles_[edge_triangles_[i]].face == triangles_[edge_triangles_[b]].face;
    if (one) edge_face_[e] = triangles_[edge_triangles_[b]].face;
  }
  // A vertex whose triangles are all of one face and whose edges are all inside it.
  vertex_face_.assign(vertices_.size(), -1);
  for (std::size_t v = 0; v < vertices_.size(); ++v) {
    const std::uint32_t face = triangles_[vertex_triangles_[vertex_first_[v]]].face;
    bool inside = true;
    for (std::uint32_t i = vertex_first_[v]; i < vertex_first_[v + 1] && inside; ++i) {
      const TriangleTopology& t = triangles_[vertex_triangles_[i]];
      inside = t.face == face;
      for (int k = 0; k < 3 && inside; ++k) {
        const bool touches_v = t.vertex[k] == v || t.vertex[(k + 1) % 3] == v;
        if (touches_v) inside = edge_face_[t.edge[k]] == static_cast<std::int64_t>(face);
      }
    }
    if (inside) vertex_face_[v] = face;
  }
  tree_ = std::make_unique<sdf::fast::TriangleTree>(kept, coordinate_scale_, /*oriented_boxes=*/false);
}

MeshContactGeometry::~MeshContactGeometry() = default;
MeshContactGeometry::MeshContactGeometry(MeshContactGeometry&&) noexcept = default;
MeshContactGeometry& MeshContactGeometry::operator=(MeshContactGeometry&&) noexcept = default;

std::uint32_t MeshContactGeometry::feature_of_edge(std::uint32_t edge) const {
  if (edge_face_[edge] >= 0) return 1 + static_cast<std::uint32_t>(edge_face_[edge]);
  return static_cast<std::uint32_t>(1 + face_count_ + edge);
}

std::uint32_t MeshContactGeometry::feature_of_vertex(std::uint32_t vertex) const {
  if (vertex_face_[vertex] >= 0) return 1 + static_cast<std::uint32_t>(vertex_face_[vertex]);
  return static_cast<std::uint32_t>(1 + face_count_ + edge_count_ + vertex);
}

void MeshContactGeometry::contacts(const Vec3& centre, double radius, std::vector<MeshContact>& out) const {
  out.clear();
  if (!(radius > 0.0)) return;
  // 1. Candidates: triangles whose box is within R (+ the tree's round-off slack).
  thread_local std::vector<std::uint32_t> near;  // scratch, reused (the engines call this per particle)
  near.clear();
  const double reach = radius + tree_->slack();
  const double at[3] = {centre.x(), centre.y(), centre.z()};
  tree_->collect_near_box(at, at, reach * reach, near);
  struct Candidate {
    std::uint32_t triangle;  // index into triangles_
    TriangleClosest closest;
    double squared_distance;
  };
  thread_local std::vector<Candidate> found;
  found.clear();
  for (const std::uint32_t s : near) {
    const std::uint32_t t = tree_->triangles()[s].original_index;
    const TriangleTopology& tri = triangles_[t];
    const TriangleClosest q =
        closest_on_triangle(centre, vertices_[tri.vertex[0]], vertices_[tri.vertex[1]], vertices_[tri.vertex[2]]);
    const double d2 = (centre - q.point).squaredNorm();
    found.push_back({t, q, d2});
  }
  std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) { return x.triangle < y.triangle; });
  // Squared distance of triangle t to the centre (+inf if it is not a candidate: beyond R).
  const auto squared_distance_of = [&](std::uint32_t t) {
    const auto it = std::lower_bound(found.begin(), found.end(), t,
                                     [](const Candidate& x, std::uint32_t v) { return x.triangle < v; });
    return it != found.end() && it->triangle == t ? it->squared_distance : std::numeric_limits<double>::infinity();
  };
  const auto in_front = [&](std::uint32_t t) {
    const TriangleTopology& tri = triangles_[t];
    return (centre - vertices_[tri.vertex[0]]).dot(tri.unit_normal) > 0.0;
  };
  // 3. A local minimum among the triangles around [first, end) of `items`, seen from the front.
  const auto local_minimum = [&](const std::vector<std::uint32_t>& items, std::uint32_t first, std::uint32_t end,
                                 double d2) {
    bool front = false;
    for (std::uint32_t i = first; i < end; ++i) {
      if (squared_distance_of(items[i]) < d2) return false;
      front = front || in_front(items[i]);
    }
    return front;
  };
  const double r2 = radius * radius;
  for (const Candidate& cand : found) {
    if (!(cand.squared_distance < r2)) continue;
    const TriangleTopology& tri = triangles_[cand.triangle];
    std::uint32_t feature = 0;
    switch (cand.closest.region) {
      case TriangleRegion::kInterior:
        if (!in_front(cand.triangle)) continue;
        feature = 1 + tri.face;
        break;
      case TriangleRegion::kEdge: {
        const std::uint32_t e = tri.edge[cand.closest.index];
        if (!local_minimum(edge_triangles_, edge_first_[e], edge_first_[e + 1], cand.squared_distance)) continue;
        feature = feature_of_edge(e);
        break;
      }
      case TriangleRegion::kVertex: {
        const std::uint32_t v = tri.vertex[cand.closest.index];
        if (!local_minimum(vertex_triangles_, vertex_first_[v], vertex_first_[v + 1], cand.squared_distance)) continue;
        feature = feature_of_vertex(v);
        break;
      }
    }
    MeshContact c;
    if (cand.closest.region == TriangleRegion::kInterior || feature <= face_count_) {
      // A face (also at an edge or vertex inside a flat face): the foot of the centre on the
      // triangle's plane. At such an edge the edge's own point would differ from the foot by
      // the round-off of which triangle is nearer, and its direction by up to the square root
      // of it: a sideways push on a flat face.
      if (!in_front(cand.triangle)) continue;
      const double height = (centre - vertices_[tri.vertex[0]]).dot(tri.unit_normal);
      c.normal = tri.unit_normal;
      c.overlap = radius - height;
      c.point = centre - height * tri.unit_normal;
    } else {
      const double d = std::sqrt(cand.squared_distance);
      if (!(d > 0.0)) continue;  // centre on an edge or vertex: no direction
      c.normal = (centre - cand.closest.point) / d;
      c.overlap = radius - d;
      c.point = cand.closest.point;
    }
    c.feature = feature;
    out.push_back(c);
  }
  // 5. One contact per feature and per point: the nearest (largest overlap), ties: lower id.
  std::sort(out.begin(), out.end(), [](const MeshContact& x, const MeshContact& y) {
    return x.overlap != y.overlap ? x.overlap > y.overlap : x.feature < y.feature;
  });
  const double coincide = 1e-11 * (coordinate_scale_ + centre.cwiseAbs().maxCoeff() + radius);  // round-off of q
  thread_local std::vector<MeshContact> kept;
  kept.clear();
  for (const MeshContact& c : out) {
    const bool merged = std::any_of(kept.begin(), kept.end(), [&](const MeshContact& k) {
      return k.feature == c.feature || (k.point - c.point).norm() <= coincide;
    });
    if (!merged) kept.push_back(c);
  }
  std::sort(kept.begin(), kept.end(), [](const MeshContact& x, const MeshContact& y) { return x.feature < y.feature; });
  out.assign(kept.begin(), kept.end());
}

}  // namespace ppohdem::dem
