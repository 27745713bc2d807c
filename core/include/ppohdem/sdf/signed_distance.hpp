#pragma once
/// \file signed_distance.hpp
/// The SdfBuilder interface shared by the reference, seed-pipeline and optimized builders.
/// Convention: phi(x) = +dist(x, surface) outside, -dist inside, in world units [m].
#include <memory>
#include <string>
#include <vector>

#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem {

struct SdfReport {
  std::vector<std::string> warnings;  ///< e.g. "mesh is not watertight: sign by winding number"
  double inside_fraction = 0.0;       ///< fraction of nodes with phi < 0
};

class SdfBuilder {
 public:
  virtual ~SdfBuilder() = default;
  /// Short method name as used by `--method` ("exact", "seed", "fast").
  virtual std::string name() const = 0;
  /// Signed distance of `mesh` at every node of `grid`.
  virtual ScalarField build(const TriangleMesh& mesh, const GridSpec& grid,
                            SdfReport* report = nullptr) const = 0;
};

}  // namespace ppohdem
