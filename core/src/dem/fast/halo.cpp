// The halo plan: which owned particles each rank holds as ghosts (built at a list build),
// and the refresh of the ghosts' moving fields after every drift.
#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

void FastEngine::Impl::make_ghosts() {
  const std::size_t ranks = static_cast<std::size_t>(comm->size());
  halo_send.assign(ranks, {});
  halo_recv.assign(ranks, 0);
  if (!distributed()) return;
  const int me = comm->rank();
  const double reach = 2.0 * r_max + skin;
  // Slack: bricks one part in 1e6 of the reach larger, so that the rounding of a brick face
  // (relative 1e-16 of the coordinates) never hides a partner; extra ghosts cost nothing but
  // memory (the list keeps only pairs within R_i + R_j + skin).
  const double slack = 1e-6 * reach;
  std::vector<Bytes> to(ranks);
  for (std::size_t k = 0; k < s.owned; ++k) {
    for (int r = 0; r < static_cast<int>(ranks); ++r) {
      if (r == me || decomposition.distance2(r, s.x[k], slack) >= reach * reach) continue;
      halo_send[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(k));
      Packer p(to[static_cast<std::size_t>(r)]);
      pack_particle(p, s, k);
    }
  }
  const std::vector<Bytes> from = comm->exchange(to);
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
  const std::vector<Bytes> from = comm->exchange(to);
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
