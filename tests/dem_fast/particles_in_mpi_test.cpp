// Run under mpirun at 1, 2 and 3 ranks: what an insertion event asks of the fast engine
// without gathering the system (DemEngine::particle_extent, particles_in; docs/objects.md
// "Particle insertion"). Oracle: particles() (the whole system, gathered) filtered by the same
// boxes, bit for bit and in the same order, and its largest id and radius. The bed of
// FastEngineMpi's tests after 60 steps, so particles have crossed brick faces; boxes: none, the
// whole bed, a corner, two that overlap, one whose lo exceeds its hi, one outside everything,
// and a point box at a particle's centre (the boxes are closed).
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bed_scene.hpp"
#include "mpi_case.hpp"
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/scene.hpp"

namespace {

using ppohdem::Vec3;
using ppohdem::dem::DemEngine;
using ppohdem::dem::Particle;
using ppohdem::dem::Particles;

bool same_bits(const Particle& a, const Particle& b) {
  auto same = [](const Vec3& x, const Vec3& y) { return std::memcmp(x.data(), y.data(), 3 * sizeof(double)) == 0; };
  return a.id == b.id && a.material == b.material && std::memcmp(&a.radius, &b.radius, sizeof(double)) == 0 &&
         same(a.position, b.position) && same(a.velocity, b.velocity) && same(a.angular_velocity, b.angular_velocity) &&
         same(a.force, b.force) && same(a.torque, b.torque);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ppohdem;
  test::MpiCase run(&argc, &argv);
  const Comm& comm = run.comm();
  const std::filesystem::path dir =
      run.scratch("dem_particles_in", [](const std::filesystem::path& d) { test::write_bed(d, 12, 12, 10, 60, 60); });
  const dem::Scene scene = dem::read_scene(dir / "bed.toml");
  dem::fast::FastOptions options;
  options.comm = &comm;
  dem::fast::FastEngine engine(scene.setup, options);
  engine.advance(scene.steps);

  const DemEngine::Extent extent = engine.particle_extent();
  const Particles all = engine.particles();  // the oracle (a gather)
  DemEngine::Extent expected;
  for (const Particle& p : all) {
    expected.largest_id = std::max(expected.largest_id, p.id);
    expected.largest_radius = std::max(expected.largest_radius, p.radius);
  }
  if (extent.largest_id != expected.largest_id || extent.largest_radius != expected.largest_radius) {
    run.fail("particle_extent: " + std::to_string(extent.largest_id) + ", " + std::to_string(extent.largest_radius) +
             " instead of " + std::to_string(expected.largest_id) + ", " + std::to_string(expected.largest_radius));
  }

  const Vec3 lo(0.0, 0.0, 0.0), hi(2.1e-3 * 12, 2.1e-3 * 12, 2.1e-3 * 10 + 0.01);
  const Vec3 middle = 0.5 * (lo + hi);
  const Vec3 point = all[all.size() / 3].position;
  const std::vector<std::pair<std::string, std::vector<DemEngine::CentreBox>>> cases = {
      {"no box", {}},
      {"the whole bed", {{lo - Vec3::Constant(0.01), hi + Vec3::Constant(0.01)}}},
      {"a corner", {{lo - Vec3::Constant(0.01), middle - Vec3(0.004, 0.0, 0.002)}}},
      {"two that overlap", {{Vec3(0.003, 0.002, 0.0), Vec3(0.012, 0.02, 0.009)}, {Vec3(0.01, 0.0, 0.004), Vec3(0.02, 0.01, 0.015)}}},
      {"lo above hi", {{hi, lo}}},
      {"outside everything", {{hi + Vec3::Constant(1.0), hi + Vec3::Constant(2.0)}}},
      {"a point at a centre", {{point, point}}},
  };
  std::size_t found_in_some = 0;
  for (const auto& [what, boxes] : cases) {
    const Particles got = engine.particles_in(boxes);
    Particles want;
    for (const Particle& p : all) {
      for (const DemEngine::CentreBox& b : boxes) {
        if (((p.position.array() >= b.lo.array()) && (p.position.array() <= b.hi.array())).all()) {
          want.push_back(p);
          break;
        }
      }
    }
    if (got.size() != want.size()) {
      run.fail(what + ": " + std::to_string(got.size()) + " particles instead of " + std::to_string(want.size()));
      continue;
    }
    for (std::size_t k = 0; k < got.size(); ++k) {
      if (!same_bits(got[k], want[k])) {
        run.fail(what + ": particle " + std::to_string(k) + " (id " + std::to_string(got[k].id) +
                 ") differs from particles()'s");
        break;
      }
    }
    if (!want.empty() && want.size() < all.size()) ++found_in_some;
    std::printf("rank %d of %d, %s: %zu of %zu particles\n", comm.rank(), comm.size(), what.c_str(), got.size(), all.size());
  }
  run.expect(found_in_some >= 3, "fewer than 3 cases select a proper part of the particles: the test exercises too little");
  return run.exit_code();
}
