#pragma once
/// \file fast_sdf_builder.hpp
/// The optimized SDF builder ("fast"): exact everywhere (or, in band mode, exact in a band and
/// an upper bound by closest-triangle transfer outside), OpenMP over bricks of 8^3 nodes, MPI
/// over z-slabs. Same contract and convention as sdf::reference::ExactSdfBuilder:
///   phi(x) = s(x) min_t |x - closest_point(x, t)|   [m],  s = -1 inside, +1 outside.
///
/// How (see docs/performance.md "How the fast builder works"):
///  - distance: bricks of 8^3 nodes (brick_distance.hpp); exact mode queries the BVH once per
///    node, 8 nodes per traversal in SIMD lanes, warm-started from a neighbour's nearest
///    triangle; band mode collects per brick the triangles that can be nearest to a node within
///    the band (Lipschitz bound from the brick centre's exact distance), halved boxes filter them
///    further, and each node takes the minimum over its box's few candidates;
///  - sign: crossings of the z-columns (column_sign.hpp): exact parity for closed meshes, the
///    cone-closed winding number for open ones;
///  - determinism: every node's value is a pure function of the node and the mesh (the
///    pruning is conservative, see brick_distance.hpp; band mode: of the node's global brick),
///    bricks are independent, nothing is
///    reduced across threads or ranks: the field is bitwise the same for any thread count,
///    any slab split and any number of MPI ranks.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/sdf/signed_distance.hpp"

namespace ppohdem::sdf::fast {

enum class FieldPrecision { float64, float32 };

/// Work counters of the fast builder (summed over threads; for profiling and the docs).
struct FastSdfCounters {
  std::size_t exact_nodes = 0;           ///< nodes given the exact minimum over all triangles
  std::size_t transferred_nodes = 0;     ///< band mode: nodes outside the band (transferred triangles)
  std::size_t candidate_tests = 0;       ///< bounding-box tests in the per-node candidate scans
  std::size_t distance_evaluations = 0;  ///< exact point-triangle distances
};

struct FastSdfOptions {
  int threads = 0;  ///< OpenMP threads; 0 = the OpenMP default (OMP_NUM_THREADS or all cores)
  /// Band mode: 0 (default) = exact everywhere. W > 0: exact wherever |phi| <= W h_max
  /// (h_max the largest spacing); farther nodes get the exact distance to one triangle
  /// transferred from the surrounding brick centres (an upper bound; the sign is exact
  /// everywhere). See brick_distance.hpp and docs/performance.md "Targets" for the measured error.
  double band_cells = 0.0;
  /// Exact nodes by the shared-candidate scheme of brick_distance.hpp instead of one BVH query per
  /// node. Same field bit for bit (both are the exact minimum); more instructions per node
  /// (docs/performance.md "How the fast builder works"), kept as the documented alternative and
  /// tested for equality.
  bool shared_candidates = false;
  /// If not null, the build adds its work counters here (not synchronized across builds).
  FastSdfCounters* counters = nullptr;
};

/// A z-slab of nodes: k in [k_begin, k_end), all i and j.
struct SlabRange {
  int k_begin = 0;
  int k_end = 0;
  std::size_t node_count(const GridSpec& grid) const {
    return static_cast<std::size_t>(k_end - k_begin) * static_cast<std::size_t>(grid.nodes[0]) *
           static_cast<std::size_t>(grid.nodes[1]);
  }
};

/// Rank r of `ranks` gets planes [r nz / ranks, (r + 1) nz / ranks) (integer division): contiguous,
/// in rank order, sizes differing by at most one. A rank may get an empty slab if ranks > nz.
SlabRange slab_of_rank(int nz, int rank, int ranks);

class FastSdfBuilder final : public SdfBuilder {
 public:
  explicit FastSdfBuilder(FastSdfOptions options = {}) : options_(options) {}
  std::string name() const override { return "fast"; }
  const FastSdfOptions& options() const { return options_; }

  ScalarField build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report = nullptr) const override;

  /// The nodes of `slab` (x fastest, then y, then z from slab.k_begin) into `out`, whose size
  /// must be slab.node_count(grid). Float output is the double result rounded to nearest.
  void build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab, std::span<double> out,
                  SdfReport* report = nullptr) const;
  void build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab, std::span<float> out,
                  SdfReport* report = nullptr) const;
  /// The same into `out`, which is sized to the slab while the tree is built (its zeroing and
  /// first page faults then overlap the setup instead of preceding it).
  void build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab, std::vector<double>& out,
                  SdfReport* report = nullptr) const;
  void build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab, std::vector<float>& out,
                  SdfReport* report = nullptr) const;

 private:
  /// `sized`: if not null, `out` is ignored and the output is *sized, resized during the setup.
  template <typename T>
  void build_slab_impl(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab, std::span<T> out,
                       std::vector<T>* sized, SdfReport* report) const;
  FastSdfOptions options_;
};

std::unique_ptr<SdfBuilder> make_fast_sdf_builder(FastSdfOptions options = {});

/// The field computed by all ranks of `comm`, each its slab_of_rank(); rank 0 gets the whole
/// field, other ranks an empty `values`. With one rank no copy is made.
/// `report` (may be null) is filled on rank 0; inside_fraction covers the whole grid.
ScalarField build_sdf_distributed(const FastSdfBuilder& builder, const Comm& comm, const TriangleMesh& mesh,
                                  const GridSpec& grid, SdfReport* report = nullptr);

/// The same in float storage (half the memory): values on rank 0, empty elsewhere.
std::vector<float> build_sdf_distributed_float(const FastSdfBuilder& builder, const Comm& comm,
                                               const TriangleMesh& mesh, const GridSpec& grid,
                                               SdfReport* report = nullptr);

}  // namespace ppohdem::sdf::fast

namespace ppohdem {
/// Peak resident memory of this process so far [bytes] (getrusage ru_maxrss; 0 if unknown).
std::size_t peak_resident_bytes();
}  // namespace ppohdem
