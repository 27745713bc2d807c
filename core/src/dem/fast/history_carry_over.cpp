// Contact histories across a list build: taken by partner id before the rebuild, installed
// into the new slots after it; histories whose pair left the list lose their stored energy.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::take_history(History& h) const {
  const std::size_t n = s.owned;
  const bool pairs = s.friction && s.first.size() == n + 1;
  const bool boundaries = s.record_first.size() == n + 1;
  // The code of the history slot `slot` of particle k carries, or kNoSpring: a pair of
  // owned particles keeps its history on the lower-id side only (the kernel evaluates it
  // there), and this side's is its mirror. With one rank the mirror is not carried:
  // install_history keeps only the lower-id side's (the pair stays owned by this rank, so
  // its lower-id side stays the one that evaluates it), and only that side books a lost
  // history. With several ranks it travels with its particle, which may leave the partner.
  const bool mirrors = distributed();
  auto carried = [&](std::size_t k, std::uint32_t slot, bool& other_side) {
    const std::uint32_t j = s.partner[slot];
    other_side = j < n && s.id[j] < s.id[k];
    if (other_side && !mirrors) return kNoSpring;
    const std::uint32_t code = other_side ? s.spring_of[s.mirror[slot]] : s.spring_of[slot];
    return code == kNoSpring || !s.spring_at(code).holds_history() ? kNoSpring : code;
  };
  // Counts, offsets, then each particle's block filled on the threads.
  h.first.assign(n + 1, 0);
  h.record_first.assign(n + 1, 0);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t k = 0; k < n; ++k) {
    std::uint32_t count = 0;
    bool other_side = false;
    if (pairs) {
      for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) count += carried(k, slot, other_side) != kNoSpring;
    }
    h.first[k + 1] = count;
    h.record_first[k + 1] = boundaries ? s.record_first[k + 1] - s.record_first[k] : 0;
  }
  for (std::size_t k = 0; k < n; ++k) {
    h.first[k + 1] += h.first[k];
    h.record_first[k + 1] += h.record_first[k];
  }
  h.partner_id.resize(h.first[n]);
  h.spring.resize(h.first[n]);
  h.records.resize(h.record_first[n]);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t k = 0; k < n; ++k) {
    std::uint32_t a = h.first[k];
    if (pairs) {
      for (std::uint32_t slot = s.first[k]; slot < s.first[k + 1]; ++slot) {
        bool other_side = false;
        const std::uint32_t code = carried(k, slot, other_side);
        if (code == kNoSpring) continue;
        h.partner_id[a] = s.id[s.partner[slot]];
        h.spring[a++] = other_side ? s.spring_at(code).mirrored() : s.spring_at(code);
      }
    }
    if (boundaries) {
      std::copy(s.records.begin() + s.record_first[k], s.records.begin() + s.record_first[k + 1],
                h.records.begin() + h.record_first[k]);
    }
  }
}

void FastEngine::Impl::install_history(const History& h, const std::vector<std::uint32_t>& before) {
  const std::size_t n = s.owned;
  const int blocks = n >= kParallelMin ? max_threads() : 1;
  if (s.friction) {
    // Each slot's history (index into h) by a merge per particle, on the threads (the lost
    // ones into per-block lists: add_lost_energy sorts them); then pool 0 in slot order.
    constexpr std::uint32_t kNone = 0xffffffffu;
    std::vector<std::uint32_t> source(s.partner.size(), kNone);
    std::vector<std::vector<std::tuple<std::uint32_t, std::int64_t, double>>> lost_in(static_cast<std::size_t>(blocks));
    PPOHDEM_OMP(omp parallel for schedule(static, 1) num_threads(blocks))
    for (int block = 0; block < blocks; ++block) {
      auto& lost_here = lost_in[static_cast<std::size_t>(block)];
      for (std::size_t k = n * static_cast<std::size_t>(block) / static_cast<std::size_t>(blocks);
           k < n * static_cast<std::size_t>(block + 1) / static_cast<std::size_t>(blocks); ++k) {
        std::uint32_t a = h.first[before[k]];
        const std::uint32_t a_end = h.first[before[k] + 1];
        for (std::uint32_t b = s.first[k]; b < s.first[k + 1]; ++b) {
          const std::int64_t want = s.id[s.partner[b]];
          for (; a < a_end && h.partner_id[a] < want; ++a) lost(lost_here, h.spring[a], k, h.partner_id[a]);
          if (a < a_end && h.partner_id[a] == want) {
            // An owned lower-id partner keeps the pair's history (its mirror is this one).
            if (!(s.partner[b] < n && want < s.id[k])) source[b] = a;
            ++a;
          }
        }
        for (; a < a_end; ++a) lost(lost_here, h.spring[a], k, h.partner_id[a]);
      }
    }
    for (const auto& lost_here : lost_in) lost_terms.insert(lost_terms.end(), lost_here.begin(), lost_here.end());
    // Codes 1, 2, ... in slot order (entry 0: kNoSpring's): each block of slots counts its
    // histories, then numbers them from the sum of the counts before it.
    s.spring_of.resize(s.partner.size());
    std::vector<std::uint32_t> block_first(static_cast<std::size_t>(blocks) + 1, 0);
    const std::size_t slots = source.size();
    auto block_slots = [&](int block) {
      return std::pair{slots * static_cast<std::size_t>(block) / static_cast<std::size_t>(blocks),
                       slots * static_cast<std::size_t>(block + 1) / static_cast<std::size_t>(blocks)};
    };
    PPOHDEM_OMP(omp parallel num_threads(blocks))
    {
      PPOHDEM_OMP(omp for schedule(static, 1))
      for (int block = 0; block < blocks; ++block) {
        const auto [from, to] = block_slots(block);
        std::uint32_t count = 0;
        for (std::size_t b = from; b < to; ++b) count += source[b] != kNone;
        block_first[static_cast<std::size_t>(block) + 1] = count;
      }
      PPOHDEM_OMP(omp single)
      {
        block_first[0] = 1;
        for (int block = 0; block < blocks; ++block) block_first[static_cast<std::size_t>(block) + 1] += block_first[static_cast<std::size_t>(block)];
      }
      PPOHDEM_OMP(omp for schedule(static, 1))
      for (int block = 0; block < blocks; ++block) {
        const auto [from, to] = block_slots(block);
        std::uint32_t code = block_first[static_cast<std::size_t>(block)];
        for (std::size_t b = from; b < to; ++b) s.spring_of[b] = source[b] != kNone ? code++ : kNoSpring;
      }
    }
    const std::uint32_t next = block_first[static_cast<std::size_t>(blocks)];
    // Pool 0 reuses the last layout's storage (the ranges' pools go: lay_out_springs adds them
    // empty): entries 1 to next - 1 are all written below, entry 0 is kNoSpring's empty one.
    // A fresh zeroed pool, copied in, would zero and copy every spring again
    // (docs/performance.md "Cheaper list builds, second pass").
    s.spring_pools.resize(1);
    s.pool_shift = 31;
    SpringPool& pool = s.spring_pools[0];
    pool.resize(next);
    pool.set(0, TangentialSpring{});
    PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
    for (std::size_t b = 0; b < source.size(); ++b) {
      if (source[b] != kNone) pool.set(s.spring_of[b], h.spring[source[b]]);
    }
    lay_out_springs(s, kernel_threads(n), /*in_slot_order=*/true);  // checks the code range, adds the ranges' pools
  }
  // The boundary records: counts in the new order (reads at random: on the threads), their
  // running sums, then each particle's block copied.
  s.record_first.assign(n + 1, 0);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t k = 0; k < n; ++k) s.record_first[k + 1] = h.record_first[before[k] + 1] - h.record_first[before[k]];
  for (std::size_t k = 0; k < n; ++k) s.record_first[k + 1] += s.record_first[k];
  s.records.resize(s.record_first[n]);
  PPOHDEM_OMP(omp parallel for schedule(static) if (n >= kParallelMin))
  for (std::size_t k = 0; k < n; ++k) {
    std::uint32_t r = s.record_first[k];
    for (std::uint32_t from = h.record_first[before[k]]; from < h.record_first[before[k] + 1]; ++from, ++r) {
      s.records[r] = h.records[from];
      s.records[r].particle = static_cast<std::uint32_t>(k);
    }
  }
}

void FastEngine::Impl::add_lost_energy() {
  if (distributed()) {
    Bytes mine;
    Packer p(mine);
    for (const auto& [o, other, e] : lost_terms) {
      p.put(o);
      p.put(other);
      p.put(e);
    }
    lost_terms.clear();
    for (const Bytes& block : comm->allgather(mine)) {
      Unpacker u(block);
      while (!u.done()) {
        const auto o = u.get<std::uint32_t>();
        const auto other = u.get<std::int64_t>();
        lost_terms.emplace_back(o, other, u.get<double>());
      }
    }
  }
  std::sort(lost_terms.begin(), lost_terms.end());
  if (energy_balance) {
    for (const auto& term : lost_terms) dissipated += std::get<2>(term);
  }
  lost_terms.clear();
}

}  // namespace ppohdem::dem::fast
