// `ppohdem project`: the fast engine's decomposition and halo for many ranks, computed in one
// process without running them (docs/performance.md "Projection to many nodes"):
//   ppohdem project SCENE.toml [--ranks 2,4,...] [--csv FILE]       the scene's particles
//   ppohdem project --lattice NX,NY,NZ [...]                          make_bench.py's bed, in memory
//   ppohdem project --weak NX,NY,NZ [...]                             weak scaling: that block per rank
// Prints per rank count P the particles, ghosts, halo bytes and messages per rank per step
// (mean and max over the ranks); --csv writes one row per rank.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "commands.hpp"
#include "ppohdem/dem/fast/halo_projection.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/io/atomic_file.hpp"

namespace ppohdem::app {
namespace {

struct ProjectOptions {
  std::string scene;
  std::vector<int> lattice;  ///< NX, NY, NZ
  std::vector<int> weak;     ///< the block of one rank: NX, NY, NZ
  std::vector<int> ranks = {2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096};
  std::string balance;  ///< "rcb", "off" or "" (the scene's, else rcb)
  double skin_fraction = dem::fast::FastOptions{}.skin_fraction;
  std::string csv;
};

/// A bed: centres, ids and the largest radius [m].
struct Bed {
  std::vector<Vec3> x;
  std::vector<std::int64_t> id;
  double r_max = 0.0;
};

// validation/peers/make_bench.py's bed: spheres of d = 1 mm on a simple cubic lattice of pitch
// 1.05 d, each centre jittered by +-0.02 R per axis (here by std::mt19937_64, seed 1, not
// Python's generator: the same lattice, other jitters), ids 1, 2, ... in x-fastest order.
constexpr double kDiameter = 1.0e-3, kPitch = 1.05 * kDiameter, kJitter = 0.02 * kDiameter / 2;

Bed lattice_bed(const std::array<long, 3>& n) {
  Bed bed;
  const long count = n[0] * n[1] * n[2];
  bed.x.reserve(static_cast<std::size_t>(count));
  bed.id.reserve(static_cast<std::size_t>(count));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> jitter(-kJitter, kJitter);
  for (long k = 0; k < n[2]; ++k) {
    for (long j = 0; j < n[1]; ++j) {
      for (long i = 0; i < n[0]; ++i) {
        const double xi = kPitch / 2 + kPitch * static_cast<double>(i) + jitter(rng);
        const double yj = kPitch / 2 + kPitch * static_cast<double>(j) + jitter(rng);
        const double zk = kPitch / 2 + kPitch * static_cast<double>(k) + jitter(rng);
        bed.x.emplace_back(xi, yj, zk);
        bed.id.push_back(static_cast<std::int64_t>(bed.id.size()) + 1);
      }
    }
  }
  bed.r_max = kDiameter / 2;
  return bed;
}

/// The weak-scaling bed of P ranks: the block replicated P times, each prime factor of P
/// (largest first) multiplying the lattice's currently shortest axis (ties: the lower axis),
/// so the bed grows in all three directions and holds exactly P blocks.
std::array<long, 3> weak_lattice(const std::vector<int>& block, int ranks) {
  std::array<long, 3> n = {block[0], block[1], block[2]};
  std::vector<int> factors;
  for (int m = ranks, f = 2; m > 1;) {
    if (m % f == 0) {
      factors.push_back(f);
      m /= f;
    } else {
      ++f;
    }
  }
  std::sort(factors.rbegin(), factors.rend());
  for (const int f : factors) {
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (n[static_cast<std::size_t>(a)] < n[static_cast<std::size_t>(axis)]) axis = a;
    }
    n[static_cast<std::size_t>(axis)] *= f;
  }
  return n;
}

Bed scene_bed(const std::string& path, std::string& balance) {
  dem::Scene scene = dem::read_scene(path);
  Bed bed;
  for (const dem::Particle& p : scene.setup.particles) {
    bed.x.push_back(p.position);
    bed.id.push_back(p.id);
    bed.r_max = std::max(bed.r_max, p.radius);
  }
  if (balance.empty()) balance = scene.parallel.balance ? "rcb" : "off";
  return bed;
}

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (const double a : v) s += a;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}
double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
double min_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

void run_project(const ProjectOptions& o) {
  const int sources = (o.scene.empty() ? 0 : 1) + (o.lattice.empty() ? 0 : 1) + (o.weak.empty() ? 0 : 1);
  if (sources != 1) throw InputError("project: give exactly one of SCENE, --lattice NX,NY,NZ, --weak NX,NY,NZ");
  for (const auto* dims : {&o.lattice, &o.weak}) {
    if (dims->empty()) continue;
    if (dims->size() != 3 || *std::min_element(dims->begin(), dims->end()) < 1) {
      throw InputError("project: --lattice / --weak: expected three counts >= 1, NX,NY,NZ");
    }
  }
  for (const int p : o.ranks) {
    if (p < 1) throw InputError("project: --ranks: expected rank counts >= 1, got " + std::to_string(p));
  }
  if (!(o.skin_fraction >= 0.0)) throw InputError("project: --skin-fraction: expected a number >= 0");
  std::string balance = o.balance;
  Bed bed;
  if (!o.scene.empty()) bed = scene_bed(o.scene, balance);
  if (!o.lattice.empty()) bed = lattice_bed({o.lattice[0], o.lattice[1], o.lattice[2]});
  if (balance.empty()) balance = "rcb";
  if (balance != "rcb" && balance != "off") throw InputError("project: --balance: expected \"rcb\" or \"off\", got \"" + balance + "\"");
  dem::fast::FastOptions options;
  options.skin_fraction = o.skin_fraction;
  options.balance = balance == "rcb" ? dem::fast::FastOptions::Balance::kBisection : dem::fast::FastOptions::Balance::kOff;

  std::unique_ptr<AtomicFileWriter> csv;
  if (!o.csv.empty()) {
    csv = std::make_unique<AtomicFileWriter>(o.csv);
    csv->stream() << "particles,ranks,rank,owned,ghosts_in,ghosts_out,peers,messages_in,messages_out,"
                     "refresh_bytes_in,refresh_bytes_out,creation_bytes_in,creation_bytes_out,interior\n";
  }
  std::printf("bricks: %s; per rank per step (halo refresh; mean / max over the ranks)\n",
              balance == "rcb" ? "recursive coordinate bisection" : "equal bricks");
  std::printf("| ranks | particles | owned mean | owned max | ghosts mean | ghosts max | halo KB in mean | max | "
              "halo KB out max | messages out mean | max | peers max | interior mean | interior min |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::size_t refresh_bytes = 0, creation_bytes = 0;
  for (const int ranks : o.ranks) {
    if (!o.weak.empty()) {
      bed = {};  // free the last bed first
      bed = lattice_bed(weak_lattice(o.weak, ranks));
    }
    if (bed.x.empty()) throw InputError("project: the bed has no particles");
    const dem::fast::HaloProjection h = dem::fast::project_halo(ranks, bed.x, bed.id, bed.r_max, options);
    refresh_bytes = h.refresh_bytes;
    creation_bytes = h.creation_bytes;
    std::vector<double> owned, interior, ghosts, in, out, messages, peers;
    for (std::size_t r = 0; r < h.rank.size(); ++r) {
      const dem::fast::RankTraffic& t = h.rank[r];
      owned.push_back(static_cast<double>(t.owned));
      interior.push_back(static_cast<double>(t.interior));
      ghosts.push_back(static_cast<double>(t.ghosts_in));
      in.push_back(static_cast<double>(t.ghosts_in * h.refresh_bytes));
      out.push_back(static_cast<double>(t.ghosts_out * h.refresh_bytes));
      messages.push_back(t.messages_out);
      peers.push_back(t.peers);
      if (csv) {
        csv->stream() << h.particles << ',' << ranks << ',' << r << ',' << t.owned << ',' << t.ghosts_in << ','
                      << t.ghosts_out << ',' << t.peers << ',' << t.messages_in << ',' << t.messages_out << ','
                      << t.ghosts_in * h.refresh_bytes << ',' << t.ghosts_out * h.refresh_bytes << ','
                      << t.ghosts_in * h.creation_bytes << ',' << t.ghosts_out * h.creation_bytes << ',' << t.interior
                      << '\n';
      }
    }
    std::printf("| %d | %zu | %.0f | %.0f | %.0f | %.0f | %.1f | %.1f | %.1f | %.2f | %.0f | %.0f | %.0f | %.0f |\n", ranks,
                h.particles, mean_of(owned), max_of(owned), mean_of(ghosts), max_of(ghosts), mean_of(in) / 1e3,
                max_of(in) / 1e3, max_of(out) / 1e3, mean_of(messages), max_of(messages), max_of(peers),
                mean_of(interior), min_of(interior));
    std::fflush(stdout);
  }
  if (csv) csv->commit();
  std::printf("reach 2 R_max + skin = %.6g m (skin %.3g R_max); %zu bytes per ghost per refresh, %zu at its creation\n",
              2.0 * bed.r_max + o.skin_fraction * bed.r_max, o.skin_fraction,
              refresh_bytes, creation_bytes);
}

}  // namespace

void register_project(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "project", "compute the fast engine's bricks and halo for many ranks in one process (no run): particles, "
                 "ghosts, halo bytes and messages per rank per step");
  auto o = std::make_shared<ProjectOptions>();
  cmd->add_option("scene", o->scene, "scene TOML whose particles to decompose");
  cmd->add_option("--lattice", o->lattice, "instead of a scene: make_bench.py's lattice bed NX,NY,NZ, made in memory")
      ->delimiter(',');
  cmd->add_option("--weak", o->weak, "weak scaling: a lattice of P blocks of NX,NY,NZ for each rank count P")
      ->delimiter(',');
  cmd->add_option("--ranks", o->ranks, "rank counts (default 2,4,...,4096)")->delimiter(',');
  cmd->add_option("--balance", o->balance, "rcb (default; the scene's [parallel] balance) or off");
  cmd->add_option("--skin-fraction", o->skin_fraction, "Verlet skin / R_max (the fast engine's default 0.2)");
  cmd->add_option("--csv", o->csv, "write one row per rank and rank count to this file");
  cmd->callback([o] { run_project(*o); });
}

}  // namespace ppohdem::app
