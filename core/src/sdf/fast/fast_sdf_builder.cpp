/// \file fast_sdf_builder.cpp
/// The "fast" builder: BVH nearest queries warm-started along x-lines, column signs, OpenMP over
/// lines, MPI over z-slabs. See fast_sdf_builder.hpp.
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <cmath>
#include <cstdint>
#include <exception>
#include <functional>
#include <optional>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/fast/brick_distance.hpp"
#include "ppohdem/sdf/fast/column_sign.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"
#include "ppohdem/simd_level.hpp"

#if defined(PPOHDEM_WITH_OPENMP)
#include <omp.h>
#endif

namespace ppohdem::sdf::fast {

namespace {

void check_inputs(const TriangleMesh& mesh, const GridSpec& grid) {
  const std::string who = "fast SDF builder";
  if (mesh.empty()) throw InputError(who + ": expected a mesh with at least one triangle, found none");
  if (mesh.size() >= (std::size_t{1} << 31)) throw InputError(who + ": more than 2^31 triangles");
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    for (const Vec3& v : mesh.triangles[t].v) {
      if (!v.allFinite()) throw InputError(who + ": triangle " + std::to_string(t) + " has a non-finite vertex coordinate");
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    const double h = grid.spacing[axis];
    const int n = grid.nodes[static_cast<std::size_t>(axis)];
    if (n < 1 || !std::isfinite(h) || !(h > 0.0) || !std::isfinite(grid.origin[axis])) {
      throw InputError(who + ": expected a grid with >= 1 node and a finite spacing > 0 on axis " +
                       std::to_string(axis) + ", found " + std::to_string(n) + " nodes, spacing " + std::to_string(h));
    }
  }
  const std::size_t columns = static_cast<std::size_t>(grid.nodes[0]) * static_cast<std::size_t>(grid.nodes[1]);
  if (columns >= (std::size_t{1} << 32)) throw InputError(who + ": more than 2^32 grid columns (nx * ny)");
}

// The tree and the column crossings are independent: with threads, the crossings are one task
// and the tree's large subtrees others (the serial setup weighs most at small grids:
// docs/performance.md "The whole voxelize process"). Both are the same as built serially.
// `alongside` (e.g. sizing the output) is one more task.
void build_tree_and_sign(const TriangleMesh& mesh, const GridSpec& grid, double coordinate_scale, bool oriented_boxes,
                         int threads, std::optional<TriangleTree>& tree, std::optional<ColumnSign>& sign,
                         const std::function<void()>& alongside) {
#if defined(PPOHDEM_WITH_OPENMP)
  std::exception_ptr sign_error, tree_error, alongside_error;  // an exception may not leave a task
#pragma omp parallel num_threads(threads > 0 ? threads : omp_get_max_threads())
#pragma omp single
  {
#pragma omp task default(shared)
    try {
      sign.emplace(mesh, grid);
    } catch (...) {
      sign_error = std::current_exception();
    }
#pragma omp task default(shared)
    try {
      alongside();
    } catch (...) {
      alongside_error = std::current_exception();
    }
    try {
      tree.emplace(mesh, coordinate_scale, oriented_boxes);
    } catch (...) {
      tree_error = std::current_exception();
    }
  }
  if (tree_error) std::rethrow_exception(tree_error);
  if (sign_error) std::rethrow_exception(sign_error);
  if (alongside_error) std::rethrow_exception(alongside_error);
#else
  (void)threads;
  tree.emplace(mesh, coordinate_scale, oriented_boxes);
  sign.emplace(mesh, grid);
  alongside();
#endif
}

}  // namespace

SlabRange slab_of_rank(int nz, int rank, int ranks) {
  const auto first = [&](int r) {
    return static_cast<int>(static_cast<long long>(nz) * r / ranks);
  };
  return {first(rank), first(rank + 1)};
}

template <typename T>
void FastSdfBuilder::build_slab_impl(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                     std::span<T> out, std::vector<T>* sized, SdfReport* report) const {
  check_inputs(mesh, grid);
  if (slab.k_begin < 0 || slab.k_end > grid.nodes[2] || slab.k_begin > slab.k_end) {
    throw InputError("fast SDF builder: slab [" + std::to_string(slab.k_begin) + ", " + std::to_string(slab.k_end) +
                     ") is not within the grid's " + std::to_string(grid.nodes[2]) + " z-planes");
  }
  if (sized == nullptr && out.size() != slab.node_count(grid)) {
    throw InputError("fast SDF builder: output holds " + std::to_string(out.size()) + " values, the slab has " +
                     std::to_string(slab.node_count(grid)) + " nodes");
  }
  if (!(options_.band_cells >= 0.0) || !std::isfinite(options_.band_cells)) {
    throw InputError("fast SDF builder: band must be a finite number of cells >= 0 (0: exact everywhere), got " +
                     std::to_string(options_.band_cells));
  }
  (void)simd_level();  // a bad PPOHDEM_SIMD is reported here, not inside the parallel loops
  const double coordinate_scale =
      std::max(grid.origin.cwiseAbs().maxCoeff(), grid.upper_corner().cwiseAbs().maxCoeff());
  const bool band_mode = options_.band_cells > 0.0;
  // Oriented boxes pay off when every node makes a tree query (exact mode), not for the few
  // brick-centre queries of band mode, where fitting them costs more than they save
  // (docs/performance.md "How the fast builder works"). The field is the same either way.
  std::optional<fast::TriangleTree> tree_storage;
  std::optional<fast::ColumnSign> sign_storage;
  build_tree_and_sign(mesh, grid, coordinate_scale, /*oriented_boxes=*/!band_mode, options_.threads, tree_storage,
                      sign_storage, [&] {
                        if (sized != nullptr) sized->resize(slab.node_count(grid));
                      });
  if (sized != nullptr) out = std::span<T>(*sized);
  const fast::TriangleTree& tree = *tree_storage;
  const fast::ColumnSign& sign = *sign_storage;
  const double band = band_mode ? options_.band_cells * grid.spacing.maxCoeff() : std::numeric_limits<double>::infinity();
  const fast::BrickDistance bricks(tree, grid, band, options_.shared_candidates);

  // Bricks of kBrick^3 nodes on GLOBAL node indices (brick b covers [b kBrick, (b + 1) kBrick)),
  // so a brick, its centre and (band mode) its transferred triangles do not depend on the slab.
  constexpr int kBrick = 8;
  const int nx = grid.nodes[0], ny = grid.nodes[1], nz = grid.nodes[2];
  const int bx = (nx + kBrick - 1) / kBrick, by = (ny + kBrick - 1) / kBrick, bz = (nz + kBrick - 1) / kBrick;
  const auto brick_box = [&](int bi, int bj, int bk) {
    fast::NodeBox b;
    const int idx[3] = {bi, bj, bk};
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = idx[a] * kBrick;
      b.hi[a] = std::min((idx[a] + 1) * kBrick, grid.nodes[static_cast<std::size_t>(a)]);
    }
    return b;
  };
  std::size_t negatives = 0;
  if (slab.k_end > slab.k_begin) {
    const int bk_first = slab.k_begin / kBrick, bk_last = (slab.k_end - 1) / kBrick;
    // Brick centres' nearest triangles (band mode: also one brick layer beyond the slab, whose
    // triangles are transferred into the slab's outer bricks).
    const int ck_first = band_mode ? std::max(0, bk_first - 1) : bk_first;
    const int ck_last = band_mode ? std::min(bz - 1, bk_last + 1) : bk_last;
    const int cz = ck_last - ck_first + 1;
    std::vector<fast::TriangleTree::Nearest> centre(static_cast<std::size_t>(bx) * static_cast<std::size_t>(by) *
                                                    static_cast<std::size_t>(cz));
    const auto centre_at = [&](int bi, int bj, int bk) -> fast::TriangleTree::Nearest& {
      return centre[static_cast<std::size_t>(bi) +
                    static_cast<std::size_t>(bx) * (static_cast<std::size_t>(bj) +
                                                     static_cast<std::size_t>(by) * static_cast<std::size_t>(bk - ck_first))];
    };
    const int threads = options_.threads;
    const long long centre_rows = static_cast<long long>(by) * cz;
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads > 0 ? threads : omp_get_max_threads())
#endif
    for (long long row = 0; row < centre_rows; ++row) {
      const int bj = static_cast<int>(row % by);
      const int bk = ck_first + static_cast<int>(row / by);
      std::int64_t hint = -1;
      for (int bi = 0; bi < bx; ++bi) {
        const fast::TriangleTree::Nearest n = tree.nearest(bricks.box_centre(brick_box(bi, bj, bk)), hint);
        centre_at(bi, bj, bk) = n;
        hint = n.triangle;
      }
    }
    (void)threads;

    const fast::NodeBox slab_box{{0, 0, slab.k_begin}, {nx, ny, slab.k_end}};
    const long long brick_count = static_cast<long long>(bx) * by * (bk_last - bk_first + 1);
    const std::size_t total = static_cast<std::size_t>(brick_count);
    const std::size_t progress_step = std::max<std::size_t>(1, total / 100);
    std::atomic<std::size_t> bricks_done{0};
    const std::size_t plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp parallel num_threads(options_.threads > 0 ? options_.threads : omp_get_max_threads()) reduction(+ : negatives)
#endif
    {
      fast::BrickDistance::Workspace ws;
      std::vector<double> d2(static_cast<std::size_t>(kBrick * kBrick * kBrick));
      std::vector<char> inside(static_cast<std::size_t>(kBrick * kBrick * kBrick));
      std::vector<std::uint32_t> transfer;
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp for schedule(dynamic, 1)
#endif
      for (long long b = 0; b < brick_count; ++b) {
        const int bi = static_cast<int>(b % bx);
        const int bj = static_cast<int>((b / bx) % by);
        const int bk = bk_first + static_cast<int>(b / (static_cast<long long>(bx) * by));
        const fast::NodeBox brick = brick_box(bi, bj, bk);
        transfer.clear();
        if (band_mode) {
          // The nearest triangles of the 27 brick centres around (and including) this brick.
          for (int dk = -1; dk <= 1; ++dk) {
            for (int dj = -1; dj <= 1; ++dj) {
              for (int di = -1; di <= 1; ++di) {
                const int i = bi + di, j = bj + dj, k = bk + dk;
                if (i < 0 || j < 0 || k < 0 || i >= bx || j >= by || k >= bz) continue;
                transfer.push_back(centre_at(i, j, k).triangle);
              }
            }
          }
          std::sort(transfer.begin(), transfer.end());
          transfer.erase(std::unique(transfer.begin(), transfer.end()), transfer.end());
        }
        bricks.solve(brick, slab_box, centre_at(bi, bj, bk), transfer, ws, d2.data());
        const fast::NodeBox nodes = brick.intersect(slab_box);
        const int ex = brick.extent(0), ey = brick.extent(1);
        // Signs of the brick's nodes, one walk up each z-column (indexed as d2).
        const std::size_t layer = static_cast<std::size_t>(ex) * static_cast<std::size_t>(ey);
        for (int j = nodes.lo[1]; j < nodes.hi[1]; ++j) {
          for (int i = nodes.lo[0]; i < nodes.hi[0]; ++i) {
            const std::size_t at = static_cast<std::size_t>(((nodes.lo[2] - brick.lo[2]) * ey + (j - brick.lo[1])) * ex +
                                                            (i - brick.lo[0]));
            sign.inside_on_column(i, j, nodes.lo[2], nodes.hi[2], inside.data() + at, layer);
          }
        }
        for (int k = nodes.lo[2]; k < nodes.hi[2]; ++k) {
          for (int j = nodes.lo[1]; j < nodes.hi[1]; ++j) {
            const char* in = inside.data() + static_cast<std::size_t>(((k - brick.lo[2]) * ey + (j - brick.lo[1])) * ex);
            T* row = out.data() + static_cast<std::size_t>(k - slab.k_begin) * plane +
                     static_cast<std::size_t>(j) * static_cast<std::size_t>(nx);
            const double* src = d2.data() + static_cast<std::size_t>(((k - brick.lo[2]) * ey + (j - brick.lo[1])) * ex);
            for (int i = nodes.lo[0]; i < nodes.hi[0]; ++i) {
              const double distance = std::sqrt(src[i - brick.lo[0]]);
              const double phi = in[i - brick.lo[0]] ? -distance : distance;
              row[i] = static_cast<T>(phi);
              negatives += phi < 0.0 ? 1 : 0;
            }
          }
        }
        const std::size_t done = bricks_done.fetch_add(1, std::memory_order_relaxed) + 1;
        bool master = true;
#if defined(PPOHDEM_WITH_OPENMP)
        master = omp_get_thread_num() == 0;
#endif
        if (master && (done % progress_step == 0 || done == total)) report_progress(done, total);
      }
      if (options_.counters != nullptr) {
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp critical(ppohdem_fast_sdf_counters)
#endif
        {
          options_.counters->exact_nodes += ws.counters.exact_nodes;
          options_.counters->transferred_nodes += ws.counters.transferred_nodes;
          options_.counters->candidate_tests += ws.counters.candidate_tests;
          options_.counters->distance_evaluations += ws.counters.distance_evaluations;
        }
      }
    }
    report_progress(total, total);
  }
  // The reduction of an integer count is exact: order does not matter.
  if (report != nullptr) {
    const auto w = sign.warnings();
    report->warnings.insert(report->warnings.end(), w.begin(), w.end());
    report->inside_fraction = out.empty() ? 0.0 : static_cast<double>(negatives) / static_cast<double>(out.size());
  }
}

void FastSdfBuilder::build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                std::span<double> out, SdfReport* report) const {
  build_slab_impl<double>(mesh, grid, slab, out, nullptr, report);
}

void FastSdfBuilder::build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                std::span<float> out, SdfReport* report) const {
  build_slab_impl<float>(mesh, grid, slab, out, nullptr, report);
}

void FastSdfBuilder::build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                std::vector<double>& out, SdfReport* report) const {
  build_slab_impl<double>(mesh, grid, slab, {}, &out, report);
}

void FastSdfBuilder::build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                std::vector<float>& out, SdfReport* report) const {
  build_slab_impl<float>(mesh, grid, slab, {}, &out, report);
}

ScalarField FastSdfBuilder::build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) const {
  check_inputs(mesh, grid);
  ScalarField phi;
  phi.grid = grid;
  build_slab(mesh, grid, {0, grid.nodes[2]}, phi.values, report);
  return phi;
}

std::unique_ptr<SdfBuilder> make_fast_sdf_builder(FastSdfOptions options) {
  return std::make_unique<FastSdfBuilder>(options);
}

namespace {

template <typename T>
std::vector<T> build_distributed(const FastSdfBuilder& builder, const Comm& comm, const TriangleMesh& mesh,
                                 const GridSpec& grid, SdfReport* report) {
  check_inputs(mesh, grid);
  const SlabRange slab = slab_of_rank(grid.nodes[2], comm.rank(), comm.size());
  std::vector<T> local;
  SdfReport local_report;
  builder.build_slab(mesh, grid, slab, local, &local_report);
  const double negatives = comm.sum_over_ranks(local_report.inside_fraction * static_cast<double>(local.size()));
  if (report != nullptr && comm.rank() == 0) {
    report->warnings.insert(report->warnings.end(), local_report.warnings.begin(), local_report.warnings.end());
    report->inside_fraction = std::round(negatives) / static_cast<double>(grid.node_count());
  }
  if (comm.size() == 1) return local;  // no copy
  std::vector<T> all = comm.gather_to_root(std::span<const T>(local));
  return all;
}

}  // namespace

ScalarField build_sdf_distributed(const FastSdfBuilder& builder, const Comm& comm, const TriangleMesh& mesh,
                                  const GridSpec& grid, SdfReport* report) {
  ScalarField field;
  field.grid = grid;
  field.values = build_distributed<double>(builder, comm, mesh, grid, report);
  return field;
}

std::vector<float> build_sdf_distributed_float(const FastSdfBuilder& builder, const Comm& comm,
                                               const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) {
  return build_distributed<float>(builder, comm, mesh, grid, report);
}

}  // namespace ppohdem::sdf::fast

namespace ppohdem {

std::size_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports kibibytes
}

}  // namespace ppohdem
