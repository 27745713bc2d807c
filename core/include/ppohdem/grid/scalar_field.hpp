#pragma once
/// \file scalar_field.hpp
/// A scalar per grid node (double), e.g. a signed distance [m] (negative inside).
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"

namespace ppohdem {

struct ScalarField {
  GridSpec grid;
  std::vector<double> values;  ///< grid.node_count() values, x fastest

  ScalarField() = default;
  explicit ScalarField(const GridSpec& g, double fill = 0.0) : grid(g), values(g.node_count(), fill) {}

  double& at(int i, int j, int k) { return values[grid.index(i, j, k)]; }
  double at(int i, int j, int k) const { return values[grid.index(i, j, k)]; }
};

}  // namespace ppohdem
