/// \file exact_sdf_builder.cpp
/// phi = sign x distance to the nearest triangle, at every node. See exact_sdf_builder.hpp.
#include "ppohdem/sdf/reference/exact_sdf_builder.hpp"

#include <cmath>

#include "ppohdem/sdf/reference/inside_classification.hpp"
#include "ppohdem/sdf/reference/triangle_bvh.hpp"

namespace ppohdem::sdf::reference {

double negative_fraction(const ScalarField& phi) {
  if (phi.values.empty()) return 0.0;
  std::size_t negative = 0;
  for (double value : phi.values) negative += value < 0.0 ? 1 : 0;
  return static_cast<double>(negative) / static_cast<double>(phi.values.size());
}

ScalarField ExactSdfBuilder::build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) const {
  check_sdf_inputs(mesh, grid, "exact SDF builder");
  const InsideClassification classification = classify_inside_nodes(mesh, grid);
  const TriangleBvh bvh(mesh);

  ScalarField phi(grid);
  for (int k = 0; k < grid.nodes[2]; ++k) {
    for (int j = 0; j < grid.nodes[1]; ++j) {
      for (int i = 0; i < grid.nodes[0]; ++i) {
        const double distance = std::sqrt(bvh.nearest(grid.position(i, j, k)).squared_distance);
        phi.at(i, j, k) = classification.inside[grid.index(i, j, k)] ? -distance : distance;
      }
    }
    report_progress(static_cast<std::size_t>(k + 1), static_cast<std::size_t>(grid.nodes[2]));
  }

  if (report != nullptr) {
    report->warnings.insert(report->warnings.end(), classification.warnings.begin(), classification.warnings.end());
    report->inside_fraction = negative_fraction(phi);
  }
  return phi;
}

}  // namespace ppohdem::sdf::reference
