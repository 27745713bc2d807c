// One time step of the fast engine: velocity Verlet (reference_engine.cpp has the formulas),
// list builds when a particle has moved half the skin, the force evaluation.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::update_reach(double time) {
  s.reach.assign(s.boundaries.size(), ReachBox{});
  if (!skip_far_objects) return;
  for (std::size_t b = 0; b < s.boundaries.size(); ++b) {
    if (!s.is_wall[b]) s.reach[b] = s.boundaries[b]->reach(time, r_max);
  }
}

void FastEngine::Impl::evaluate_forces(double history_dt, bool closing_kick) {
  s.closing_kick = closing_kick;
  s.kick_closed = false;
  const double time = static_cast<double>(steps) * s.dt;
  update_reach(time);
  kernel->evaluate(s, time, history_dt);
  energies_cache.reset();
  restored_elastic.reset();
  if (closing_kick) close_step();
  // The energies of the state, boundary_loads() and (one rank) escaped_count() sum when
  // asked; the energies' rates every evaluation.
  if (energy_balance) add_step_sums(history_dt);
  loads_stale = true;
  out_valid = false;
  if (lazy_sums()) return;
  // What the run needs from every rank, in ONE allgather of a few bytes per rank: the counts,
  // the deepest contact and the screen of the motion. The energies and the loads are exact
  // sums merged by one allreduce of fixed size when asked (sum_energies, sum_loads), O(1) per
  // rank whatever N.
  {
    Bytes mine;
    Packer pk(mine);
    pk.put(static_cast<std::uint64_t>(s.pair_contacts));
    pk.put(static_cast<std::uint64_t>(s.boundary_contacts));
    pk.put(static_cast<std::uint64_t>(count_escaped()));
    pk.put(static_cast<std::uint8_t>(std::isfinite(s.screen) ? 1 : 0));
    pk.put(static_cast<std::uint8_t>(s.deepest ? 1 : 0));
    if (s.deepest) {
      pk.put(s.deepest->ratio);
      pk.put(s.deepest->overlap);
      pk.put(s.deepest->id_a);
      pk.put(s.deepest->id_b);
      pk.put(s.deepest->boundary);
    }
    s.pair_contacts = 0;
    s.boundary_contacts = 0;
    escaped = 0;
    screens_finite = true;
    s.deepest.reset();
    for (const Bytes& block : comm->allgather(mine)) {
      Unpacker u(block);
      s.pair_contacts += u.get<std::uint64_t>();
      s.boundary_contacts += u.get<std::uint64_t>();
      escaped += u.get<std::uint64_t>();
      const bool screen_finite_there = u.get<std::uint8_t>() != 0;  // read whatever the flags so far
      screens_finite = screens_finite && screen_finite_there;
      if (u.get<std::uint8_t>() != 0) {
        // keep_deeper is a total order, so the rank order does not matter.
        LargestOverlap c;
        u.get(c.ratio);
        u.get(c.overlap);
        u.get(c.id_a);
        u.get(c.id_b);
        u.get(c.boundary);
        keep_deeper(s.deepest, c);
      }
    }
  }
}

/// Particles per close_kicks call of close_step (any piece gives the same bits).
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
  }
  kick_cached = true;
}

void FastEngine::Impl::step() {
  const double dt = s.dt;
  const double half = 0.5 * dt;
  const Vec3 g = s.gravity;
  const std::size_t n = s.owned;
  double largest = 0.0;  // max |x - x_build|^2 [m^2]
  // Half kick and drift (the reference's expressions, so the same bits). The kick of
  // f(n) / m is the one the closing kick of the previous step computed from the same f(n):
  // that step left it in pv, pw (free between steps), which saves 6 of the 12 divisions of
  // a particle-step; after a (re)start the kick is computed afresh.
  const bool cached = kick_cached;
  PPOHDEM_OMP(omp parallel for schedule(static) reduction(max : largest) if (n >= kParallelMin))
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 kick = cached ? s.pv[i] : Vec3(half * (s.f[i] / s.mass[i] + g));
    const Vec3 spin_kick = cached ? s.pw[i] : Vec3(half * s.t[i] / s.inertia[i]);
    s.v[i] += kick;
    s.w[i] += spin_kick;
    s.x[i] += dt * s.v[i];
    s.pv[i] = s.v[i] + kick;
    s.pw[i] = s.w[i] + spin_kick;
    largest = std::max(largest, (s.x[i] - s.x_build[i]).squaredNorm());
  }
  ++steps;
  if (distributed()) largest = comm->max_over_ranks(largest);  // the same decision on every rank
  if (largest > 0.25 * skin * skin) {  // largest displacement > skin / 2
    build_lists();
  } else {
    refresh_ghosts();
  }
  evaluate_forces(dt, /*closing_kick=*/true);
  out_valid = false;
}

}  // namespace ppohdem::dem::fast
