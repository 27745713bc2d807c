#pragma once
/// \file signed_distance.hpp
/// The SdfBuilder interface shared by the reference, seed-pipeline and optimized builders.
/// Convention: phi(x) = +dist(x, surface) outside, -dist inside, in world units [m].
#include <cstddef>
#include <functional>
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

/// Called now and then during a long build with (work done, total work); may print progress.
using SdfProgress = std::function<void(std::size_t done, std::size_t total)>;

class SdfBuilder {
 public:
  virtual ~SdfBuilder() = default;
  /// Optional progress callback (implementations call it at most every ~1% of the work).
  void set_progress(SdfProgress progress) { progress_ = std::move(progress); }
  /// Short method name as used by `--method` ("exact", "seed", "fast").
  virtual std::string name() const = 0;
  /// Signed distance of `mesh` at every node of `grid`.
  virtual ScalarField build(const TriangleMesh& mesh, const GridSpec& grid,
                            SdfReport* report = nullptr) const = 0;

 protected:
  void report_progress(std::size_t done, std::size_t total) const {
    if (progress_) progress_(done, total);
  }

 private:
  SdfProgress progress_;
};

}  // namespace ppohdem
