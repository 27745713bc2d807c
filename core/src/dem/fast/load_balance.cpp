// Load balance: the bricks at the start (equal, or a bisection by particle count) and their
// re-cut at a list build when the ranks' particle counts drift apart (docs/dem.md "Load
// balance"). No result depends on the bricks (docs/dem.md "Domain decomposition"), only the
// time does.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::decompose_whole(const Particles& particles) {
  std::vector<Vec3> centres;
  std::vector<std::int64_t> ids;
  centres.reserve(particles.size());
  ids.reserve(particles.size());
  for (const Particle& p : particles) {
    centres.push_back(p.position);
    ids.push_back(p.id);
  }
  // The equal bricks are those of the box at construction, the scene's initial particles
  // (kept at a restore, as before there was a balance).
  if (!equal_bricks_made) equal_bricks = Decomposition(comm->size(), centres);
  equal_bricks_made = true;
  // Every rank holds the whole system here: the bisection counts without communication.
  decomposition = balance == FastOptions::Balance::kBisection
                      ? Decomposition::bisection(comm->size(), centres, ids, centres.size(), serial)
                      : equal_bricks;
  update_peers();
}

void FastEngine::Impl::decompose_owned() {
  // Equal bricks over the box of every centre (minima and maxima: the same bits as from all
  // the centres on one rank), and the bisection of the owned centres (collective, the one a
  // re-cut makes).
  if (!equal_bricks_made) {
    std::vector<double> box(6, -std::numeric_limits<double>::infinity());  // -lo, hi
    for (std::size_t k = 0; k < s.owned; ++k) {
      for (int a = 0; a < 3; ++a) {
        box[static_cast<std::size_t>(a)] = std::max(box[static_cast<std::size_t>(a)], -s.x[k][a]);
        box[static_cast<std::size_t>(3 + a)] = std::max(box[static_cast<std::size_t>(3 + a)], s.x[k][a]);
      }
    }
    box = comm->max_each_over_ranks(std::move(box));
    if (total == 0) box.assign(6, 0.0);  // as Decomposition's empty box
    equal_bricks = Decomposition(comm->size(), Vec3(-box[0], -box[1], -box[2]), Vec3(box[3], box[4], box[5]));
    equal_bricks_made = true;
  }
  decomposition = balance == FastOptions::Balance::kBisection
                      ? Decomposition::bisection(comm->size(), s.x, s.id, s.owned, *comm)
                      : equal_bricks;
  update_peers();
}

void FastEngine::Impl::rebalance(History& h) {
  if (balance != FastOptions::Balance::kBisection || !distributed()) return;
  // The load is the particle count: the force pass costs about the same per particle in the
  // dense phases that dominate a run, and a count is the same on every run, so the bricks
  // are reproducible (a measured time is not).
  const double most = comm->max_over_ranks(static_cast<double>(s.owned));
  const double mean = comm->sum_over_ranks(static_cast<double>(s.owned)) / comm->size();
  if (!(most > balance_threshold * mean)) return;
  decomposition = Decomposition::bisection(comm->size(), s.x, s.id, s.owned, *comm);
  ++recuts;
  migrate(h, /*global=*/true);  // the new bricks may lie anywhere
  update_peers();
}

LoadReport FastEngine::Impl::load_report() const {
  LoadReport r;
  r.recuts = recuts;
  r.global_exchanges = global_exchanges;
  r.peers = peers.size();
  r.exchanges = exchanges;
  r.overlapped_refreshes = overlapped_refreshes;
  if (!distributed()) return r;
  const int ranks = comm->size();
  // The counts of the last build's positions (x_build: the owners were decided there) in the
  // current bricks and in the equal ones.
  std::vector<double> counts(2 * static_cast<std::size_t>(ranks), 0.0);
  counts[static_cast<std::size_t>(comm->rank())] = static_cast<double>(s.owned);
  for (std::size_t k = 0; k < s.owned; ++k) {
    counts[static_cast<std::size_t>(ranks + equal_bricks.owner(s.x_build[k], s.id[k]))] += 1.0;
  }
  counts = comm->sum_each_over_ranks(std::move(counts));
  auto max_over_mean = [&](std::size_t first) {
    double most = 0.0, sum = 0.0;
    for (int q = 0; q < ranks; ++q) {
      most = std::max(most, counts[first + static_cast<std::size_t>(q)]);
      sum += counts[first + static_cast<std::size_t>(q)];
    }
    return sum > 0.0 ? most / (sum / ranks) : 1.0;
  };
  const auto ghosts = static_cast<double>(s.size() - s.owned);  // made at the last list build
  r.ghosts_mean = comm->sum_over_ranks(ghosts) / ranks;
  r.ghosts_max = comm->max_over_ranks(ghosts);
  const auto interior = static_cast<double>(s.n_interior);
  r.interior_mean = comm->sum_over_ranks(interior) / ranks;
  r.interior_min = -comm->max_over_ranks(-interior);
  r.max_over_mean = max_over_mean(0);
  r.equal_bricks_max_over_mean = max_over_mean(static_cast<std::size_t>(ranks));
  return r;
}

}  // namespace ppohdem::dem::fast
