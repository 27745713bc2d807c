// Sums over particles in construction order, the same bits for any thread and rank count
// (ordered_sum.hpp): contact energies, escaped counts and boundary loads.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

std::vector<FastEngine::Impl::Load> FastEngine::Impl::own_loads() const {
  std::vector<Load> mine(s.records.size());
  for (std::size_t r = 0; r < s.records.size(); ++r) {
    const BoundaryRecord& record = s.records[r];
    mine[r] = {s.original[record.particle], record.boundary, record.feature, {record.force.x(), record.force.y(), record.force.z()},
               {record.point.x(), record.point.y(), record.point.z()},
               {record.rolling.x(), record.rolling.y(), record.rolling.z()}};
  }
  return mine;
}

void FastEngine::Impl::add_gathered_loads(std::vector<Load>& all_records) const {
  const std::size_t nb = s.boundaries.size();
  block_loads.assign(sum_blocks(total) * nb, BoundaryLoad{});
  std::sort(all_records.begin(), all_records.end(), [](const Load& a, const Load& b) {
    return std::tuple(a.original, a.boundary, a.feature) < std::tuple(b.original, b.boundary, b.feature);
  });
  for (const Load& r : all_records) {
    add_load(block_loads.data() + r.original / kSumBlock * nb, r.boundary, Vec3(r.force[0], r.force[1], r.force[2]),
             Vec3(r.point[0], r.point[1], r.point[2]), Vec3(r.rolling[0], r.rolling[1], r.rolling[2]));
  }
  add_block_loads();
  loads_stale = false;
}

std::size_t FastEngine::Impl::count_escaped() const {
  return static_cast<std::size_t>(std::count_if(s.escaped_via.begin(), s.escaped_via.begin() + static_cast<std::ptrdiff_t>(s.owned),
                                                [](std::int32_t via) { return via != 0; }));
}

void FastEngine::Impl::sum_loads() const {
  if (distributed()) {  // collective: every rank's records (made on every rank, run.cpp)
    const std::vector<Load> mine = own_loads();
    Bytes packed;
    Packer pk(packed);
    pk.put(static_cast<std::uint64_t>(mine.size()));
    pk.put_rows(mine.data(), mine.size());
    std::vector<Load> all_records;
    for (const Bytes& block : comm->allgather(packed)) {
      Unpacker u(block);
      u.get_rows(all_records, u.get<std::uint64_t>());
    }
    add_gathered_loads(all_records);
    return;
  }
  const std::size_t nb = s.boundaries.size();
  const std::size_t count = sum_blocks(total);
  block_loads.assign(count * nb, BoundaryLoad{});
  PPOHDEM_OMP(omp parallel for schedule(static) if (total >= kParallelMin))
  for (std::size_t b = 0; b < count; ++b) {
    for (std::size_t o = b * kSumBlock; o < std::min(total, (b + 1) * kSumBlock); ++o) {
      add_records(block_loads.data() + b * nb, s.where[o]);
    }
  }
  add_block_loads();
  loads_stale = false;
}

void FastEngine::Impl::add_block_loads() const {
  const std::size_t nb = s.boundaries.size();
  loads.assign(nb, BoundaryLoad{});
  for (std::size_t first = 0; first < block_loads.size(); first += nb) {
    for (std::size_t j = 0; j < nb; ++j) {
      loads[j].force += block_loads[first + j].force;
      loads[j].moment_about_origin += block_loads[first + j].moment_about_origin;
    }
  }
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

void FastEngine::Impl::reduce_one_rank(double history_dt, bool motion) {
  const std::size_t nb = s.boundaries.size();
  const std::size_t count = sum_blocks(total);
  block_sums.assign(count, {});
  block_loads.assign(count * nb, BoundaryLoad{});
  PPOHDEM_OMP(omp parallel for schedule(static) if (total >= kParallelMin))
  for (std::size_t b = 0; b < count; ++b) {
    std::array<double, 7> sum{};
    BoundaryLoad* to = block_loads.data() + b * nb;
    for (std::size_t o = b * kSumBlock; o < std::min(total, (b + 1) * kSumBlock); ++o) {
      const std::size_t k = s.where[o];
      const FastState::ParticleTerms& c = s.terms[k];
      sum[0] += c.elastic;
      sum[1] += c.dissipated;
      sum[2] += c.work;
      sum[3] += c.power;
      if (motion) {  // written by close_step
        sum[4] += c.kinetic;
        sum[5] += c.rotational;
        sum[6] += c.gravitational;
      }
      add_records(to, k);
    }
    block_sums[b] = sum;
  }
  const std::array<double, 7> sums = add_blocks(block_sums);
  add_contact_sums({sums[0], sums[1], sums[2], sums[3]}, history_dt);
  if (motion) {
    motion_sums = {sums[4], sums[5], sums[6]};
    motion_valid = true;
  }
  // A count (in storage order: the sums above visit the particles in construction order,
  // a random order in memory).
  escaped = count_escaped();
  add_block_loads();
  out_valid = false;
}

}  // namespace ppohdem::dem::fast
