#pragma once
/// \file exact_sdf_builder.hpp
/// The "exact" reference builder: at every node,
///   phi(x) = s(x) min_t |x - closest_point(x, t)|    [m],   s = -1 inside, +1 outside,
/// the distance from the nearest triangle (TriangleBvh, Ericson's closest point) and the sign
/// from inside_classification.hpp (column ray parity for closed meshes, generalized winding number
/// otherwise). Exact up to rounding of the closest point (a few eps of the coordinates).
#include "ppohdem/sdf/signed_distance.hpp"

namespace ppohdem::sdf::reference {

class ExactSdfBuilder final : public SdfBuilder {
 public:
  std::string name() const override { return "exact"; }
  ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report = nullptr) const override;
};

/// Fraction of values < 0 (SdfReport::inside_fraction).
double negative_fraction(const ScalarField& phi);

}  // namespace ppohdem::sdf::reference
