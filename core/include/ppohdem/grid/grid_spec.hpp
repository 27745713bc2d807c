#pragma once
/// \file grid_spec.hpp
/// A regular grid of *nodes*: node (i, j, k), 0-based, sits at origin + (i, j, k) .* spacing
/// (world units). Values are stored with x fastest: index = i + nx (j + ny k), the order of
/// VTK STRUCTURED_POINTS and of the original program's distance files.
#include <cstddef>
#include <optional>
#include <string>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem {

struct GridSpec {
  Vec3 origin = Vec3::Zero();   ///< position of node (0,0,0) [m]
  Vec3 spacing = Vec3::Ones();  ///< node spacing h per axis [m]
  Index3 nodes = {1, 1, 1};     ///< node count per axis (>= 1)

  std::size_t node_count() const {
    return static_cast<std::size_t>(nodes[0]) * static_cast<std::size_t>(nodes[1]) *
           static_cast<std::size_t>(nodes[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(nodes[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(nodes[1]) * static_cast<std::size_t>(k));
  }
  Vec3 position(int i, int j, int k) const {
    return origin + Vec3(i * spacing.x(), j * spacing.y(), k * spacing.z());
  }
  /// Position of the last node (origin + (n - 1) h).
  Vec3 upper_corner() const { return position(nodes[0] - 1, nodes[1] - 1, nodes[2] - 1); }
  /// Smallest spacing [m], the "h" that errors are reported in.
  double min_spacing() const { return spacing.minCoeff(); }

  /// Throws InputError unless every count >= 1 and every spacing is finite and > 0.
  void validate(const std::string& context = {}) const;

  /// Grid with nodes[a] nodes spanning [lo_a, hi_a] inclusive: h = (hi - lo) / (n - 1)
  /// (the `ppohdem voxelize --cells --box` form). Needs n >= 2 and hi > lo.
  static GridSpec spanning(const Vec3& lo, const Vec3& hi, const Index3& nodes);
  /// The original program's grid: n nodes at x = (L / n) (i - 1), i = 1..n, i.e. origin 0,
  /// h = L / n, covering [0, L - h].
  static GridSpec ppohdem_legacy(const Vec3& length, const Index3& nodes);
};

bool operator==(const GridSpec& a, const GridSpec& b);

/// nodes[0] * nodes[1] * nodes[2], or nullopt if a count is < 1 or the product does not fit in
/// size_t (readers check this before trusting GridSpec::node_count() with counts from a file).
std::optional<std::size_t> checked_node_count(const Index3& nodes);

}  // namespace ppohdem
