// The initial-overlap check of a setup shared over ranks (SimulationSetup::share): no rank
// holds every particle, so the pairs are found among each rank's owned particles and their
// ghosts once the first list build has placed them (docs/dem.md "Reading on every rank").
#include <cstring>

#include "../checks_over_ranks.hpp"
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::check_initial_overlaps(const std::string& source) const {
  // Owned and ghosts as particles: a pair that touches lies within 2 R_max of the brick of
  // each of its particles, so each rank sees both of them (the halo reach is 2 R_max + skin).
  Particles near(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) {
    near[k].id = s.id[k];
    near[k].position = s.x[k];
    near[k].radius = s.radius[k];
  }
  // Each pair counted once: on the rank owning its particle of the smaller id.
  std::size_t count = 0;
  std::optional<std::pair<std::size_t, std::size_t>> example;  // (smaller id's, other), the smallest ids
  auto ids = [&](const std::pair<std::size_t, std::size_t>& q) { return std::pair(near[q.first].id, near[q.second].id); };
  for (auto [i, j] : overlapping_pairs(near, 0.01)) {
    if (near[j].id < near[i].id) std::swap(i, j);
    if (i >= s.owned) continue;
    ++count;
    if (!example || ids({i, j}) < ids(*example)) example = std::pair(i, j);
  }
  const double pairs = comm->sum_over_ranks(static_cast<double>(count));  // exact below 2^53
  if (pairs == 0.0) return;
  // The pair with the smallest ids over the ranks, named by the rank that has it.
  Bytes mine;
  if (example) {
    const auto [a, b] = ids(*example);
    mine.resize(2 * sizeof(std::int64_t));
    std::memcpy(mine.data(), &a, sizeof a);
    std::memcpy(mine.data() + sizeof a, &b, sizeof b);
  }
  std::optional<std::pair<std::int64_t, std::int64_t>> smallest;
  for (const Bytes& block : comm->allgather(mine)) {
    if (block.empty()) continue;
    std::pair<std::int64_t, std::int64_t> q;
    std::memcpy(&q.first, block.data(), sizeof q.first);
    std::memcpy(&q.second, block.data() + sizeof q.first, sizeof q.second);
    if (!smallest || q < *smallest) smallest = q;
  }
  std::optional<PlacedError> error;
  if (example && ids(*example) == *smallest) {
    error = PlacedError{0, overlap_error(source, static_cast<std::size_t>(pairs), near[example->first], near[example->second])};
  }
  throw_earliest_error(*comm, error);
}

}  // namespace ppohdem::dem::fast
