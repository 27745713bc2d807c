// The decomposition and halo of P ranks computed in one process (halo_projection.hpp): the
// engine's own bricks (load_balance.cpp, decompose_whole) and halo rule (decomposition.hpp,
// in_halo; halo.cpp applies it), counted instead of exchanged.
#include "ppohdem/dem/fast/halo_projection.hpp"

#include <stdexcept>

#include "engine_impl.hpp"

namespace ppohdem::dem::fast {

namespace {

/// Bytes of one ghost when it is created: pack_particle of one particle (halo.cpp).
std::size_t creation_bytes() {
  FastState s;
  for_each_particle_array(s, [](auto& a) { a.resize(1); });
  Bytes b;
  Packer p(b);
  pack_particle(p, s, 0);
  return b.size();
}

/// Bytes of one ghost in the per-step refresh: its owner's half kick (halo.cpp).
std::size_t refresh_bytes() { return sizeof(HalfKick); }

}  // namespace

HaloProjection project_halo(int ranks, const std::vector<Vec3>& x, const std::vector<std::int64_t>& id, double r_max,
                            const FastOptions& options) {
  if (ranks < 1) throw std::invalid_argument("project_halo: ranks must be >= 1");
  if (x.size() != id.size()) throw std::invalid_argument("project_halo: one id per particle expected");
  if (x.size() >= std::numeric_limits<std::uint32_t>::max()) throw std::invalid_argument("project_halo: too many particles");
  HaloProjection out;
  out.ranks = ranks;
  out.particles = x.size();
  out.reach = halo_reach(r_max, options.skin_fraction * r_max);  // skin as FastEngine's constructor sets it
  out.refresh_bytes = refresh_bytes();
  out.creation_bytes = creation_bytes();
  out.rank.assign(static_cast<std::size_t>(ranks), RankTraffic{});
  // The bricks as decompose_whole makes them with every particle on every rank.
  const SerialComm serial;
  const Decomposition d = options.balance == FastOptions::Balance::kBisection
                              ? Decomposition::bisection(ranks, x, id, x.size(), serial)
                              : Decomposition(ranks, x);
  // Owners, and the particles grouped by owner (a counting sort).
  std::vector<std::int32_t> owner(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    owner[k] = d.owner(x[k], id[k]);
    ++out.rank[static_cast<std::size_t>(owner[k])].owned;
  }
  std::vector<std::size_t> first(static_cast<std::size_t>(ranks) + 1, 0);
  for (int r = 0; r < ranks; ++r) first[static_cast<std::size_t>(r) + 1] = first[static_cast<std::size_t>(r)] + out.rank[static_cast<std::size_t>(r)].owned;
  std::vector<std::uint32_t> members(x.size());
  {
    std::vector<std::size_t> at(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < x.size(); ++k) members[at[static_cast<std::size_t>(owner[k])]++] = static_cast<std::uint32_t>(k);
  }
  owner = {};
  // Each rank's sends to each peer, as make_ghosts selects them.
  for (int r = 0; r < ranks; ++r) {
    RankTraffic& me = out.rank[static_cast<std::size_t>(r)];
    const std::vector<int> peers = halo_peers(d, r, out.reach);
    me.peers = static_cast<int>(peers.size());
    std::vector<std::size_t> sends(peers.size(), 0);
    for (std::size_t m = first[static_cast<std::size_t>(r)]; m < first[static_cast<std::size_t>(r) + 1]; ++m) {
      const Vec3& p = x[members[m]];
      bool layer = false;  // the halo layer, as put_halo_layer_last selects it
      for (std::size_t i = 0; i < peers.size(); ++i) {
        if (in_halo(d, peers[i], p, out.reach)) {
          ++sends[i];
          layer = true;
        }
      }
      me.interior += layer ? 0 : 1;
    }
    for (std::size_t i = 0; i < peers.size(); ++i) {
      if (sends[i] == 0) continue;  // refresh_ghosts sends no empty block
      RankTraffic& peer = out.rank[static_cast<std::size_t>(peers[i])];
      me.ghosts_out += sends[i];
      ++me.messages_out;
      peer.ghosts_in += sends[i];
      ++peer.messages_in;
    }
  }
  return out;
}

}  // namespace ppohdem::dem::fast
