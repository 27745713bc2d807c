/// \file fast_sdf_builder.cpp
/// The "fast" builder: BVH nearest queries warm-started along x-lines, column signs, OpenMP over
/// lines, MPI over z-slabs. See fast_sdf_builder.hpp.
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"

#include <sys/resource.h>

#include <atomic>
#include <cmath>
#include <cstdint>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/fast/column_sign.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"

#if defined(PPOHDEM_WITH_OPENMP)
#include <omp.h>
#endif

namespace ppohdem {

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

}  // namespace

SlabRange slab_of_rank(int nz, int rank, int ranks) {
  const auto first = [&](int r) {
    return static_cast<int>(static_cast<long long>(nz) * r / ranks);
  };
  return {first(rank), first(rank + 1)};
}

template <typename T>
void FastSdfBuilder::build_slab_impl(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                     std::span<T> out, SdfReport* report) const {
  check_inputs(mesh, grid);
  if (slab.k_begin < 0 || slab.k_end > grid.nodes[2] || slab.k_begin > slab.k_end) {
    throw InputError("fast SDF builder: slab [" + std::to_string(slab.k_begin) + ", " + std::to_string(slab.k_end) +
                     ") is not within the grid's " + std::to_string(grid.nodes[2]) + " z-planes");
  }
  if (out.size() != slab.node_count(grid)) {
    throw InputError("fast SDF builder: output holds " + std::to_string(out.size()) + " values, the slab has " +
                     std::to_string(slab.node_count(grid)) + " nodes");
  }
  const fast::TriangleTree tree(mesh);
  const fast::ColumnSign sign(mesh, grid);

  const int nx = grid.nodes[0];
  const int ny = grid.nodes[1];
  const long long lines = static_cast<long long>(ny) * (slab.k_end - slab.k_begin);
  const std::size_t total_lines = static_cast<std::size_t>(lines);
  std::atomic<std::size_t> lines_done{0};
  std::size_t negatives = 0;
  const std::size_t progress_step = std::max<std::size_t>(1, total_lines / 100);

#if defined(PPOHDEM_WITH_OPENMP)
  const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
#pragma omp parallel num_threads(threads) reduction(+ : negatives)
#endif
  {
    std::vector<char> inside;
    std::int64_t line_start_hint = -1;
#if defined(PPOHDEM_WITH_OPENMP)
#pragma omp for schedule(dynamic, 4)
#endif
    for (long long line = 0; line < lines; ++line) {
      const int j = static_cast<int>(line % ny);
      const int k = slab.k_begin + static_cast<int>(line / ny);
      sign.inside_on_line(j, k, inside);
      T* row = out.data() + static_cast<std::size_t>(line) * static_cast<std::size_t>(nx);
      std::int64_t hint = line_start_hint;
      for (int i = 0; i < nx; ++i) {
        const fast::TriangleTree::Nearest nearest = tree.nearest(grid.position(i, j, k), hint);
        hint = nearest.triangle;
        if (i == 0) line_start_hint = hint;
        const double distance = std::sqrt(nearest.squared_distance);
        const double phi = inside[static_cast<std::size_t>(i)] ? -distance : distance;
        row[i] = static_cast<T>(phi);
        negatives += phi < 0.0 ? 1 : 0;
      }
      const std::size_t done = lines_done.fetch_add(1, std::memory_order_relaxed) + 1;
      bool master = true;
#if defined(PPOHDEM_WITH_OPENMP)
      master = omp_get_thread_num() == 0;
#endif
      if (master && (done % progress_step == 0 || done == total_lines)) report_progress(done, total_lines);
    }
  }
  report_progress(total_lines, total_lines);
  // The reduction of an integer count is exact: order does not matter.
  if (report != nullptr) {
    const auto w = sign.warnings();
    report->warnings.insert(report->warnings.end(), w.begin(), w.end());
    report->inside_fraction = out.empty() ? 0.0 : static_cast<double>(negatives) / static_cast<double>(out.size());
  }
}

void FastSdfBuilder::build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                std::span<double> out, SdfReport* report) const {
  build_slab_impl(mesh, grid, slab, out, report);
}

void FastSdfBuilder::build_slab(const TriangleMesh& mesh, const GridSpec& grid, SlabRange slab,
                                std::span<float> out, SdfReport* report) const {
  build_slab_impl(mesh, grid, slab, out, report);
}

ScalarField FastSdfBuilder::build(const TriangleMesh& mesh, const GridSpec& grid, SdfReport* report) const {
  check_inputs(mesh, grid);
  ScalarField phi(grid);
  build_slab(mesh, grid, {0, grid.nodes[2]}, std::span<double>(phi.values), report);
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
  std::vector<T> local(slab.node_count(grid));
  SdfReport local_report;
  builder.build_slab(mesh, grid, slab, std::span<T>(local), &local_report);
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

std::size_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports kibibytes
}

}  // namespace ppohdem
