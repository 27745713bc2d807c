#pragma once
// Internal to reference/compat/src: the original's MPI x-slabs, simulated in one process.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ppohdem/geometry/vector.hpp"
#include "ppohdem/compat/ppohdem10_steps.hpp"

namespace ppohdem::compat {

/// A 0/1 flag per node of the full grid, addressed with the original's 1-based (i, j, k).
class NodeFlags {
 public:
  explicit NodeFlags(const Index3& nodes)
      : nx_(nodes[0]), ny_(nodes[1]),
        flags_(static_cast<std::size_t>(nodes[0]) * static_cast<std::size_t>(nodes[1]) *
                   static_cast<std::size_t>(nodes[2]),
               0) {}
  std::uint8_t operator()(int i, int j, int k) const { return flags_[index(i, j, k)]; }
  std::uint8_t& operator()(int i, int j, int k) { return flags_[index(i, j, k)]; }
  const std::vector<std::uint8_t>& gridspec_order() const { return flags_; }

 private:
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i - 1) +
           static_cast<std::size_t>(nx_) *
               (static_cast<std::size_t>(j - 1) + static_cast<std::size_t>(ny_) * static_cast<std::size_t>(k - 1));
  }
  int nx_, ny_;
  std::vector<std::uint8_t> flags_;
};

/// One rank's distance_3D(i_x_start-1 : i_x_end+1, 1:gridY, 1:gridZ): its own planes
/// first..last (1-based global i) plus one ghost plane on each side.
struct RankSlab {
  RankSlab(int rank, int nprocs, int first, int last, const Index3& nodes, double fill);

  int rank, nprocs;
  int first, last;                ///< own planes (i_x_start, i_x_end)
  int ny, nz, nx;
  int sweep_first = 0, sweep_last = 0;  ///< loopX_start, loopX_end

  double& at(int i, int j, int k) { return planes_[offset(i, j, k)]; }
  double at(int i, int j, int k) const { return planes_[offset(i, j, k)]; }
  /// Storage index of global node (i, j, k): planes first-1..last+1, x fastest.
  std::size_t offset(int i, int j, int k) const {
    return static_cast<std::size_t>(i - (first - 1)) + stride_j_ * static_cast<std::size_t>(j - 1) +
           stride_k_ * static_cast<std::size_t>(k - 1);
  }
  std::size_t planes_size() const { return planes_.size(); }

 private:
  std::size_t stride_j_ = 0;  ///< planes per row: last - first + 3
  std::size_t stride_k_ = 0;  ///< stride_j_ * gridY
  std::vector<double> planes_;
};

/// Copy the neighbours' edge planes into every rank's ghost planes (the MPI_SEND/RECV pair at
/// the start of each sweep).
void exchange_ghost_planes(std::vector<RankSlab>& ranks);

/// ppohDEM_v_distancecalculate_MPI on all ranks: reset, gridZ Jacobi sweeps, boundary
/// extrapolation.
void jacobi_pass(std::vector<RankSlab>& ranks, const Ppohdem10Grid& grid, const NodeFlags& value,
                 const NodeFlags& calculated);

}  // namespace ppohdem::compat
