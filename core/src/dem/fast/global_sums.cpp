// Sums over particles, exact until one rounding (ppohdem/dem/exact_sum.hpp): the same bits for
// any thread count, rank count and storage order, without gathering any particle's terms
// (docs/dem.md "Sums over particles"): contact energies, boundary loads, escaped counts.
#include <algorithm>
#include <array>
#include <span>

#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

EvaluationSums FastEngine::Impl::sum_owned(bool state, bool with_loads) const {
  const std::size_t nb = s.boundaries.size();
  const std::size_t n = s.owned;
  const auto threads = static_cast<std::size_t>(n >= kParallelMin ? max_threads() : 1);
  if (thread_sums.size() < threads || thread_sums.front().sums.size() != EvaluationSums::kEnergies + 6 * nb) {
    thread_sums.assign(threads, EvaluationSums(nb));
  }
  const bool elastic = state && energy_balance;
  PPOHDEM_OMP(omp parallel num_threads(static_cast<int>(threads)) if (threads > 1))
  {
    EvaluationSums& mine = thread_sums[static_cast<std::size_t>(thread_id())];  // merged in any order below
    mine.reset();
    if (with_loads) {
      PPOHDEM_OMP(omp for schedule(static))
      for (std::size_t k = 0; k < n; ++k) add_records(mine, k);
    }
    if (state) {
      // The state's energies a block at a time, each column added in lanes (add_terms: the
      // same bits as one exact add a term), in place: the columns are scratch.
      ExactSum* const e = mine.energy();
      constexpr std::size_t kBlock = 1024;
      std::array<std::array<double, kBlock>, 4> terms;  // elastic, kinetic, rotational, gravitational
      const std::size_t blocks = (n + kBlock - 1) / kBlock;
      PPOHDEM_OMP(omp for schedule(static))
      for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t begin = b * kBlock, count = std::min(kBlock, n - begin);
        for (std::size_t j = 0; j < count; ++j) {
          const std::array<double, 3> m = motion_terms(s, begin + j);
          terms[1][j] = m[0];
          terms[2][j] = m[1];
          terms[3][j] = m[2];
        }
        if (elastic) {
          for (std::size_t j = 0; j < count; ++j) terms[0][j] = s.terms[begin + j].elastic;
          add_terms_overwriting(e[0], std::span<double>(terms[0].data(), count));
        }
        for (std::size_t c = 1; c < 4; ++c) add_terms_overwriting(e[3 + c], std::span<double>(terms[c].data(), count));
      }
    }
  }
  EvaluationSums all = thread_sums[0];
  for (std::size_t t = 1; t < threads; ++t) all.merge(thread_sums[t]);
  return all;
}

std::size_t FastEngine::Impl::count_escaped() const {
  return static_cast<std::size_t>(std::count_if(s.escaped_via.begin(), s.escaped_via.begin() + static_cast<std::ptrdiff_t>(s.owned),
                                                [](std::int32_t via) { return via != 0; }));
}

void FastEngine::Impl::sum_loads() const {
  EvaluationSums sums = sum_owned(false, true);
  if (distributed()) sums.merge_over_ranks(*comm);  // collective: every rank asks (run.cpp)
  loads = sums.loads(s.boundaries.size());
  loads_stale = false;
}

Energies FastEngine::Impl::sum_energies() const {
  if (energies_cache) return *energies_cache;
  EvaluationSums sums = sum_owned(true, false);
  if (distributed()) sums.merge_over_ranks(*comm);
  ExactSum* const e = sums.energy();
  Energies totals;
  totals.kinetic = e[4].value();
  totals.rotational = e[5].value();
  totals.gravitational = e[6].value();
  if (energy_balance) {
    totals.elastic = restored_elastic ? *restored_elastic : e[0].value();
    totals.dissipated = dissipated;
    totals.boundary_work = boundary_work;
  } else {
    totals.elastic = totals.dissipated = totals.boundary_work = std::numeric_limits<double>::quiet_NaN();
  }
  energies_cache = totals;
  return totals;
}

void FastEngine::Impl::add_rates(const ExactSum* rates, double history_dt) {
  dissipated += rates[0].value();
  boundary_work += rates[1].value();
  // W = (P(n) + P(n+1)) dt / 2 (contact_force.hpp "Moving boundaries"); the start-up
  // evaluation (dt = 0) records P(0).
  const double p = rates[2].value();
  boundary_work += 0.5 * (power + p) * history_dt;
  power = p;
}

}  // namespace ppohdem::dem::fast
