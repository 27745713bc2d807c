// One time step of the fast engine: velocity Verlet (reference_engine.cpp has the formulas),
// list builds when a particle has moved half the skin, the force evaluation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine_impl.hpp"
#include "step_record.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::update_reach(double time) {
  s.reach.assign(s.boundaries.size(), ReachBox{});
  if (!skip_far_objects) return;
  for (std::size_t b = 0; b < s.boundaries.size(); ++b) {
    if (!s.is_wall[b]) s.reach[b] = s.boundaries[b]->reach(time, r_max);
  }
}

void FastEngine::Impl::evaluate_forces(double history_dt, bool closing_kick, HaloInFlight* halo) {
  s.closing_kick = closing_kick;
  s.kick_closed = false;
  s.predict_drift = closing_kick && distributed();
  const double time = static_cast<double>(steps) * s.dt;
  update_reach(time);
  kernel->evaluate(s, time, history_dt, halo);
  s.screen_skip_bound = std::numeric_limits<double>::infinity();  // set by step() for its evaluation only
  if (halo != nullptr) halo->complete();  // done by the kernel (a no-op then)
  energies_cache.reset();
  restored_elastic.reset();
  if (closing_kick) close_step();
  loads_stale = true;
  out_valid = false;
  // The energies of the state, boundary_loads() and (one rank) escaped_count() sum when
  // asked; the energies' rates every evaluation (the kernel's s.rates).
  if (lazy_sums()) {
    if (energy_balance) add_rates(s.rates.data(), history_dt);
    return;
  }
  // What the run needs from every rank, in ONE allreduce of a fixed-size record (StepRecord):
  // the counts, the screen, the rates, the deepest contact, and the next drift's largest
  // displacement, so that the next step needs no collective before its list-build decision.
  // O(1) per rank whatever N and P (docs/dem.md "One collective a step").
  StepRecord record(energy_balance);
  record.set_counts(s.pair_contacts, s.boundary_contacts, count_escaped(), std::isfinite(s.screen));
  if (energy_balance) record.set_rates(s.rates.data());
  record.set_drift(s.predict_drift ? s.next_drift : 0.0);
  record.set_deepest(s.deepest);
  comm->combine_over_ranks(record.words(), &StepRecord::combine);
  s.pair_contacts = record.pair_contacts();
  s.boundary_contacts = record.boundary_contacts();
  escaped = record.escaped();
  screens_finite = record.screens_finite();
  s.deepest = record.deepest();
  if (energy_balance) {
    const ExactSum rates[StepRecord::kRates] = {record.rate(0), record.rate(1), record.rate(2)};
    add_rates(rates, history_dt);
  }
  drift_over_ranks = s.predict_drift ? std::optional<double>(record.drift()) : std::nullopt;
}

/// Particles per close_kicks and kicks_and_drifts call (any piece gives the same bits).
constexpr std::size_t kKickPiece = 64;

void FastEngine::Impl::close_step() {
  if (!s.kick_closed) {  // else the kernel's sum pass applied it (fast_state.hpp)
    const std::size_t owned = s.owned;  // changed if the build migrated particles
    double screen = 0.0;
    PPOHDEM_OMP(omp parallel for schedule(static) reduction(+ : screen) if (owned >= kParallelMin))
    for (std::size_t piece = 0; piece < owned; piece += kKickPiece) {
      screen += close_kicks(s, piece, std::min(piece + kKickPiece, owned));
    }
    s.screen = screen;
    if (s.predict_drift) {
      double drift = 0.0;
      PPOHDEM_OMP(omp parallel for schedule(static) reduction(max : drift) if (owned >= kParallelMin))
      for (std::size_t i = 0; i < owned; ++i) drift = std::max(drift, next_drift(s, i));
      s.next_drift = drift;
    }
  }
  kick_cached = true;
}

void FastEngine::Impl::step() {
  const std::size_t n = s.owned;
  double largest = 0.0;  // max |x - x_build|^2 [m^2]
  // Half kick and drift (the reference's expressions, so the same bits). The kick of
  // f(n) / m is the one the closing kick of the previous step computed from the same f(n):
  // that step left it in pv, pw (free between steps), which saves 6 of the 12 divisions of
  // a particle-step; after a (re)start the kick is computed afresh.
  const bool cached = kick_cached;
  const double limit = 0.25 * skin * skin;  // largest displacement > skin / 2
  // Several ranks: when the last closing kick predicted this drift (drift_over_ranks) and
  // no build follows, the halo refresh is posted now and travels during the drift and the
  // interior particles' pairs (docs/dem.md "Domain decomposition (MPI)").
  std::unique_ptr<HaloInFlight> in_flight;
  if (distributed()) {
    pack_ghost_kicks(cached);  // before the drift, which overwrites pv, pw
    if (cached && drift_over_ranks && !(*drift_over_ranks > limit)) in_flight = post_ghost_kicks(cached);
  }
  PPOHDEM_OMP(omp parallel for schedule(static) reduction(max : largest) if (n >= kParallelMin))
  for (std::size_t piece = 0; piece < n; piece += kKickPiece) {
    largest = std::max(largest, kicks_and_drifts(s, piece, std::min(piece + kKickPiece, n), cached));
  }
  ++steps;
  // The same decision on every rank: the maximum over ranks, known since the last closing
  // kick's allreduce when that kick is the one just applied (evaluate_forces), else asked now.
  bool build = largest > limit;
  if (distributed()) {
    if (cached && drift_over_ranks) {
      build = *drift_over_ranks > limit;
      // next_drift repeats this drift's expressions: a rank that now finds a larger one has a
      // bug that would miss contacts, so it stops the program rather than run on.
      if (largest > limit && !build) {
        std::fprintf(stderr, "fast engine: internal error: the drift's largest displacement %.17g exceeds its prediction %.17g\n",
                     largest, *drift_over_ranks);
        comm->abort(3);
      }
    } else {
      build = comm->max_over_ranks(largest) > limit;
    }
  }
  drift_over_ranks.reset();
  if (build) {
    build_lists();  // (drift_since_build back to 0)
  } else {
    drift_since_build = std::max(drift_since_build, largest);
    if (!in_flight) refresh_ghosts(cached);
  }
  // Particles whose slots cannot touch skip their screening (mark_screen_gaps, one rank).
  if (!s.screen_gap.empty()) s.screen_skip_bound = 2.0 * std::sqrt(drift_since_build) + 1e-9 * (2.0 * r_max + skin);
  evaluate_forces(s.dt, /*closing_kick=*/true, in_flight.get());
  out_valid = false;
}

}  // namespace ppohdem::dem::fast
