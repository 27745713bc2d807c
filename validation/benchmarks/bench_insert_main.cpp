// The cost of one particle-insertion event in the fast engine against its step
// (docs/objects.md "Particle insertion"): `ppohdem-bench-insert SCENE [events]` builds the
// scene's system, then alternates 20 steps with one event of 10 particles (1 mm, box region
// over the top 15 mm of the system's bounding box) and prints the medians: seconds per step,
// per candidate search (insert_event), per engine insertion (FastEngine::insert_particles).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/insertion.hpp"
#include "ppohdem/dem/scene.hpp"

using namespace ppohdem::dem;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: ppohdem-bench-insert SCENE [events]\n");
    return 2;
  }
  const int events = argc > 2 ? std::atoi(argv[2]) : 15;
  const Scene scene = read_scene(argv[1]);
  fast::FastEngine engine(scene.setup);
  engine.advance(20);
  ppohdem::Vec3 lo = engine.particles().front().position, hi = lo;
  for (const Particle& p : engine.particles()) {
    lo = lo.cwiseMin(p.position);
    hi = hi.cwiseMax(p.position);
  }
  InsertSpec spec;
  spec.region.lo = ppohdem::Vec3(lo.x(), lo.y(), hi.z());
  spec.region.hi = ppohdem::Vec3(hi.x(), hi.y(), hi.z() + 0.015);
  spec.sizes.r_min = spec.sizes.r_max = 1e-3;
  InsertCounters counters;
  std::int64_t next_id = 0;
  for (const Particle& p : engine.particles()) next_id = std::max(next_id, p.id + 1);
  std::vector<double> step, search, insert;
  using clock = std::chrono::steady_clock;
  for (int k = 0; k < events; ++k) {
    const auto t0 = clock::now();
    engine.advance(20);
    const auto t1 = clock::now();
    const Particles added = insert_event(spec, 10, counters, engine.particles(), scene.setup.boundaries, engine.time(), next_id);
    const auto t2 = clock::now();
    engine.insert_particles(added);
    const auto t3 = clock::now();
    step.push_back(std::chrono::duration<double>(t1 - t0).count() / 20.0);
    search.push_back(std::chrono::duration<double>(t2 - t1).count());
    insert.push_back(std::chrono::duration<double>(t3 - t2).count());
  }
  std::printf("particles %zu, %d events: step %.3g s, candidate search %.3g s, engine insertion %.3g s (%.1f steps)\n",
              engine.particles().size(), events, median(step), median(search), median(insert),
              median(insert) / median(step));
  return 0;
}
