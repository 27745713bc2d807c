// Sums over particles, exact until one rounding (ppohdem/dem/exact_sum.hpp): the same bits for
// any thread count, rank count and storage order, without gathering any particle's terms
// (docs/dem.md "Sums over particles"): contact energies, boundary loads, escaped counts.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

EvaluationSums FastEngine::Impl::sum_owned(bool contact, bool motion, bool with_loads) const {
  const std::size_t nb = s.boundaries.size();
  const std::size_t n = s.owned;
  const auto threads = static_cast<std::size_t>(n >= kParallelMin ? max_threads() : 1);
  if (thread_sums.size() < threads || thread_sums.front().sums.size() != EvaluationSums::kEnergies + 6 * nb) {
    thread_sums.assign(threads, EvaluationSums(nb));
  }
  PPOHDEM_OMP(omp parallel num_threads(static_cast<int>(threads)) if (threads > 1))
  {
    EvaluationSums& mine = thread_sums[static_cast<std::size_t>(thread_id())];  // merged in any order below
    mine.reset();
    ExactSum* const e = mine.energy();
    PPOHDEM_OMP(omp for schedule(static))
    for (std::size_t k = 0; k < n; ++k) {
      const FastState::ParticleTerms& c = s.terms[k];
      if (contact) {
        e[0].add(c.elastic);
        e[1].add(c.dissipated);
        e[2].add(c.work);
        e[3].add(c.power);
      }
      if (motion) {
        e[4].add(c.kinetic);
        e[5].add(c.rotational);
        e[6].add(c.gravitational);
      }
      if (with_loads) add_records(mine, k);
    }
  }
  EvaluationSums all = thread_sums[0];
  for (std::size_t t = 1; t < threads; ++t) all.merge(thread_sums[t]);
  return all;
}

std::array<double, 3> FastEngine::Impl::motion_energies() const {
  const std::size_t n = s.owned;
  ExactSums<3> all;
  PPOHDEM_OMP(omp parallel if (n >= kParallelMin))
  {
    ExactSums<3> mine;
    PPOHDEM_OMP(omp for schedule(static) nowait)
    for (std::size_t k = 0; k < n; ++k) mine.add(motion_terms(s, k));
    PPOHDEM_OMP(omp critical(ppohdem_fast_sums))
    all.merge(mine);
  }
  if (distributed()) {
    EvaluationSums three(0);  // its first three energy sums carry the motion terms
    for (std::size_t c = 0; c < 3; ++c) three.energy()[c] = all.sum[c];
    three.merge_over_ranks(*comm);
    for (std::size_t c = 0; c < 3; ++c) all.sum[c] = three.energy()[c];
  }
  return all.values();
}

std::size_t FastEngine::Impl::count_escaped() const {
  return static_cast<std::size_t>(std::count_if(s.escaped_via.begin(), s.escaped_via.begin() + static_cast<std::ptrdiff_t>(s.owned),
                                                [](std::int32_t via) { return via != 0; }));
}

void FastEngine::Impl::sum_loads() const {
  EvaluationSums sums = sum_owned(false, false, true);
  if (distributed()) sums.merge_over_ranks(*comm);  // collective: every rank asks (run.cpp)
  loads = sums.loads(s.boundaries.size());
  loads_stale = false;
}

void FastEngine::Impl::add_contact_sums(const std::array<double, 4>& sums, double history_dt) {
  if (!energy_balance) return;  // not tracked: the accumulators stay zero
  const auto [e, d, w, p] = sums;
  elastic = e;
  dissipated += d;
  boundary_work += w;
  // W = (P(n) + P(n+1)) dt / 2 (contact_force.hpp "Moving boundaries"); the start-up
  // evaluation (dt = 0) records P(0).
  boundary_work += 0.5 * (power + p) * history_dt;
  power = p;
}

void FastEngine::Impl::add_evaluation_sums(double history_dt, bool motion) {
  EvaluationSums sums = sum_owned(true, motion, true);
  if (distributed()) sums.merge_over_ranks(*comm);
  std::array<double, 7> e{};
  for (std::size_t c = 0; c < 7; ++c) e[c] = sums.energy()[c].value();
  add_contact_sums({e[0], e[1], e[2], e[3]}, history_dt);
  if (motion) {
    motion_sums = {e[4], e[5], e[6]};
    motion_valid = true;
  }
  loads = sums.loads(s.boundaries.size());
  loads_stale = false;
  out_valid = false;
}

}  // namespace ppohdem::dem::fast
