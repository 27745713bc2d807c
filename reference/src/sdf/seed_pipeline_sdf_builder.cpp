/// \file seed_pipeline_sdf_builder.cpp
/// The original ppohDEM pipeline made correct: crosslist parity, exact band, fast sweeping.
/// See seed_pipeline_sdf_builder.hpp and docs/sdf.md.
#include "ppohdem/sdf/reference/seed_pipeline_sdf_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/reference/closest_point_triangle.hpp"
#include "ppohdem/sdf/reference/exact_sdf_builder.hpp"
#include "ppohdem/sdf/reference/fast_sweeping.hpp"
#include "ppohdem/sdf/reference/triangle_bvh.hpp"

namespace ppohdem::sdf::reference {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Node indices n with origin + n h in [lo, hi] on one axis, clamped to the grid (may be empty).
std::pair<int, int> node_range(double lo, double hi, double origin, double h, int count) {
  const double first = std::ceil((lo - origin) / h);
  const double last = std::floor((hi - origin) / h);
  const double max_index = static_cast<double>(count - 1);
  return {static_cast<int>(std::clamp(first, 0.0, max_index + 1.0)),
          static_cast<int>(std::clamp(last, -1.0, max_index))};
}

}  // namespace

ScalarField exact_distance_in_band(const TriangleMesh& mesh, const GridSpec& grid, double band_radius) {
  ScalarField squared(grid, kInfinity);
  const Vec3 reach = Vec3::Constant(band_radius);
  for (const Triangle& t : mesh.triangles) {
    BoundingBox box;
    for (const Vec3& v : t.v) box.expand(v);
    // Grown by one extra rounding's worth so that a node at exactly r is not lost to the division.
    const Vec3 lo = box.min - reach - grid.spacing * 1e-9;
    const Vec3 hi = box.max + reach + grid.spacing * 1e-9;
    const auto [i0, i1] = node_range(lo.x(), hi.x(), grid.origin.x(), grid.spacing.x(), grid.nodes[0]);
    const auto [j0, j1] = node_range(lo.y(), hi.y(), grid.origin.y(), grid.spacing.y(), grid.nodes[1]);
    const auto [k0, k1] = node_range(lo.z(), hi.z(), grid.origin.z(), grid.spacing.z(), grid.nodes[2]);
    for (int k = k0; k <= k1; ++k) {
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const double d2 = squared_distance_to_triangle(grid.position(i, j, k), t.v[0], t.v[1], t.v[2]);
          squared.at(i, j, k) = std::min(squared.at(i, j, k), d2);
        }
      }
    }
  }
  // A node farther than r from its nearest scanned triangle may have a nearer unscanned one:
  // keep only distances <= r, which are then the true nearest-triangle distances.
  ScalarField distance(grid, kInfinity);
  for (std::size_t n = 0; n < squared.values.size(); ++n) {
    const double d = std::sqrt(squared.values[n]);
    if (d <= band_radius) distance.values[n] = d;
  }
  return distance;
}

SeedPipelineSdfBuilder::SeedPipelineSdfBuilder(double band_in_h) : band_in_h_(band_in_h) {
  if (!(band_in_h >= 1.0) || !std::isfinite(band_in_h)) {
    throw InputError("seed SDF builder: expected a band half-width of at least 1 cell, found " +
                     std::to_string(band_in_h));
  }
}

SeedPipelineResult SeedPipelineSdfBuilder::run(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) const {
  check_sdf_inputs(mesh, grid, "seed SDF builder");
  SeedPipelineResult result;

  // makecrosslist + makegridout (or the winding number for an open mesh).
  const InsideClassification classification = classify_inside_nodes(mesh, grid);
  result.sign_method = classification.method;
  std::vector<std::string> warnings = classification.warnings;

  // distanceprecise: the exact band.
  const double band_radius = band_in_h_ * grid.spacing.maxCoeff();
  ScalarField distance = exact_distance_in_band(mesh, grid, band_radius);
  result.band.assign(grid.node_count(), false);
  for (std::size_t n = 0; n < distance.values.size(); ++n) {
    result.band[n] = distance.values[n] != kInfinity;
    result.band_nodes += result.band[n] ? 1 : 0;
  }

  // distancecalculate: sweep the rest from the frozen band.
  if (result.band_nodes > 0) {
    result.sweeps = fast_sweep(distance, result.band);
  } else {
    // Nothing to sweep from (every node farther than r from the surface): exact distances.
    warnings.push_back("no grid node lies within the band of the surface: distances computed exactly");
    const TriangleBvh bvh(mesh);
    for (int k = 0; k < grid.nodes[2]; ++k)
      for (int j = 0; j < grid.nodes[1]; ++j)
        for (int i = 0; i < grid.nodes[0]; ++i)
          distance.at(i, j, k) = std::sqrt(bvh.nearest(grid.position(i, j, k)).squared_distance);
  }

  // Sign.
  result.phi = std::move(distance);
  for (std::size_t n = 0; n < result.phi.values.size(); ++n) {
    if (classification.inside[n]) result.phi.values[n] = -result.phi.values[n];
  }

  if (report != nullptr) {
    report->warnings.insert(report->warnings.end(), warnings.begin(), warnings.end());
    report->inside_fraction = negative_fraction(result.phi);
  }
  return result;
}

ScalarField SeedPipelineSdfBuilder::build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) const {
  return run(mesh, grid, report).phi;
}

}  // namespace ppohdem::sdf::reference
