#include "ppohdem/sdf/field_metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "ppohdem/error.hpp"

namespace ppohdem {
namespace {

std::string describe(const GridSpec& g) {
  std::ostringstream out;
  out << std::setprecision(17) << g.nodes[0] << "x" << g.nodes[1] << "x" << g.nodes[2]
      << " nodes, origin (" << g.origin.x() << ", " << g.origin.y() << ", " << g.origin.z()
      << "), spacing (" << g.spacing.x() << ", " << g.spacing.y() << ", " << g.spacing.z() << ")";
  return out.str();
}

// Exact comparison on purpose: two fields are only comparable node by node if every node
// sits at the same position.
bool same_grid(const GridSpec& a, const GridSpec& b) {
  return a.nodes == b.nodes && a.origin == b.origin && a.spacing == b.spacing;
}

void check_values(const ScalarField& f, const char* which) {
  if (f.values.size() != f.grid.node_count()) {
    throw InputError(std::string("compare_fields: ") + which + " field has " +
                     std::to_string(f.values.size()) + " values, its grid has " +
                     std::to_string(f.grid.node_count()) + " nodes");
  }
}

// Running sum for one ErrorStats set.
struct Accumulator {
  ErrorStats stats;
  double sum_sq = 0.0;  // sum of e^2 [h^2]

  void add(double e, const Index3& node) {
    ++stats.nodes;
    sum_sq += e * e;
    if (e > stats.max_error_h || stats.worst_node[0] < 0) {
      stats.max_error_h = e;
      stats.worst_node = node;
    }
  }
  ErrorStats finish() const {
    ErrorStats s = stats;
    s.rms_error_h = s.nodes == 0 ? 0.0 : std::sqrt(sum_sq / static_cast<double>(s.nodes));
    return s;
  }
};

}  // namespace

FieldComparison compare_fields(const ScalarField& candidate, const ScalarField& oracle,
                               double band_in_h, double sign_tolerance_in_h) {
  if (!same_grid(candidate.grid, oracle.grid)) {
    throw InputError("compare_fields: grids differ: candidate " + describe(candidate.grid) +
                     ", oracle " + describe(oracle.grid));
  }
  if (!(std::isfinite(band_in_h) && band_in_h >= 0.0)) {
    throw InputError("compare_fields: band must be finite and >= 0 (in h), got " +
                     std::to_string(band_in_h));
  }
  if (!(std::isfinite(sign_tolerance_in_h) && sign_tolerance_in_h >= 0.0)) {
    throw InputError("compare_fields: sign tolerance must be finite and >= 0 (in h), got " +
                     std::to_string(sign_tolerance_in_h));
  }
  check_values(candidate, "candidate");
  check_values(oracle, "oracle");

  const GridSpec& g = oracle.grid;
  FieldComparison result;
  result.h = g.min_spacing();
  result.band_in_h = band_in_h;
  result.sign_tolerance_in_h = sign_tolerance_in_h;
  const double band = band_in_h * result.h;                  // [world units]
  const double sign_tolerance = sign_tolerance_in_h * result.h;  // [world units]
  constexpr double kInf = std::numeric_limits<double>::infinity();

  Accumulator all;
  Accumulator in_band;
  for (int k = 0; k < g.nodes[2]; ++k) {
    for (int j = 0; j < g.nodes[1]; ++j) {
      for (int i = 0; i < g.nodes[0]; ++i) {
        const std::size_t n = g.index(i, j, k);
        const double c = candidate.values[n];
        const double o = oracle.values[n];
        if (!std::isfinite(o)) {
          throw InputError("compare_fields: oracle value at node (" + std::to_string(i) + ", " +
                           std::to_string(j) + ", " + std::to_string(k) + ") is not finite");
        }
        const bool finite = std::isfinite(c);
        if (!finite) ++result.non_finite_candidate;
        const double diff = finite ? std::abs(c - o) : kInf;  // [world units]
        const double e = diff / result.h;                      // [h]
        const Index3 node = {i, j, k};
        all.add(e, node);
        if (std::abs(o) < band) in_band.add(e, node);
        if (std::abs(o) > sign_tolerance) {
          ++result.sign_checked_nodes;
          const bool same_sign = o > 0.0 ? c > 0.0 : c < 0.0;  // NaN and 0 never match
          if (!same_sign) ++result.sign_mismatches;
        }
        const double relative = diff / std::max(std::abs(o), std::numeric_limits<double>::min());
        result.max_relative_error = std::max(result.max_relative_error, relative);
      }
    }
  }
  result.all = all.finish();
  result.band = in_band.finish();
  return result;
}

double lipschitz_ratio(const ScalarField& field) {
  const GridSpec& g = field.grid;
  if (field.values.size() != g.node_count()) {
    throw InputError("lipschitz_ratio: field has " + std::to_string(field.values.size()) +
                     " values, its grid has " + std::to_string(g.node_count()) + " nodes");
  }
  // The 13 "forward" offsets of the 26-neighbourhood: each unordered neighbour pair is visited
  // exactly once (the other 13 offsets are their negatives).
  std::array<Index3, 13> offsets{};
  std::size_t count = 0;
  for (int dk = -1; dk <= 1; ++dk) {
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        const bool forward = dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0)));
        if (forward) offsets[count++] = {di, dj, dk};
      }
    }
  }
  double ratio = 0.0;
  for (const Index3& d : offsets) {
    const double length = Vec3(d[0] * g.spacing.x(), d[1] * g.spacing.y(), d[2] * g.spacing.z())
                              .norm();  // |x_a - x_b| [world units]
    for (int k = std::max(0, -d[2]); k < std::min(g.nodes[2], g.nodes[2] - d[2]); ++k) {
      for (int j = std::max(0, -d[1]); j < std::min(g.nodes[1], g.nodes[1] - d[1]); ++j) {
        for (int i = std::max(0, -d[0]); i < std::min(g.nodes[0], g.nodes[0] - d[0]); ++i) {
          const double a = field.values[g.index(i, j, k)];
          const double b = field.values[g.index(i + d[0], j + d[1], k + d[2])];
          const double r = std::abs(a - b) / length;
          if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
          ratio = std::max(ratio, r);
        }
      }
    }
  }
  return ratio;
}

std::string format_comparison(const FieldComparison& c) {
  std::ostringstream out;
  auto row = [&out](const std::string& label, const std::string& value) {
    out << std::left << std::setw(34) << label << value << '\n';
  };
  auto num = [](double v) {
    std::ostringstream s;
    s << std::setprecision(6) << v;
    return s.str();
  };
  auto node = [](const Index3& n) {
    std::ostringstream s;  // (not "(" + std::string: GCC 12 gives a false -Wrestrict there)
    s << '(' << n[0] << ", " << n[1] << ", " << n[2] << ')';
    return s.str();
  };
  row("h [world units]", num(c.h));
  row("band |oracle| < [h]", num(c.band_in_h));
  row("band nodes", std::to_string(c.band.nodes));
  row("band max |error| [h]", num(c.band.max_error_h) + " at " + node(c.band.worst_node));
  row("band RMS error [h]", num(c.band.rms_error_h));
  row("all nodes", std::to_string(c.all.nodes));
  row("all max |error| [h]", num(c.all.max_error_h) + " at " + node(c.all.worst_node));
  row("all RMS error [h]", num(c.all.rms_error_h));
  row("max relative error", num(c.max_relative_error));
  row("sign-checked nodes (|o| > tol)", std::to_string(c.sign_checked_nodes) + " (tol " +
                                            num(c.sign_tolerance_in_h) + " h)");
  row("sign mismatches", std::to_string(c.sign_mismatches));
  row("non-finite candidate values", std::to_string(c.non_finite_candidate));
  return out.str();
}

}  // namespace ppohdem
