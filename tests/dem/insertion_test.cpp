// Particle insertion (issue 38 item 5; ppohdem/dem/insertion.hpp, docs/objects.md "Particle
// insertion"). Oracles:
//   - the schedule's counts, worked out by hand;
//   - every inserted sphere inside its region and clear of every particle (an all-pairs loop,
//     independent of the cells of the insertion), of the walls and of an object (its analytic
//     distance), with controls where every candidate must fail;
//   - the size distributions' moments against the analytic ones (fixed seed, 5 standard errors);
//   - runs through run_scene: the counts in insertions.csv, the reference and the fast engine
//     at 1 and 2 threads bitwise equal, a restart from a checkpoint after some insertions
//     equal to the uninterrupted run; clear errors for bad [[insert]] keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/insertion.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/error.hpp"
#include "test_paths.hpp"

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

namespace ppohdem::dem {
namespace {

namespace fs = std::filesystem;

// ---- the schedule ---------------------------------------------------------------------------

TEST(InsertSchedule, CountModeEventsAndTotal) {
  InsertSchedule s;
  s.first_step = 5;
  s.every_steps = 10;
  s.last_step = 45;
  s.count = 4;
  // Events at steps 5, 15, 25, 35, 45 and no more.
  for (std::uint64_t k = 0; k < 5; ++k) {
    EXPECT_TRUE(s.has_event(k)) << k;
    EXPECT_EQ(s.step_of(k), 5 + 10 * static_cast<long>(k));
  }
  EXPECT_FALSE(s.has_event(5));
  EXPECT_EQ(s.wanted(0, 0, 1e-3), 4);
  s.total = 10;  // 4, 4, then the 2 left, then none
  EXPECT_EQ(s.wanted(0, 0, 1e-3), 4);
  EXPECT_EQ(s.wanted(1, 4, 1e-3), 4);
  EXPECT_EQ(s.wanted(2, 8, 1e-3), 2);
  EXPECT_EQ(s.wanted(3, 10, 1e-3), 0);
  InsertSchedule once;  // every_steps = 0: one event
  once.first_step = 7;
  once.count = 3;
  EXPECT_TRUE(once.has_event(0));
  EXPECT_FALSE(once.has_event(1));
}

TEST(InsertSchedule, RateModeCountsTheParticlesDueInEachInterval) {
  InsertSchedule s;
  s.every_steps = 100;  // with dt = 1e-4 s: 0.01 s
  s.rate = 250.0;       // 2.5 per interval: due 2, 5, 7, 10, 12 -> 2, 3, 2, 3, 2
  const long expected[] = {2, 3, 2, 3, 2};
  long so_far = 0;
  for (std::uint64_t k = 0; k < 5; ++k) {
    const long n = s.wanted(k, so_far, 1e-4);
    EXPECT_EQ(n, expected[k]) << "event " << k;
    so_far += n;
  }
  // A count that is an integer in exact arithmetic: 1/3 s^-1 x 3 s per event = 1 (0.999...
  // in floating point) is not lost.
  InsertSchedule third;
  third.every_steps = 3;
  third.rate = 1.0 / 3.0;
  EXPECT_EQ(third.wanted(0, 0, 1.0), 1);
}

// ---- candidates and their overlap tests -----------------------------------------------------

/// A sphere of radius `r_o` at `c` as a distance-field object (phi = |x - c| - r_o at the nodes).
std::shared_ptr<DistanceFieldObject> sphere_object(const Vec3& c, double r_o, double h) {
  const int n = static_cast<int>(std::ceil(4.0 * r_o / h)) + 1;
  const GridSpec g = GridSpec::spanning(c - Vec3::Constant(2.0 * r_o), c + Vec3::Constant(2.0 * r_o), {n, n, n});
  ScalarField f(g);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) f.at(i, j, k) = (g.position(i, j, k) - c).norm() - r_o;
    }
  }
  return std::make_shared<DistanceFieldObject>(f, RigidMotion{}, "ball");
}

Particles lattice(const Vec3& lo, int nx, int ny, int nz, double spacing, double r) {
  Particles out;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        Particle p;
        p.id = static_cast<std::int64_t>(out.size()) + 1;
        p.position = lo + spacing * Vec3(i, j, k);
        p.radius = r;
        out.push_back(p);
      }
    }
  }
  return out;
}

InsertSpec spec_in(const InsertRegion& region, double r_min, double r_max) {
  InsertSpec s;
  s.name = "test";
  s.region = region;
  s.sizes.kind = r_min == r_max ? InsertSizes::Kind::kConstant : InsertSizes::Kind::kUniform;
  s.sizes.r_min = r_min;
  s.sizes.r_max = r_max;
  s.seed = 12345;
  s.attempts = 200;
  return s;
}

InsertRegion box(const Vec3& lo, const Vec3& hi) {
  InsertRegion r;
  r.lo = lo;
  r.hi = hi;
  return r;
}

InsertRegion cylinder(const Vec3& point, const Vec3& axis, double radius, double length) {
  InsertRegion r;
  r.kind = InsertRegion::Kind::kCylinder;
  r.point = point;
  r.axis = axis.normalized();
  r.radius = radius;
  r.length = length;
  return r;
}

/// The oracle: every pair of `all` apart by at least the sum of its radii (all pairs, no cells).
void expect_no_overlap(const Particles& all) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    for (std::size_t j = i + 1; j < all.size(); ++j) {
      if ((all[i].position - all[j].position).norm() < all[i].radius + all[j].radius) ++bad;
    }
  }
  EXPECT_EQ(bad, 0u) << "overlapping pairs";
}

TEST(InsertEvent, InsertedSpheresLieInTheRegionAndTouchNothing) {
  // A 4 cm box region with a lattice of 64 existing particles in one corner, a plane wall
  // cutting it at z = 0.01 (normal +z: the region below is outside the domain) and a ball object
  // of radius 8 mm in its middle; 400 spheres of 0.8-1.5 mm asked for in a box and in a
  // cylinder (axis tilted).
  const double h = 0.5e-3;
  const Vec3 ball_centre(0.02, 0.02, 0.025);
  const double ball_radius = 0.008;
  BoundaryList boundaries = {std::make_shared<PlaneWall>(Vec3(0, 0, 0.01), Vec3(0, 0, 1)),
                             sphere_object(ball_centre, ball_radius, h)};
  const Particles existing = lattice(Vec3(0.002, 0.002, 0.012), 4, 4, 4, 0.0025, 1e-3);
  for (const InsertRegion& region : {box(Vec3(0, 0, 0), Vec3(0.04, 0.04, 0.04)),
                                     cylinder(Vec3(0.02, 0.02, 0.0), Vec3(0.1, -0.1, 1.0), 0.018, 0.04)}) {
    SCOPED_TRACE(region.kind == InsertRegion::Kind::kBox ? "box" : "cylinder");
    const InsertSpec spec = spec_in(region, 0.8e-3, 1.5e-3);
    InsertCounters c;
    std::int64_t next_id = 1000;
    const Particles added = insert_event(spec, 400, c, existing, boundaries, 0.0, next_id);
    EXPECT_EQ(c.inserted + c.failed, 400);
    EXPECT_EQ(static_cast<std::int64_t>(added.size()), c.inserted);
    EXPECT_GT(c.inserted, 300);  // a sparse fill: most find a place
    EXPECT_EQ(next_id, 1000 + c.inserted);
    for (std::size_t k = 0; k < added.size(); ++k) {
      const Particle& p = added[k];
      EXPECT_EQ(p.id, 1000 + static_cast<std::int64_t>(k));  // ids in candidate order
      EXPECT_TRUE(region.holds(p.position, p.radius)) << "id " << p.id;
      EXPECT_GE(p.position.z() - 0.01, p.radius) << "id " << p.id << " in the wall";
      // The field's interpolant exceeds the distance by at most the cell diagonal (d is
      // 1-Lipschitz), so the analytic distance is at least R minus that diagonal...
      const double d = (p.position - ball_centre).norm() - ball_radius;
      EXPECT_GE(d, p.radius - std::sqrt(3.0) * h) << "id " << p.id << " in the ball";
      // ...and the engines see no contact.
      EXPECT_FALSE(boundaries[1]->contact(p.position, p.radius, 0.0).has_value()) << "id " << p.id;
      EXPECT_GE(p.radius, 0.8e-3);
      EXPECT_LE(p.radius, 1.5e-3);
    }
    Particles all = existing;
    all.insert(all.end(), added.begin(), added.end());
    expect_no_overlap(all);
    // The candidates did reach the wall, the ball and the lattice (else the checks above saw
    // nothing): draws beyond 4 per particle are rejections.
    EXPECT_GT(c.draws, 4u * static_cast<std::uint64_t>(c.inserted + c.failed));
  }
}

TEST(InsertEvent, CandidatesThatCannotFitFailAndAreCounted) {
  // Controls: a region inside the wall, a region inside the ball, a region full of particles.
  const BoundaryList wall = {std::make_shared<PlaneWall>(Vec3(0, 0, 0.01), Vec3(0, 0, 1))};
  const BoundaryList ball = {sphere_object(Vec3(0.02, 0.02, 0.02), 0.008, 0.5e-3)};
  const Particles packed = lattice(Vec3(0, 0, 0), 10, 10, 10, 2e-3, 1e-3);  // touching spheres
  struct Case {
    const char* what;
    InsertRegion region;
    const BoundaryList* boundaries;
    const Particles* existing;
  };
  const BoundaryList none;
  const Particles empty;
  for (const Case& k : {Case{"wall", box(Vec3(0, 0, 0), Vec3(0.01, 0.01, 0.0105)), &wall, &empty},
                        Case{"ball", box(Vec3(0.017, 0.017, 0.017), Vec3(0.023, 0.023, 0.023)), &ball, &empty},
                        Case{"particles", box(Vec3(0.002, 0.002, 0.002), Vec3(0.016, 0.016, 0.016)), &none, &packed}}) {
    SCOPED_TRACE(k.what);
    const InsertSpec spec = spec_in(k.region, 1e-3, 1e-3);
    InsertCounters c;
    std::int64_t next_id = 5000;
    const Particles added = insert_event(spec, 7, c, *k.existing, *k.boundaries, 0.0, next_id);
    EXPECT_TRUE(added.empty());
    EXPECT_EQ(c.failed, 7);
    EXPECT_EQ(c.draws, 7u * 200u * 4u);  // every attempt of every particle
  }
}

/// The particles of `all` whose centre lies in [lo, hi] (closed).
Particles within(const Particles& all, const std::pair<Vec3, Vec3>& box) {
  Particles in;
  for (const Particle& p : all) {
    if (((p.position.array() >= box.first.array()) && (p.position.array() <= box.second.array())).all()) in.push_back(p);
  }
  return in;
}

TEST(InsertEvent, FromTheParticlesWithinReachTheSameAsFromTheWholeSystem) {
  // What each rank of a run passes (insertion_run.cpp): the particles within insert_reach of
  // the region for a radius at least the system's largest, and that largest radius. Oracle:
  // the event from the whole system. A bed of 1 mm spheres reaching into the box region, and
  // three 6 mm spheres whose centres lie 4 mm outside its faces, so that they reach 2 mm into
  // it: only the largest radius makes the reach hold them.
  Particles all = lattice(Vec3(0.0, 0.0, 0.0), 16, 16, 10, 0.0026, 1e-3);
  for (const Vec3& c : {Vec3(-0.004, 0.02, 0.035), Vec3(0.02, 0.044, 0.032), Vec3(0.03, 0.03, 0.054)}) {
    Particle big;
    big.id = static_cast<std::int64_t>(all.size()) + 1;
    big.position = c;
    big.radius = 6e-3;
    all.push_back(big);
  }
  const double largest = 6e-3;
  const BoundaryList walls = {std::make_shared<PlaneWall>(Vec3(0, 0, 0), Vec3(0, 0, 1))};
  for (const InsertRegion& region : {box(Vec3(0.0, 0.0, 0.02), Vec3(0.04, 0.04, 0.05)),
                                     cylinder(Vec3(0.02, 0.02, 0.02), Vec3(0.05, 0.1, 1.0), 0.02, 0.03)}) {
    SCOPED_TRACE(region.kind == InsertRegion::Kind::kBox ? "box" : "cylinder");
    const InsertSpec spec = spec_in(region, 0.8e-3, 1.4e-3);
    InsertCounters whole_counters;
    std::int64_t whole_id = 5000;
    const Particles whole = insert_event(spec, 600, whole_counters, all, walls, 0.0, whole_id);
    ASSERT_GT(whole.size(), 100u);
    ASSERT_GT(whole_counters.draws, 4u * 600u) << "no candidate was refused: the particles near the region were never tested";
    Particles together = all;  // the independent oracle: all pairs, no cells, no reach
    together.insert(together.end(), whole.begin(), whole.end());
    expect_no_overlap(together);
    for (const double bound : {largest, 2.0 * largest}) {  // the run's bound is at least the largest
      SCOPED_TRACE("reach for a radius of " + std::to_string(bound) + " m");
      const Particles nearby = within(all, insert_reach(spec, bound));
      EXPECT_LT(nearby.size(), all.size());
      InsertCounters c;
      std::int64_t next_id = 5000;
      const Particles part = insert_event(spec, 600, c, nearby, largest, walls, 0.0, next_id);
      ASSERT_EQ(part.size(), whole.size());
      for (std::size_t k = 0; k < part.size(); ++k) {
        EXPECT_EQ(part[k].id, whole[k].id);
        EXPECT_EQ(part[k].radius, whole[k].radius);
        EXPECT_TRUE(part[k].position == whole[k].position) << "particle " << k;
      }
      EXPECT_EQ(c.draws, whole_counters.draws);
      EXPECT_EQ(c.inserted, whole_counters.inserted);
      EXPECT_EQ(c.failed, whole_counters.failed);
      EXPECT_EQ(next_id, whole_id);
    }
    if (region.kind != InsertRegion::Kind::kBox) continue;
    // Control: a reach taken for the small spheres only leaves the large ones out, and the
    // event then places spheres into them.
    InsertCounters c;
    std::int64_t next_id = 5000;
    const Particles blind = insert_event(spec, 600, c, within(all, insert_reach(spec, 1e-3)), 1e-3, walls, 0.0, next_id);
    std::size_t overlaps = 0;
    for (const Particle& p : blind) {
      for (std::size_t b = all.size() - 3; b < all.size(); ++b) {
        if ((p.position - all[b].position).norm() < p.radius + all[b].radius) ++overlaps;
      }
    }
    EXPECT_GT(overlaps, 0u) << "the control found no sphere in a large one: the test would not see a short reach";
  }
}

// ---- size distributions ---------------------------------------------------------------------

/// `n` particles in a cube of 1 m (volume fraction ~1e-7: rejections, which would favour small
/// sizes, are negligible).
TEST(InsertCells, AtLeastTheReachAndAtMostFourMillionCellsForAnyBox) {
  // The cells of an event's overlap test: two particles that can touch must lie in adjacent
  // cells (side >= reach), and the table of list heads must stay small (<= 2^22 cells) for
  // any box, the thin ones whose thin axis counts one cell however small the side.
  const auto cells = [](const Vec3& lo, const Vec3& hi, double side) {
    double n = 1.0;
    for (int i = 0; i < 3; ++i) n *= std::max(1.0, std::ceil((hi[i] - lo[i]) / side));
    return n;
  };
  struct Case {
    const char* what;
    Vec3 lo, hi;
    double reach;
  };
  const Case cases[] = {
      {"a 10 cm cube, 1 mm reach", Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1), 1e-3},
      {"a 10 x 10 x 30 cm box of 0.5 mm spheres", Vec3(0, 0, 0), Vec3(0.105, 0.105, 0.3), 1e-3},
      {"a 4 x 4 m plate 0.64 mm thick", Vec3(-2, -2, 0), Vec3(2, 2, 6.4e-4), 2e-4},
      {"a 100 x 100 m plate 1 um thick", Vec3(0, 0, 0), Vec3(100, 100, 1e-6), 4e-7},
      {"a 1 km needle", Vec3(0, 0, 0), Vec3(1000, 1e-3, 1e-3), 2e-4},
      {"a box smaller than its reach", Vec3(0, 0, 0), Vec3(1e-4, 1e-4, 1e-4), 1e-3},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const double side = insert_cell_side(c.lo, c.hi, c.reach);
    EXPECT_GE(side, c.reach);
    EXPECT_LE(cells(c.lo, c.hi, side), 4194304.0);
  }
  // Not coarser than needed: a cube's cells are the reach while it leaves fewer than 2^21, and
  // its side is the cube root of the volume over 2^21 when the reach would leave more.
  EXPECT_EQ(insert_cell_side(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1), 1e-3), 1e-3);
  EXPECT_NEAR(insert_cell_side(Vec3(0, 0, 0), Vec3(1, 1, 1), 1e-4), std::cbrt(1.0 / 2097152.0), 1e-15);
  // A thin plate that needs it gets a side grown by less than the last factor of 1.25.
  const double plate = insert_cell_side(Vec3(0, 0, 0), Vec3(100, 100, 1e-6), 4e-7);
  EXPECT_GT(cells(Vec3(0, 0, 0), Vec3(100, 100, 1e-6), plate / 1.25), 4194304.0);
}

Particles sparse_sample(const InsertSizes& sizes, long n) {
  InsertSpec spec = spec_in(box(Vec3::Zero(), Vec3::Ones()), 1e-4, 1e-4);
  spec.sizes = sizes;
  InsertCounters c;
  std::int64_t next_id = 1;
  Particles out = insert_event(spec, n, c, {}, {}, 0.0, next_id);
  EXPECT_EQ(static_cast<long>(out.size()), n);
  return out;
}

TEST(InsertSizes, UniformRadiiHaveTheAnalyticMeanAndVariance) {
  // Uniform on [a, b]: mean (a + b)/2, variance (b - a)^2/12, fourth central moment
  // (b - a)^4/80. Tolerance 5 standard errors (sigma/sqrt(N) for the mean,
  // sqrt((mu4 - sigma^4)/N) for the variance): a correct generator fails with probability
  // ~6e-7, and the fixed seed makes the outcome reproducible.
  const double a = 1e-4, b = 3e-4;
  const long n = 20000;
  InsertSizes sizes;
  sizes.kind = InsertSizes::Kind::kUniform;
  sizes.r_min = a;
  sizes.r_max = b;
  const Particles p = sparse_sample(sizes, n);
  double mean = 0.0;
  for (const Particle& q : p) mean += q.radius;
  mean /= static_cast<double>(n);
  double var = 0.0;
  for (const Particle& q : p) var += (q.radius - mean) * (q.radius - mean);
  var /= static_cast<double>(n - 1);
  const double sigma2 = (b - a) * (b - a) / 12.0, mu4 = std::pow(b - a, 4) / 80.0;
  EXPECT_NEAR(mean, (a + b) / 2.0, 5.0 * std::sqrt(sigma2 / n));
  EXPECT_NEAR(var, sigma2, 5.0 * std::sqrt((mu4 - sigma2 * sigma2) / n));
}

TEST(InsertSizes, DiscreteFractionsAndMaterialsFollowTheProbabilities) {
  // Fractions by number against p_k within 5 binomial standard errors sqrt(p (1 - p) / N).
  InsertSizes sizes;
  sizes.kind = InsertSizes::Kind::kDiscrete;
  sizes.entries = {{1e-4, 0.2, 0}, {2e-4, 0.5, 1}, {4e-4, 0.3, 2}};
  const long n = 20000;
  const Particles p = sparse_sample(sizes, n);
  std::array<long, 3> counts{};
  for (const Particle& q : p) {
    const int k = q.radius == 1e-4 ? 0 : q.radius == 2e-4 ? 1 : q.radius == 4e-4 ? 2 : -1;
    ASSERT_GE(k, 0) << "radius " << q.radius << " is not an entry's";
    EXPECT_EQ(q.material, sizes.entries[static_cast<std::size_t>(k)].material);
    ++counts[static_cast<std::size_t>(k)];
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const double prob = sizes.entries[k].probability;
    EXPECT_NEAR(static_cast<double>(counts[k]) / n, prob, 5.0 * std::sqrt(prob * (1.0 - prob) / n)) << "entry " << k;
  }
}

TEST(InsertUniform, IsTheTop53BitsOfSplitMix64) {
  // SplitMix64's first output for seed 0 is 0xE220A8397B1DCDAF (Vigna's reference splitmix64.c
  // with x = 0: x += 0x9E3779B97F4A7C15, then the two multiply-xorshift rounds).
  EXPECT_EQ(insert_uniform(0, 0), static_cast<double>(0xE220A8397B1DCDAFULL >> 11) * 0x1.0p-53);
  for (std::uint64_t u = 0; u < 1000; ++u) {
    const double x = insert_uniform(99, u);
    ASSERT_TRUE(x >= 0.0 && x < 1.0) << x;
  }
}

// ---- runs -----------------------------------------------------------------------------------

/// A 3 cm box with five walls filled from above at 5,000 particles/s every 200 steps (7 per
/// event with dt = 7e-6 s), two materials (discrete sizes), falling at 0.2 m/s and spinning,
/// friction (histories); a second table adds 5 particles every 600 steps from 0.004 s into a
/// cylinder; 2,400 steps; the energy check on.
const char* kFill = R"([simulation]
dt = 7.0e-6
steps = 2400
gravity = [0.0, 0.0, -9.81]

[[material]]
name = "a"
density = 2500.0
young = 5.0e7
poisson = 0.3
restitution = 0.5
friction = 0.5

[[material]]
name = "b"
density = 7800.0
young = 1.0e8
poisson = 0.3
restitution = 0.6
friction = 0.3

[contact]
model = "hertz-mindlin"

[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
[[wall]]
point = [0.03, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
[[wall]]
point = [0.0, 0.03, 0.0]
normal = [0.0, -1.0, 0.0]

[[insert]]
region = "box"
lo = [0.0, 0.0, 0.004]
hi = [0.03, 0.03, 0.012]
rate = 5000.0
every_steps = 200
sizes = [{ radius = 1.0e-3, probability = 0.6, material = "a" },
         { radius = 1.4e-3, probability = 0.4, material = "b" }]
velocity = [0.0, 0.0, -0.2]
angular_velocity = [0.0, 10.0, 0.0]
seed = 3

[[insert]]
region = "cylinder"
point = [0.015, 0.015, 0.014]
axis = [0.0, 0.0, 1.0]
radius = 0.01
length = 0.008
count = 5
start = 0.004
every_steps = 600
radius_min = 0.8e-3
radius_max = 1.2e-3
material = "b"

[output]
dir = "out"
every = 600
progress = false
)";

std::string file_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The file without its comment lines (the provenance header names the engine).
std::string body(const fs::path& file) {
  std::stringstream in(file_text(file));
  std::string line, out;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') out += line + '\n';
  }
  return out;
}

Scene fill_scene(const fs::path& dir, const std::string& text = kFill) {
  return read_scene_text(text, (dir / "fill.toml").string(), dir);
}

template <class Engine>
Particles run_fill(const fs::path& dir, RunOptions options = {}) {
  const Scene scene = fill_scene(dir);
  Engine engine(scene.setup);
  std::ostringstream log;
  run_scene(engine, scene, "test", log, options);
  return engine.particles();
}

bool same_bits(const Particles& a, const Particles& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Particle &p = a[i], &q = b[i];
    if (p.id != q.id || p.material != q.material || std::memcmp(&p.radius, &q.radius, sizeof(double)) != 0) return false;
    for (const auto& [x, y] : {std::pair(&p.position, &q.position), std::pair(&p.velocity, &q.velocity),
                               std::pair(&p.angular_velocity, &q.angular_velocity), std::pair(&p.force, &q.force)}) {
      if (std::memcmp(x->data(), y->data(), 3 * sizeof(double)) != 0) return false;
    }
  }
  return true;
}

TEST(InsertRun, CountsFollowTheScheduleAndEnginesAgreeBitwise) {
  const fs::path root = ppohdem::test::scratch_dir();
  fs::create_directories(root / "reference");
  const Particles reference = run_fill<reference::ReferenceEngine>(root / "reference");
  // insertions.csv: insert 0 at steps 0, 200, ..., 2400 (13 events), 5000/s x 200 x 7e-6 s
  // = 7 per event (6.99999... in floating point: not lost to rounding); insert 1 at steps 571
  // (0.004 s / dt = 571.4, the nearest step), 1171, 1771, 2371 with 5 each.
  std::stringstream rows(body(root / "reference" / "out" / "insertions.csv"));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "step,time,insert,requested,inserted,failed,total_inserted,total_failed");
  std::vector<std::array<long, 4>> seen;  // step, insert, requested, inserted + failed
  while (std::getline(rows, line)) {
    long step, insert, requested, inserted, failed;
    double time;
    ASSERT_EQ(std::sscanf(line.c_str(), "%ld,%lf,%ld,%ld,%ld,%ld", &step, &time, &insert, &requested, &inserted, &failed), 6) << line;
    seen.push_back({step, insert, requested, inserted + failed});
  }
  std::vector<std::array<long, 4>> expected;
  long total = 0;
  for (long k = 0; k <= 12; ++k) {
    expected.push_back({200 * k, 0, 7, 7});
    total += 7;
    for (const long s : {571L, 1171L, 1771L, 2371L}) {
      if (s > 200 * k && s < 200 * (k + 1)) {
        expected.push_back({s, 1, 5, 5});
        total += 5;
      }
    }
  }
  EXPECT_EQ(seen, expected);
  EXPECT_EQ(static_cast<long>(reference.size()), total);  // 111: no failures in this sparse fill
  // Fast engine, 1 and 2 threads: the same bits.
  for (const int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
#ifdef PPOHDEM_WITH_OPENMP
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
#endif
    const fs::path dir = root / ("fast" + std::to_string(threads));
    fs::create_directories(dir);
    const Particles fast = run_fill<fast::FastEngine>(dir);
#ifdef PPOHDEM_WITH_OPENMP
    omp_set_num_threads(before);
#endif
    EXPECT_TRUE(same_bits(fast, reference));
    for (const char* file : {"final.csv", "energy.csv", "insertions.csv", "frame_001200.csv"}) {
      EXPECT_EQ(body(dir / "out" / file), body(root / "reference" / "out" / file)) << file;
    }
  }
}

/// The fill scene onto a bed of 1,152 particles (a jittered lattice), inserting every 100
/// steps for 400 steps: from kParallelMin = 1024 particles on, the fast engine's loops really
/// run on several threads.
std::string bed_fill_text() {
  std::string text = kFill;
  text.replace(text.find("steps = 2400"), 12, "steps = 400");
  text.insert(text.find("[[wall]]"),
              "[particles]\ngenerator = \"lattice\"\nbox_min = [0.001, 0.001, 0.001]\nbox_max = [0.029, 0.029, 0.0195]\n"
              "count = 1152\nradius = 1.0e-3\nseed = 4\njitter = 0.1\nmaterial = \"a\"\n\n");
  text.replace(text.find("lo = [0.0, 0.0, 0.004]"), 22, "lo = [0.0, 0.0, 0.022]");
  text.replace(text.find("hi = [0.03, 0.03, 0.012]"), 24, "hi = [0.03, 0.03, 0.030]");
  text.replace(text.find("every_steps = 200"), 17, "every_steps = 100");
  return text;
}

template <class Engine>
Particles run_bed_fill(const fs::path& dir, int threads) {
#ifdef PPOHDEM_WITH_OPENMP
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  fs::create_directories(dir);
  const Scene scene = fill_scene(dir, bed_fill_text());
  Engine engine(scene.setup);
  std::ostringstream log;
  const RunSummary summary = run_scene(engine, scene, "test", log);
#ifdef PPOHDEM_WITH_OPENMP
  omp_set_num_threads(before);
#endif
  // Insert 0 at steps 0, 100, ..., 400, 3.5 per event: due 3, 7, 10, 14, 17; insert 1 starts
  // at step 571, after the end.
  EXPECT_EQ(summary.inserted, 17);
  return engine.particles();
}

TEST(InsertRun, OntoABedOfManyParticlesThreadsAndEnginesAgreeBitwise) {
  const fs::path root = ppohdem::test::scratch_dir();
  const Particles reference = run_bed_fill<reference::ReferenceEngine>(root / "reference", 1);
  ASSERT_EQ(reference.size(), 1152u + 17u);
  EXPECT_EQ(reference.back().id, 1169);  // ids after the bed's 1..1152, in insertion order
  for (const int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    const fs::path dir = root / ("fast" + std::to_string(threads));
    EXPECT_TRUE(same_bits(run_bed_fill<fast::FastEngine>(dir, threads), reference));
    for (const char* file : {"energy.csv", "insertions.csv"}) {
      EXPECT_EQ(body(dir / "out" / file), body(root / "reference" / "out" / file)) << file;
    }
  }
}

TEST(InsertRun, RestartAfterSomeInsertionsContinuesBitwise) {
  const fs::path root = ppohdem::test::scratch_dir();
  for (const bool fast_engine : {true, false}) {
    SCOPED_TRACE(fast_engine ? "fast" : "reference");
    const fs::path whole = root / (fast_engine ? "fast_whole" : "reference_whole");
    const fs::path parts = root / (fast_engine ? "fast_parts" : "reference_parts");
    fs::create_directories(whole);
    fs::create_directories(parts);
    auto run = [&](const fs::path& dir, RunOptions options, long steps) {
      Scene scene = fill_scene(dir);
      scene.steps = steps;
      std::unique_ptr<DemEngine> engine;
      if (fast_engine) engine = std::make_unique<fast::FastEngine>(scene.setup);
      else engine = std::make_unique<reference::ReferenceEngine>(scene.setup);
      std::ostringstream log;
      run_scene(*engine, scene, "test", log, options);
      return engine->particles();
    };
    const Particles uninterrupted = run(whole, {}, 2400);
    // 1200 steps (an energy row of the whole run too): 7 events of insert 0, the last one at
    // the checkpoint's step (in it), and 2 of insert 1.
    RunOptions first;
    first.checkpoint_every = 1200;
    run(parts, first, 1200);
    RunOptions second;
    second.restart = std::make_shared<const Checkpoint>(read_checkpoint(parts / "out" / kCheckpointFile));
    EXPECT_EQ(second.restart->insertion.counters.at(0).events, 7u);
    EXPECT_EQ(second.restart->insertion.counters.at(1).events, 2u);
    const Particles continued = run(parts, second, 2400);
    EXPECT_TRUE(same_bits(continued, uninterrupted));
    // A checkpoint without the scene's [[insert]] tables (another scene, or format version 3)
    // is refused by name.
    RunOptions other;
    Checkpoint without = *second.restart;
    without.insertion = InsertionRecord{};
    other.restart = std::make_shared<const Checkpoint>(without);
    try {
      run(root / "other", other, 2400);
      ADD_FAILURE() << "restart accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("checkpoint: 0 [[insert]] tables, the scene has 2"), std::string::npos) << e.what();
    }
    for (const char* file : {"final.csv", "energy.csv", "insertions.csv"}) {
      EXPECT_EQ(body(parts / "out" / file), body(whole / "out" / file)) << file;
    }
  }
}

TEST(InsertRun, TheInsertedEnergyIsInputNotAnEnergyError) {
  // Particles inserted above the floor bring kinetic and potential energy in; the energy check
  // counts it as input, so a run of 13 insertions passes a growth limit of 1 % (each event
  // adds about as much energy as the particles already in the box hold).
  const fs::path dir = ppohdem::test::scratch_dir();
  std::string text = kFill;
  text.replace(text.find("progress = false\n"), 17, "progress = false\n\n[checks]\nmax_energy_growth = 0.01\n");
  const Scene scene = fill_scene(dir, text);
  reference::ReferenceEngine engine(scene.setup);
  std::ostringstream log;
  const RunSummary s = run_scene(engine, scene, "test", log);
  EXPECT_GT(s.inserted, 100);
  EXPECT_EQ(s.insert_failed, 0);
  EXPECT_LT(s.margins.energy_growth, 0.01);
  EXPECT_NE(log.str().find("inserted " + std::to_string(s.inserted) + " particles, 0 could not"), std::string::npos) << log.str();
}

TEST(InsertRun, AnEventSeesTheLargeParticlesOfEarlierEventsNearItsRegion) {
  // A run gives an event only the particles within its reach (DemEngine::particles_in), the
  // reach taken for the largest radius present. Step 0 inserts three 6 mm spheres whose
  // centres lie 4.5 mm outside the region of step 1's 1 mm spheres and reach 1.5 mm into it: a
  // reach taken for the small spheres alone (2.8 mm) would leave them out. Oracle: no overlap
  // among all the particles afterwards (all pairs, no cells). Both engines (the reference
  // through DemEngine's default particles_in, the fast one through its own).
  const fs::path dir = ppohdem::test::scratch_dir();
  const std::string text = R"([simulation]
dt = 1.0e-6
steps = 2
gravity = [0.0, 0.0, 0.0]

[material]
density = 2500.0
young = 5.0e7
poisson = 0.3
restitution = 0.5
friction = 0.5

[contact]
model = "hertz-mindlin"

[[insert]]
name = "large"
region = "box"
lo = [-0.0105, 0.0, 0.0]
hi = [0.00151, 0.04, 0.03]
count = 3
radius = 6.0e-3
seed = 5

[[insert]]
name = "small"
region = "box"
lo = [0.0, 0.0, 0.0]
hi = [0.02, 0.04, 0.03]
count = 1500
start = 1.0e-6
radius = 1.0e-3
seed = 6

[output]
dir = "out"
progress = false
)";
  const Scene scene = fill_scene(dir, text);
  for (const bool fast : {false, true}) {
    SCOPED_TRACE(fast ? "fast" : "reference");
    std::unique_ptr<DemEngine> engine;
    if (fast) engine = std::make_unique<fast::FastEngine>(scene.setup);
    else engine = std::make_unique<reference::ReferenceEngine>(scene.setup);
    std::ostringstream log;
    const RunSummary summary = run_scene(*engine, scene, "test", log);
    const Particles& all = engine->particles();
    ASSERT_EQ(std::count_if(all.begin(), all.end(), [](const Particle& p) { return p.radius == 6e-3; }), 3);
    EXPECT_GT(summary.inserted, 1000);
    expect_no_overlap(all);
  }
}

// ---- errors ---------------------------------------------------------------------------------

std::string error_of(const std::string& insert_table) {
  std::string text = kFill;
  const auto at = text.find("[[insert]]");
  const auto end = text.find("[output]");
  text = text.substr(0, at) + insert_table + "\n" + text.substr(end);
  try {
    (void)read_scene_text(text, "fill.toml", ppohdem::test::scratch_dir());
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(InsertScene, BadKeysAreRefusedNamingFileLineAndWhatWasExpected) {
  const std::string text = kFill;  // the [[insert]] table's first line:
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("[[insert]]")), '\n'));
  struct Case {
    std::string table;
    int line_offset;
    std::string expected;
  };
  const std::string box = "[[insert]]\nregion = \"box\"\nlo = [0.0, 0.0, 0.0]\nhi = [0.03, 0.03, 0.03]\n";
  for (const Case& c : {
           Case{box + "radius = 1e-3\ncount = 1\ncolour = 3\n", 6, "unknown key 'colour' in [insert]"},
           Case{"[[insert]]\nregion = \"sphere\"\nradius = 1e-3\ncount = 1\n", 1, "region: expected \"box\" or \"cylinder\""},
           Case{box + "radius = 1e-3\ncount = 1\nrate = 5.0\nevery = 0.1\n", 0, "exactly one of count (per event) or rate"},
           Case{box + "radius = 1e-3\nrate = 5.0\n", 5, "rate needs every"},
           Case{box + "count = 1\n", 0, "exactly one size distribution"},
           Case{box + "count = 1\nsizes = [{radius = 1e-3, probability = 0.3}, {radius = 2e-3, probability = 0.6}]\n", 5,
                "probabilities sum to 0.9"},
           Case{box + "count = 1\nsizes = [{radius = 1e-3, probability = 1.0, material = \"c\"}]\n", 5, "unknown material 'c'"},
           Case{box + "count = 1\nradius_min = 2e-3\nradius_max = 1e-3\n", 6, "radius_max must be >= radius_min"},
           Case{"[[insert]]\nregion = \"box\"\nlo = [0.0, 0.0, 0.0]\nhi = [0.03, 0.001, 0.03]\nradius = 1e-3\ncount = 1\n", 0,
                "region is too small"},
           Case{box + "radius = 1e-3\ncount = 1\nevery_steps = 0\n", 6, "every: expected at least one time step"},
           Case{box + "radius = 1e-3\ncount = 1\nstart = 0.1\nstop = 0.05\n", 7, "stop must be >= start"},
           Case{"[[insert]]\nregion = \"cylinder\"\npoint = [0.0, 0.0, 0.0]\naxis = [0.0, 0.0, 0.0]\nradius = 0.01\nlength = 0.01\n"
                "radius_min = 1e-3\nradius_max = 1e-3\ncount = 1\n", 3, "axis must not be zero"},
           Case{box + "radius = 1e-3\ncount = 1\nattempts = 0\n", 6, "attempts must be >= 1"},
       }) {
    const std::string message = error_of(c.table);
    SCOPED_TRACE(c.table);
    EXPECT_NE(message.find("fill.toml:" + std::to_string(line + c.line_offset)), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

TEST(InsertScene, AFillNeedsNoParticlesTable) {
  const Scene scene = fill_scene(ppohdem::test::scratch_dir());
  EXPECT_TRUE(scene.setup.particles.empty());
  ASSERT_EQ(scene.inserts.size(), 2u);
  EXPECT_EQ(scene.inserts[0].name, "insert 0");
  EXPECT_EQ(scene.inserts[1].schedule.first_step, 571);  // 0.004 s / 7e-6 s = 571.4: the nearest step
  // The time-step limit covers the particles to come: radius 0.8 mm of material b is the
  // fastest, 0.2 T_R = 0.2 pi R sqrt(rho/G) / (0.1631 nu + 0.8766).
  const double g = 1.0e8 / (2.0 * 1.3);
  const double t_r = 3.141592653589793 * 0.8e-3 * std::sqrt(7800.0 / g) / (0.1631 * 0.3 + 0.8766);
  EXPECT_NEAR(time_step_limit(scene.setup).limit, 0.2 * t_r, 1e-12 * t_r);
}

TEST(InsertScene, CollisionTimeOfAnEmptySceneUsesTheInsertedSizes) {
  // The linear law's reference pair (two particles of the mean radius) comes from the sizes
  // to come: a discrete 0.25 x 1 mm + 0.75 x 2 mm has the mean radius 1.75 mm.
  const std::string text = R"([simulation]
dt = 1e-6
steps = 10
[material]
density = 2500.0
young = 5.0e7
poisson = 0.3
restitution = 0.5
friction = 0.5
[contact]
model = "linear"
collision_time = 1e-4
[[insert]]
region = "box"
lo = [0.0, 0.0, 0.0]
hi = [0.03, 0.03, 0.03]
count = 10
sizes = [{ radius = 1.0e-3, probability = 0.25 }, { radius = 2.0e-3, probability = 0.75 }]
)";
  const Scene scene = fill_scene(ppohdem::test::scratch_dir(), text);
  ASSERT_EQ(scene.inserts.size(), 1u);
  const Material& m = scene.setup.material;
  const auto expected = LinearSpringDashpot::from_collision_time(1e-4, m.mass(1.75e-3) / 2.0, m.restitution, m.friction, 2.0 / 7.0);
  EXPECT_EQ(std::get<LinearSpringDashpot>(scene.setup.law).normal_stiffness(), expected.normal_stiffness());
}

}  // namespace
}  // namespace ppohdem::dem
