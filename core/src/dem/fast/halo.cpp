// The halo plan: which owned particles each rank holds as ghosts (built at a list build),
// and the refresh of the ghosts' moving fields after every drift: their owners' half kicks,
// from which each ghost repeats its owner's arithmetic.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::update_peers() {
  const double reach = halo_reach(r_max, skin);
  peers = distributed() ? halo_peers(decomposition, comm->rank(), reach) : std::vector<int>{};
}

void FastEngine::Impl::put_halo_layer_last(std::vector<std::uint32_t>& order) {
  update_peers();  // the bricks may have been re-cut (rebalance)
  const double reach = halo_reach(r_max, skin);
  // A ghost partner j of rank r lies in r's brick at the build (migration puts every particle
  // in its owner's brick; the outer bricks extend to infinity) and within reach of owned
  // particle k, so k is within reach of that brick: the halo rule, as make_ghosts applies it.
  std::vector<std::uint8_t> layer(order.size(), 0);  // by index before the sort
  PPOHDEM_OMP(omp parallel for schedule(static) if (order.size() >= kParallelMin))
  for (std::size_t k = 0; k < order.size(); ++k) {
    for (const int r : peers) {
      if (in_halo(decomposition, r, s.x[k], reach)) {
        layer[k] = 1;
        break;
      }
    }
  }
  const auto interior_end = std::stable_partition(order.begin(), order.end(), [&](std::uint32_t k) { return layer[k] == 0; });
  s.n_interior = static_cast<std::size_t>(interior_end - order.begin());
}

void FastEngine::Impl::make_ghosts() {
  update_peers();  // r_max may have changed (a restore)
  const std::size_t ranks = peers.size();
  halo_send.assign(ranks, {});
  halo_recv.assign(ranks, 0);
  if (!distributed()) return;
  const double reach = halo_reach(r_max, skin);
  std::vector<Bytes> to(ranks);
  for (std::size_t k = 0; k < s.owned; ++k) {
    for (std::size_t i = 0; i < ranks; ++i) {
      if (!in_halo(decomposition, peers[i], s.x[k], reach)) continue;
      halo_send[i].push_back(static_cast<std::uint32_t>(k));
      Packer p(to[i]);
      pack_particle(p, s, k);
    }
  }
  const std::vector<Bytes> from = comm->exchange_with(peers, to);
  ++exchanges;
  for (std::size_t r = 0; r < ranks; ++r) {
    Unpacker u(from[r]);
    while (!u.done()) {
      unpack_particle(u, s);
      ++halo_recv[r];
    }
  }
}

void FastEngine::Impl::pack_ghost_kicks(bool cached) {
  const std::size_t ranks = halo_send.size();
  halo_kicks.resize(ranks);
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::vector<std::uint32_t>& send = halo_send[r];
    halo_kicks[r].resize(send.size() * sizeof(HalfKick));
    unsigned char* write = halo_kicks[r].data();
    for (const std::uint32_t k : send) {
      const HalfKick kick = first_half_kick(s, k, cached);
      std::memcpy(write, kick.v.data(), sizeof(Vec3));
      std::memcpy(write + sizeof(Vec3), kick.w.data(), sizeof(Vec3));
      write += sizeof(HalfKick);
    }
  }
}

std::vector<std::size_t> FastEngine::Impl::ghost_kick_sizes() const {
  std::vector<std::size_t> sizes(halo_recv.size());  // known from the plan: one message each way
  for (std::size_t r = 0; r < sizes.size(); ++r) sizes[r] = halo_recv[r] * sizeof(HalfKick);
  return sizes;
}

void FastEngine::Impl::refresh_ghosts(bool cached) {
  if (!distributed()) return;
  static_assert(sizeof(HalfKick) == 2 * sizeof(Vec3) && sizeof(Vec3) == 3 * sizeof(double), "plain doubles");
  const std::vector<std::size_t> sizes = ghost_kick_sizes();
  const std::vector<Bytes> from = comm->exchange_with(peers, halo_kicks, &sizes);
  ++exchanges;
  apply_ghost_kicks(from, cached);
}

void FastEngine::Impl::apply_ghost_kicks(const std::vector<Bytes>& from, bool cached) {
  const std::size_t ranks = halo_send.size();
  std::size_t g = s.owned;
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::size_t count = halo_recv[r];
    if (from[r].size() != count * sizeof(HalfKick)) throw std::logic_error("fast engine: a halo message of the wrong size");
    const unsigned char* read = from[r].data();
    for (std::size_t c = 0; c < count; ++c, ++g) {
      HalfKick kick;
      std::memcpy(kick.v.data(), read, sizeof(Vec3));
      std::memcpy(kick.w.data(), read + sizeof(Vec3), sizeof(Vec3));
      read += sizeof(HalfKick);
      if (cached) {  // the owner's closing kick of the last step (close_kick)
        s.v[g] += kick.v;
        s.w[g] += kick.w;
      }
      kick_and_drift(s, g, kick);
    }
  }
}

struct FastEngine::Impl::GhostKicksInFlight final : HaloInFlight {
  Impl& m;
  bool cached;
  std::unique_ptr<Comm::PostedExchange> posted;
  bool done = false;
  GhostKicksInFlight(Impl& engine, bool cached_kick, std::unique_ptr<Comm::PostedExchange> exchange)
      : m(engine), cached(cached_kick), posted(std::move(exchange)) {}
  void poll() override {
    if (!done) m.comm->progress_exchange(*posted);
  }
  void complete() override {
    if (done) return;
    m.comm->finish_exchange(*posted);
    m.apply_ghost_kicks(posted->from, cached);
    done = true;
  }
};

std::unique_ptr<HaloInFlight> FastEngine::Impl::post_ghost_kicks(bool cached) {
  ++exchanges;
  ++overlapped_refreshes;
  return std::make_unique<GhostKicksInFlight>(*this, cached, comm->post_exchange_with(peers, halo_kicks, ghost_kick_sizes()));
}

}  // namespace ppohdem::dem::fast
