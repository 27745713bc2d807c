// One time step of the fast engine: velocity Verlet (reference_engine.cpp has the formulas),
// list builds when a particle has moved half the skin, the force evaluation and its sums.
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
  s.motion_terms = !lazy_sums();
  const double time = static_cast<double>(steps) * s.dt;
  update_reach(time);
  kernel->evaluate(s, time, history_dt);
  motion_valid = false;
  if (closing_kick) close_step();
  if (lazy_sums()) {  // energies(), boundary_loads() and escaped_count() sum when asked
    loads_stale = true;
    out_valid = false;
    return;
  }
  if (!distributed()) {
    reduce_one_rank(history_dt, closing_kick);
    return;
  }
  // What the sums need from every rank, in ONE allgather per evaluation (with several
  // ranks): counts, the deepest contact and, with the energies tracked, the per-particle
  // energy terms (after a step's closing kick with the motion terms, so energies() needs no
  // gather of its own) and the boundary records, the tables as rows of bytes. Sums in
  // construction order: independent of the cell sort (so of restarts), of the decomposition
  // and of the thread count. Untracked, the energies and the loads are gathered and summed
  // when asked (the same rows in the same order, so the same bits): gathering every
  // particle's 64-byte row at every step is O(N) per rank (docs/performance.md "Ranks gather
  // only what is asked, untracked").
  struct TermRow {  // 64 bytes: construction index and the 7 terms
    std::uint32_t original, unused;
    double values[7];  // elastic, dissipated, work, power, kinetic, rotational, gravitational
  };
  const bool gather_sums = energy_balance;
  std::vector<Load> all_records;
  std::vector<TermRow> term_rows;
  const std::size_t owned = s.owned;
  const std::size_t escaped_here = count_escaped();
  std::array<double, 7> sums{};  // (elastic, dissipated, work, power [J, J, J, W]; motion terms [J])
  {
    if (gather_sums) {
      term_rows.resize(owned);
      for (std::size_t k = 0; k < owned; ++k) {
        const FastState::ParticleTerms& c = s.terms[k];
        term_rows[k] = {s.original[k], 0, {c.elastic, c.dissipated, c.work, c.power, c.kinetic, c.rotational, c.gravitational}};
      }
    }
    const std::vector<Load> my_records = gather_sums ? own_loads() : std::vector<Load>{};
    Bytes mine;
    Packer pk(mine);
    pk.put(static_cast<std::uint64_t>(s.pair_contacts));
    pk.put(static_cast<std::uint64_t>(s.boundary_contacts));
    pk.put(static_cast<std::uint64_t>(escaped_here));
    pk.put(static_cast<std::uint8_t>(std::isfinite(s.screen) ? 1 : 0));
    pk.put(static_cast<std::uint8_t>(s.deepest ? 1 : 0));
    if (s.deepest) {
      pk.put(s.deepest->ratio);
      pk.put(s.deepest->overlap);
      pk.put(s.deepest->id_a);
      pk.put(s.deepest->id_b);
      pk.put(s.deepest->boundary);
    }
    pk.put(static_cast<std::uint64_t>(term_rows.size()));
    pk.put_rows(term_rows.data(), term_rows.size());
    pk.put(static_cast<std::uint64_t>(my_records.size()));
    pk.put_rows(my_records.data(), my_records.size());
    s.pair_contacts = 0;
    s.boundary_contacts = 0;
    escaped = 0;
    screens_finite = true;
    s.deepest.reset();
    if (gather_sums) all_terms.resize(total);  // every construction index is owned by one rank: all written
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
      term_rows.clear();
      u.get_rows(term_rows, u.get<std::uint64_t>());
      for (const TermRow& row : term_rows) std::copy(row.values, row.values + 7, all_terms[row.original].begin());
      u.get_rows(all_records, u.get<std::uint64_t>());
    }
  }
  out_valid = false;
  if (!gather_sums) {  // energies() and boundary_loads() gather and sum when asked
    loads_stale = true;
    return;
  }
  sums = parallel_ordered_sum<7>(total, [&](std::size_t o) { return all_terms[o]; });
  if (closing_kick) {
    motion_sums = {sums[4], sums[5], sums[6]};
    motion_valid = true;
  }
  add_contact_sums({sums[0], sums[1], sums[2], sums[3]}, history_dt);
  add_gathered_loads(all_records);
}

void FastEngine::Impl::close_step() {
  if (!s.kick_closed) {  // else the kernel's sum pass applied it (fast_state.hpp)
    const std::size_t owned = s.owned;  // changed if the build migrated particles
    double screen = 0.0;
    PPOHDEM_OMP(omp parallel for schedule(static) reduction(+ : screen) if (owned >= kParallelMin))
    for (std::size_t i = 0; i < owned; ++i) screen += close_kick(s, i);
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
