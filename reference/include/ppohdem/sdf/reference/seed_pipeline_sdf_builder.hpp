#pragma once
/// \file seed_pipeline_sdf_builder.hpp
/// The "seed" builder: the original ppohDEM DEM-Util pipeline, step for step, each step made
/// correct (docs/sdf.md has the side-by-side table):
///
///  original subroutine              here
///  ppohDEM_v_makecrosslist    ->    make_cross_list        (ray_parity.hpp, exact predicates)
///  ppohDEM_v_makegridout      ->    inside_by_column_parity (or the winding number, open meshes)
///  ppohDEM_v_distanceprecise  ->    exact_distance_in_band: for each triangle, every node in its
///                                   bounding box grown by r = band_in_h h gets
///                                   d = min(d, |x - closest_point(x, t)|); nodes with d <= r are
///                                   the band (exactly the exact builder's distances there).
///  ppohDEM_v_distancecalculate ->   fast_sweep (Zhao 2005 Gauss-Seidel, to convergence) of the
///                                   unsigned distance from the frozen band; then phi = s d.
///
/// h is the LARGEST spacing so that the band is at least band_in_h cells thick on every axis.
/// The original's band is 2 sqrt(3) h (every node whose 3x3x3 neighbourhood meets the surface).
#include <vector>

#include "ppohdem/sdf/reference/inside_classification.hpp"
#include "ppohdem/sdf/signed_distance.hpp"

namespace ppohdem::sdf::reference {

/// Unsigned distance at the nodes within `band_radius` [m] of the surface, +inf elsewhere.
ScalarField exact_distance_in_band(const TriangleMesh& mesh, const GridSpec& grid, double band_radius);

/// Everything the pipeline computed, for tests and for the lecture.
struct SeedPipelineResult {
  ScalarField phi;                 ///< signed distance [m]
  std::vector<bool> band;          ///< node was in the exact band (frozen during sweeping)
  std::size_t band_nodes = 0;
  int sweeps = 0;                  ///< fast-sweeping sweeps until no value changed
  SignMethod sign_method = SignMethod::ray_parity;
};

class SeedPipelineSdfBuilder final : public SdfBuilder {
 public:
  /// 2 sqrt(3): the original program's band half-width in cells.
  static constexpr double kOriginalBandInH = 3.4641016151377544;

  explicit SeedPipelineSdfBuilder(double band_in_h = kOriginalBandInH);

  std::string name() const override { return "seed"; }
  ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report = nullptr) const override;

  /// build() with all intermediate results.
  SeedPipelineResult run(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report = nullptr) const;

  double band_in_h() const { return band_in_h_; }

 private:
  double band_in_h_;
};

}  // namespace ppohdem::sdf::reference
