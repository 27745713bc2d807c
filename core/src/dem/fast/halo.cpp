// The halo plan: which owned particles each rank holds as ghosts (built at a list build),
// and the refresh of the ghosts' moving fields after every drift.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::update_peers() {
  const double reach = halo_reach(r_max, skin);
  peers = distributed() ? halo_peers(decomposition, comm->rank(), reach) : std::vector<int>{};
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

void FastEngine::Impl::refresh_ghosts() {
  if (!distributed()) return;
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "a Vec3 array is a plain array of doubles");
  constexpr std::size_t kMovingArrays = 5;  // for_each_moving_array
  const std::size_t ranks = halo_send.size();
  std::vector<Bytes> to(ranks);
  std::vector<std::size_t> sizes(ranks);  // known from the plan: one message each way
  for (std::size_t r = 0; r < ranks; ++r) sizes[r] = halo_recv[r] * kMovingArrays * sizeof(Vec3);
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::vector<std::uint32_t>& send = halo_send[r];
    to[r].resize(send.size() * kMovingArrays * sizeof(Vec3));
    unsigned char* write = to[r].data();
    for_each_moving_array(s, [&](const std::vector<Vec3>& a) {
      for (const std::uint32_t k : send) {
        std::memcpy(write, a[k].data(), sizeof(Vec3));
        write += sizeof(Vec3);
      }
    });
  }
  const std::vector<Bytes> from = comm->exchange_with(peers, to, &sizes);
  ++exchanges;
  std::size_t g = s.owned;
  for (std::size_t r = 0; r < ranks; ++r) {
    const std::size_t count = halo_recv[r];
    if (from[r].size() != count * kMovingArrays * sizeof(Vec3)) {
      throw std::logic_error("fast engine: a halo message of the wrong size");
    }
    const unsigned char* read = from[r].data();
    for_each_moving_array(s, [&](std::vector<Vec3>& a) {
      for (std::size_t c = 0; c < count; ++c) {
        std::memcpy(a[g + c].data(), read, sizeof(Vec3));
        read += sizeof(Vec3);
      }
    });
    g += count;
  }
}

}  // namespace ppohdem::dem::fast
