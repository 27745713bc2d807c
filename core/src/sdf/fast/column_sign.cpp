/// \file column_sign.cpp
/// Column crossings, parity and cone-closed winding numbers. See column_sign.hpp.
#include "ppohdem/sdf/fast/column_sign.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <cmath>
#include <numbers>
#include <tuple>

#include "ppohdem/sdf/fast/exact_orient2d.hpp"

namespace ppohdem::sdf::fast {

namespace {

/// The coordinates' bits of a vertex, with -0.0 turned into +0.0 (adding +0.0 does it): equal
/// keys are equal points (the coordinates are finite: check_inputs()).
struct VertexKey {
  std::uint64_t x, y, z;
  bool operator==(const VertexKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

VertexKey key_of(const Vec3& v) {
  return {std::bit_cast<std::uint64_t>(v.x() + 0.0), std::bit_cast<std::uint64_t>(v.y() + 0.0),
          std::bit_cast<std::uint64_t>(v.z() + 0.0)};
}

std::uint64_t mix(std::uint64_t h) {  // splitmix64's finaliser
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

struct WeldedSoup {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> faces;
};

/// Vertex ids in order of first appearance. An open-addressing table (linear probing, at most
/// half full) instead of a node-based std::unordered_map: one probe per corner mostly, and no
/// allocation per vertex (docs/performance.md "The whole voxelize process").
WeldedSoup weld(const TriangleMesh& mesh) {
  WeldedSoup soup;
  constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
  std::size_t size = 16;
  while (size < 6 * mesh.size()) size *= 2;  // > 2 x the corners: at most half full
  const std::size_t mask = size - 1;
  std::vector<std::uint32_t> slot(size, kEmpty);  // a vertex id, or kEmpty
  std::vector<VertexKey> keys;
  keys.reserve(mesh.size());
  soup.vertices.reserve(mesh.size());
  soup.faces.resize(mesh.size());
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      const Vec3& v = mesh.triangles[t].v[c];
      const VertexKey key = key_of(v);
      std::size_t at = mix(key.x ^ mix(key.y ^ mix(key.z))) & mask;
      while (slot[at] != kEmpty && !(keys[slot[at]] == key)) at = (at + 1) & mask;
      if (slot[at] == kEmpty) {
        slot[at] = static_cast<std::uint32_t>(soup.vertices.size());
        keys.push_back(key);
        soup.vertices.push_back(v);
      }
      soup.faces[t][c] = slot[at];
    }
  }
  return soup;
}

/// Directed edge uses, sorted by the undirected edge (low, high) then direction.
struct EdgeUse {
  std::uint32_t low, high;
  bool forward;  ///< low -> high
  bool operator<(const EdgeUse& o) const { return std::tie(low, high, forward) < std::tie(o.low, o.high, o.forward); }
};

/// The order of std::sort by (low, high, forward), made as a counting sort by `low` and a sort of
/// each vertex's uses, mostly a few (equal uses are identical, so the order is unique).
std::vector<EdgeUse> edge_uses(const WeldedSoup& soup) {
  std::vector<std::uint32_t> start(soup.vertices.size() + 1, 0);
  for (const auto& f : soup.faces) {
    for (std::size_t c = 0; c < 3; ++c) {
      const std::uint32_t from = f[c], to = f[(c + 1) % 3];
      if (from != to) ++start[std::min(from, to) + 1];
    }
  }
  for (std::size_t v = 0; v + 1 < start.size(); ++v) start[v + 1] += start[v];
  std::vector<EdgeUse> uses(start.back());
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (const auto& f : soup.faces) {
    for (std::size_t c = 0; c < 3; ++c) {
      const std::uint32_t from = f[c], to = f[(c + 1) % 3];
      if (from == to) continue;  // collapsed edge of a degenerate triangle
      const std::uint32_t low = std::min(from, to);
      uses[next[low]++] = {low, std::max(from, to), from < to};
    }
  }
  for (std::size_t v = 0; v + 1 < start.size(); ++v) {
    if (start[v + 1] - start[v] > 16) {  // a vertex of high valence (a fan's centre): n log n
      std::sort(uses.begin() + start[v], uses.begin() + start[v + 1]);
      continue;
    }
    for (std::uint32_t s = start[v] + 1; s < start[v + 1]; ++s) {
      const EdgeUse use = uses[s];
      std::uint32_t at = s;
      for (; at > start[v] && use < uses[at - 1]; --at) uses[at] = uses[at - 1];
      uses[at] = use;
    }
  }
  return uses;
}

/// Column indices n with origin + n h in [lo, hi], widened by one on each side (the exact
/// predicate decides), clamped to the grid (as the reference's column_range).
std::pair<int, int> column_range(double lo, double hi, double origin, double h, int count) {
  const double first = std::ceil((lo - origin) / h) - 1.0;
  const double last = std::floor((hi - origin) / h) + 1.0;
  const double max_index = static_cast<double>(count - 1);
  return {static_cast<int>(std::clamp(first, 0.0, max_index + 1.0)),
          static_cast<int>(std::clamp(last, -1.0, max_index))};
}

/// Height of the triangle's plane over p (barycentric in xy, clamped): the reference's
/// crossing_height, operation for operation, so both builders get bit-identical heights.
double crossing_height(const Vec3& a, const Vec3& b, const Vec3& c, double px, double py) {
  const double abx = b.x() - a.x(), aby = b.y() - a.y();
  const double acx = c.x() - a.x(), acy = c.y() - a.y();
  const double apx = px - a.x(), apy = py - a.y();
  const double twice_area = abx * acy - aby * acx;
  double beta = 1.0 / 3.0;
  double gamma = 1.0 / 3.0;
  if (twice_area != 0.0) {
    beta = std::clamp((apx * acy - apy * acx) / twice_area, 0.0, 1.0);
    gamma = std::clamp((abx * apy - aby * apx) / twice_area, 0.0, 1.0);
    if (beta + gamma > 1.0) {
      const double sum = beta + gamma;
      beta /= sum;
      gamma /= sum;
    }
  }
  return a.z() + beta * (b.z() - a.z()) + gamma * (c.z() - a.z());
}

/// Signed solid angle of (a, b, c) seen from p [sr] (Van Oosterom & Strackee 1983), as the
/// reference's solid_angle.
double solid_angle(const Vec3& p, const Vec3& av, const Vec3& bv, const Vec3& cv) {
  const Vec3 a = av - p, b = bv - p, c = cv - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace

EdgeCensus count_edges(const TriangleMesh& mesh) {
  const WeldedSoup soup = weld(mesh);
  const std::vector<EdgeUse> uses = edge_uses(soup);
  EdgeCensus census;
  census.welded_vertices = soup.vertices.size();
  for (std::size_t s = 0; s < uses.size();) {
    std::size_t e = s, forward = 0;
    while (e < uses.size() && uses[e].low == uses[s].low && uses[e].high == uses[s].high) {
      forward += uses[e].forward ? 1 : 0;
      ++e;
    }
    const std::size_t count = e - s;
    if (count == 1) ++census.boundary_edges;
    if (count >= 3) ++census.non_manifold_edges;
    if (count == 2 && forward != 1) ++census.misoriented_edges;
    s = e;
  }
  return census;
}

ColumnSign::ColumnSign(const TriangleMesh& mesh, const GridSpec& grid) : grid_(grid) {
  const WeldedSoup soup = weld(mesh);
  const std::vector<EdgeUse> uses = edge_uses(soup);
  census_.welded_vertices = soup.vertices.size();
  std::vector<std::tuple<std::uint32_t, std::uint32_t, int>> boundary;  // (from, to, multiplicity)
  for (std::size_t s = 0; s < uses.size();) {
    std::size_t e = s;
    int net = 0;  // uses(low -> high) - uses(high -> low)
    while (e < uses.size() && uses[e].low == uses[s].low && uses[e].high == uses[s].high) {
      net += uses[e].forward ? 1 : -1;
      ++e;
    }
    const std::size_t count = e - s;
    if (count == 1) ++census_.boundary_edges;
    if (count >= 3) ++census_.non_manifold_edges;
    if (count == 2 && net != 0) ++census_.misoriented_edges;
    if (net > 0) boundary.emplace_back(uses[s].low, uses[s].high, net);
    if (net < 0) boundary.emplace_back(uses[s].high, uses[s].low, -net);
    s = e;
  }
  winding_ = !census_.closed();

  if (winding_ && !boundary.empty()) {
    // The cone K over the chain boundary: triangle (v, u, C) cancels the directed edge u -> v.
    Vec3 apex = Vec3::Zero();
    std::vector<std::uint32_t> boundary_vertices;
    for (const auto& [from, to, m] : boundary) {
      boundary_vertices.push_back(from);
      boundary_vertices.push_back(to);
    }
    std::sort(boundary_vertices.begin(), boundary_vertices.end());
    boundary_vertices.erase(std::unique(boundary_vertices.begin(), boundary_vertices.end()), boundary_vertices.end());
    for (std::uint32_t v : boundary_vertices) apex += soup.vertices[v];
    apex /= static_cast<double>(boundary_vertices.size());
    for (const auto& [from, to, m] : boundary) {
      for (int copy = 0; copy < m; ++copy) {
        Triangle t;
        t.v = {soup.vertices[to], soup.vertices[from], apex};
        cone_.push_back(t);
      }
    }
  }

  // Crossings of every column with M (and K): (column, z, direction).
  const int nx = grid.nodes[0], ny = grid.nodes[1];
  struct Hit {
    std::uint32_t column;
    double z;
    std::int32_t direction;
  };
  std::vector<Hit> hits;
  auto add_triangle = [&](const Triangle& tri) {
    const Vec3 &a = tri.v[0], &b = tri.v[1], &c = tri.v[2];
    const int orientation = orient2d_sign(a.x(), a.y(), b.x(), b.y(), c.x(), c.y());
    if (orientation == 0) return;  // zero-area projection: parallel to the columns, never crossed
    const double lox = std::min({a.x(), b.x(), c.x()}), hix = std::max({a.x(), b.x(), c.x()});
    const double loy = std::min({a.y(), b.y(), c.y()}), hiy = std::max({a.y(), b.y(), c.y()});
    const auto [i0, i1] = column_range(lox, hix, grid.origin.x(), grid.spacing.x(), nx);
    const auto [j0, j1] = column_range(loy, hiy, grid.origin.y(), grid.spacing.y(), ny);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Vec3 column = grid.position(i, j, 0);
        const double px = column.x(), py = column.y();
        if (orient2d_sign_perturbed(a.x(), a.y(), b.x(), b.y(), px, py) != orientation) continue;
        if (orient2d_sign_perturbed(b.x(), b.y(), c.x(), c.y(), px, py) != orientation) continue;
        if (orient2d_sign_perturbed(c.x(), c.y(), a.x(), a.y(), px, py) != orientation) continue;
        hits.push_back({static_cast<std::uint32_t>(i + nx * j), crossing_height(a, b, c, px, py), orientation});
      }
    }
  };
  for (const Triangle& t : mesh.triangles) add_triangle(t);
  for (const Triangle& t : cone_) add_triangle(t);
  std::sort(hits.begin(), hits.end(), [](const Hit& s, const Hit& t) {
    return std::tie(s.column, s.z, s.direction) < std::tie(t.column, t.z, t.direction);
  });
  const std::size_t columns = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  column_start_.assign(columns + 1, 0);
  for (const Hit& h : hits) ++column_start_[h.column + 1];
  for (std::size_t c = 0; c < columns; ++c) column_start_[c + 1] += column_start_[c];
  crossings_.reserve(hits.size());
  for (const Hit& h : hits) crossings_.push_back({h.z, h.direction});
  // Winding: replace each direction by the suffix sum of directions from it to the column's top,
  // so "sum over crossings above z" is one lookup after a binary search.
  if (winding_) {
    for (std::size_t c = 0; c < columns; ++c) {
      std::int32_t suffix = 0;
      for (std::uint32_t s = column_start_[c + 1]; s-- > column_start_[c];) {
        suffix += crossings_[s].direction;
        crossings_[s].direction = suffix;
      }
    }
  }
}

std::vector<std::string> ColumnSign::warnings() const {
  std::vector<std::string> out;
  if (!winding_ && census_.misoriented_edges > 0) {
    out.push_back("mesh is closed but not consistently oriented (" + std::to_string(census_.misoriented_edges) +
                  " edges used twice in the same direction): sign from ray parity, which does not depend on "
                  "orientation");
  }
  if (winding_) {
    out.push_back("mesh is not watertight (" + std::to_string(census_.boundary_edges) + " boundary edges, " +
                  std::to_string(census_.non_manifold_edges) +
                  " non-manifold edges): sign from the generalized winding number");
  }
  return out;
}

void ColumnSign::inside_on_line(int j, int k, std::vector<char>& inside) const {
  const int nx = grid_.nodes[0];
  inside.assign(static_cast<std::size_t>(nx), 0);
  inside_on_segment(j, k, 0, nx, inside.data());
}

void ColumnSign::inside_on_segment(int j, int k, int i_begin, int i_end, char* inside) const {
  const int nx = grid_.nodes[0];
  const double z = grid_.position(0, j, k).z();
  for (int i = i_begin; i < i_end; ++i) {
    const std::size_t column = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * static_cast<std::size_t>(j);
    const auto begin = crossings_.begin() + column_start_[column];
    const auto end = crossings_.begin() + column_start_[column + 1];
    // First crossing strictly above z (ties count as not above, as in the reference).
    const auto first_above = std::upper_bound(begin, end, z, [](double value, const Crossing& c) { return value < c.z; });
    if (!winding_) {
      inside[i - i_begin] = (std::distance(first_above, end) % 2) == 1;
      continue;
    }
    const double integer_winding = first_above == end ? 0.0 : static_cast<double>(first_above->direction);
    double cone = 0.0;
    if (!cone_.empty()) {
      const Vec3 p = grid_.position(i, j, k);
      for (const Triangle& t : cone_) cone += solid_angle(p, t.v[0], t.v[1], t.v[2]);
      cone /= 4.0 * std::numbers::pi;
    }
    inside[i - i_begin] = (integer_winding - cone) > 0.5;
  }
}

void ColumnSign::inside_on_column(int i, int j, int k_begin, int k_end, char* inside, std::size_t stride) const {
  const int nx = grid_.nodes[0];
  const std::size_t column = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * static_cast<std::size_t>(j);
  const Crossing* const end = crossings_.data() + column_start_[column + 1];
  const Crossing* above = crossings_.data() + column_start_[column];
  if (k_begin < k_end) {  // the first node by binary search, as inside_on_segment
    const double z0 = grid_.position(0, j, k_begin).z();
    above = std::upper_bound(above, end, z0, [](double value, const Crossing& c) { return value < c.z; });
  }
  if (!winding_) {
    // Parity of the crossings above (the same walk as below), counted as an index difference:
    // (end - above) % 2 on the pointers would divide by sizeof(Crossing) at every node, a large
    // part of this loop's instructions.
    const std::size_t last = static_cast<std::size_t>(end - crossings_.data());
    std::size_t at = static_cast<std::size_t>(above - crossings_.data());
    for (int k = k_begin; k < k_end; ++k) {
      const double z = grid_.position(0, j, k).z();
      while (at != last && !(z < crossings_[at].z)) ++at;
      inside[static_cast<std::size_t>(k - k_begin) * stride] = static_cast<char>((last - at) & 1);
    }
    return;
  }
  for (int k = k_begin; k < k_end; ++k) {
    // z grows with k, so the first crossing strictly above z only moves up (same tie rule as
    // inside_on_segment's upper_bound: a crossing at z itself is not above).
    const double z = grid_.position(0, j, k).z();
    while (above != end && !(z < above->z)) ++above;
    char* out = inside + static_cast<std::size_t>(k - k_begin) * stride;
    if (!winding_) {
      *out = ((end - above) % 2) == 1;
      continue;
    }
    const double integer_winding = above == end ? 0.0 : static_cast<double>(above->direction);
    double cone = 0.0;
    if (!cone_.empty()) {
      const Vec3 p = grid_.position(i, j, k);
      for (const Triangle& t : cone_) cone += solid_angle(p, t.v[0], t.v[1], t.v[2]);
      cone /= 4.0 * std::numbers::pi;
    }
    *out = (integer_winding - cone) > 0.5;
  }
}

std::size_t ColumnSign::memory_bytes() const {
  return column_start_.capacity() * sizeof(std::uint32_t) + crossings_.capacity() * sizeof(Crossing) +
         cone_.capacity() * sizeof(Triangle);
}

}  // namespace ppohdem::sdf::fast
