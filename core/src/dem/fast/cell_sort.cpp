// The owned particles sorted by cell (stable counting sort), so neighbours sit close in memory.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

FastEngine::Impl::CellOrder FastEngine::Impl::sort_owned_by_cell() {
  const std::size_t n = s.owned;
  s.where.assign(total, kNotHere);
  if (n == 0) return {};
  const Grid grid = grid_for(s.x, 2.0 * r_max + skin);
  // Counting sort by cell (stable): order[new] = old.
  std::vector<std::uint32_t> cell(n);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) cell[i] = static_cast<std::uint32_t>(grid.linear(grid.index(s.x[i])));
  std::vector<std::uint32_t> start(grid.size() + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++start[cell[i] + 1];
  for (std::size_t c = 0; c < grid.size(); ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> order(n);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[fill[cell[i]]++] = static_cast<std::uint32_t>(i);
  }
  s.n_interior = n;
  if (distributed()) put_halo_layer_last(order);  // (the search then makes its own cells)
  // Every array follows its particle except two that the sort need not carry: x_build is
  // set from x below, and the energy terms are the last evaluation's outputs, which this
  // step's evaluation (after the build) writes afresh for every owned particle before any
  // sum reads them (force_sums.hpp, close_kick). They are zeroed (what untracked terms
  // hold) rather than moved: moving them through a new vector zero-filled on one thread is a
  // serial pass (docs/performance.md "The cell sort carries less").
  for_each_particle_array(s, [&](auto& a) {
    using Array = std::decay_t<decltype(a)>;
    if constexpr (std::is_same_v<Array, std::vector<FastState::ParticleTerms>>) {
      PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
      for (std::size_t k = 0; k < n; ++k) a[k] = FastState::ParticleTerms{};
    } else if constexpr (std::is_same_v<Array, std::vector<Vec3>>) {
      if (&a != &s.x_build) permute(a, order);
    } else {
      permute(a, order);
    }
  });
  s.x_build.resize(s.x.size());  // (= n: the ghosts are dropped before the sort)
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t k = 0; k < s.x.size(); ++k) {
    s.x_build[k] = s.x[k];
    if (k < n) s.where[s.original[k]] = static_cast<std::uint32_t>(k);  // `original` holds distinct indices: one writer per entry
  }
  return {grid, std::move(start), std::move(order)};
}

}  // namespace ppohdem::dem::fast
