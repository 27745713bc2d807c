#include "ppohdem/grid/grid_spec.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {

constexpr const char* kAxis[3] = {"x", "y", "z"};

std::string describe(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

void GridSpec::validate(const std::string& context) const {
  for (int a = 0; a < 3; ++a) {
    if (nodes[static_cast<std::size_t>(a)] < 1) {
      throw InputError(context, 0,
                       std::string("grid: expected a node count >= 1 along ") + kAxis[a] + ", found " +
                           std::to_string(nodes[static_cast<std::size_t>(a)]));
    }
    if (!std::isfinite(spacing[a]) || !(spacing[a] > 0.0)) {
      throw InputError(context, 0,
                       std::string("grid: expected a finite spacing > 0 along ") + kAxis[a] + ", found " +
                           number(spacing[a]));
    }
    if (!std::isfinite(origin[a])) {
      throw InputError(context, 0, std::string("grid: expected a finite origin along ") + kAxis[a] +
                                       ", found " + number(origin[a]));
    }
  }
}

GridSpec GridSpec::spanning(const Vec3& lo, const Vec3& hi, const Index3& nodes) {
  GridSpec g;
  g.origin = lo;
  g.nodes = nodes;
  for (int a = 0; a < 3; ++a) {
    const int n = nodes[static_cast<std::size_t>(a)];
    if (n < 2) {
      throw InputError(std::string("grid spanning a box: expected >= 2 nodes along ") + kAxis[a] +
                       ", found " + std::to_string(n));
    }
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]) || !(hi[a] > lo[a])) {
      throw InputError(std::string("grid spanning a box: expected finite lo < hi along ") + kAxis[a] +
                       ", found lo " + describe(lo) + ", hi " + describe(hi));
    }
    // h = (hi - lo) / (n - 1): node n-1 lands on hi up to one rounding.
    g.spacing[a] = (hi[a] - lo[a]) / static_cast<double>(n - 1);
  }
  g.validate("grid spanning a box");
  return g;
}

GridSpec GridSpec::ppohdem_legacy(const Vec3& length, const Index3& nodes) {
  GridSpec g;
  g.origin = Vec3::Zero();
  g.nodes = nodes;
  for (int a = 0; a < 3; ++a) {
    const int n = nodes[static_cast<std::size_t>(a)];
    if (n < 1) {
      throw InputError(std::string("legacy grid: expected a node count >= 1 along ") + kAxis[a] +
                       ", found " + std::to_string(n));
    }
    if (!std::isfinite(length[a]) || !(length[a] > 0.0)) {
      throw InputError(std::string("legacy grid: expected a finite length > 0 along ") + kAxis[a] +
                       ", found " + number(length[a]));
    }
    // The original computes the spacing as L / n (gridsize = Lx / gridX), not L / (n - 1).
    g.spacing[a] = length[a] / static_cast<double>(n);
  }
  return g;
}

bool operator==(const GridSpec& a, const GridSpec& b) {
  return a.origin == b.origin && a.spacing == b.spacing && a.nodes == b.nodes;
}

std::optional<std::size_t> checked_node_count(const Index3& nodes) {
  std::size_t count = 1;
  for (int n : nodes) {
    if (n < 1) return std::nullopt;
    const auto factor = static_cast<std::size_t>(n);
    if (count > std::numeric_limits<std::size_t>::max() / factor) return std::nullopt;
    count *= factor;
  }
  return count;
}

}  // namespace ppohdem
