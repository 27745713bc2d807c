#pragma once
// The scene of the reliability tests: a small frictional pile in a box with a moving side
// wall and a rotating ball (a distance-field object) pushed into it from above, so that a
// checkpoint holds particle-pair and particle-boundary tangential histories, a moving wall,
// a moving object, dissipated energy and boundary work. As SimulationSetup (engine tests)
// and as a TOML scene with its files (CLI tests).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "../objects/object_fields.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/dem/simulation_setup.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"

namespace ppohdem::dem::test {

constexpr double kPileRadius = 1.0e-3;  // m
constexpr double kPileBox = 8.4e-3;     // box edge [m]: 4 x 4 lattice of 2.1 mm pitch
constexpr double kPileDt = 1.0e-5;      // s: 58% of the limit 0.2 T_R = 1.73e-5 s
constexpr double kBallRadius = 3.0e-3;  // m

inline Material pile_material() {
  Material m;
  m.density = 2500.0;  // kg/m^3
  m.young = 1.0e7;     // Pa
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = 0.5;  // tangential histories
  return m;
}

/// 4 x 4 x 3 = 48 spheres on a lattice of pitch 2.1 mm (gaps 0.1 mm), with deterministic
/// "random" velocities of up to 0.15 m/s and spins so contacts form within ~10 steps.
inline Particles pile_particles() {
  Particles ps;
  std::int64_t id = 100;  // ids unrelated to storage order
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        Particle p;
        p.id = id;
        id += 7;
        p.radius = kPileRadius * (1.0 - 0.02 * ((i + 2 * j + 3 * k) % 3));  // 0.96 .. 1 mm
        p.position = Vec3(1.05e-3 + 2.1e-3 * i, 1.05e-3 + 2.1e-3 * j, 1.05e-3 + 2.1e-3 * k);
        const double a = 1.7 * i + 2.3 * j + 3.1 * k;
        p.velocity = 0.15 * Vec3(std::sin(a), std::cos(1.3 * a), std::sin(0.7 * a + 1.0));  // m/s
        p.angular_velocity = Vec3(50.0 * std::cos(a), 0.0, 30.0 * std::sin(a));            // rad/s
        ps.push_back(p);
      }
    }
  }
  return ps;
}

/// Ball of radius 3 mm above the pile's centre, moving down at 0.3 m/s and spinning at
/// 40 rad/s about x: it reaches the top layer (6.25 mm) after ~1.2 ms (120 steps).
inline GridSpec ball_grid() {
  const double h = 0.25e-3;  // m
  const int n = 41;          // 10 mm: ball plus 2 mm on each side
  const Vec3 centre(0.5 * kPileBox, 0.5 * kPileBox, 6.3e-3 + kBallRadius + 0.3e-3);
  return GridSpec{centre - Vec3::Constant(0.5 * h * (n - 1)), Vec3::Constant(h), {n, n, n}};
}
inline Vec3 ball_centre() { return ball_grid().origin + Vec3::Constant(0.5 * 0.25e-3 * 40); }
inline RigidMotion ball_motion(double speed = 0.3) {
  RigidMotion m;
  m.velocity = Vec3(0.0, 0.0, -speed);        // m/s
  m.angular_velocity = Vec3(40.0, 0.0, 0.0);  // rad/s
  m.centroid = ball_centre();
  return m;
}

/// Floor, four side walls (the +x wall moving inwards at 5 mm/s) and the ball (boundary 5).
inline SimulationSetup pile_setup() {
  SimulationSetup s;
  s.dt = kPileDt;
  s.gravity = Vec3(0, 0, -9.81);
  s.material = pile_material();
  s.law = HertzMindlin::from_material(s.material);
  s.particles = pile_particles();
  s.boundaries = {
      std::make_shared<PlaneWall>(Vec3(0, 0, 0), Vec3(0, 0, 1)),
      std::make_shared<PlaneWall>(Vec3(0, 0, 0), Vec3(1, 0, 0)),
      std::make_shared<PlaneWall>(Vec3(kPileBox, 0, 0), Vec3(-1, 0, 0), Vec3(-5e-3, 0, 0)),
      std::make_shared<PlaneWall>(Vec3(0, 0, 0), Vec3(0, 1, 0)),
      std::make_shared<PlaneWall>(Vec3(0, kPileBox, 0), Vec3(0, -1, 0)),
      std::make_shared<DistanceFieldObject>(ball_field(ball_grid(), ball_centre(), kBallRadius), ball_motion(),
                                            "ball")};
  s.source = "pile";
  return s;
}
constexpr std::int64_t kBallBoundary = 5;

inline std::string vec_toml(const Vec3& v) {
  std::ostringstream s;
  s.precision(17);
  s << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return s.str();
}

/// Writes pile.toml (+ pile.csv, ball.vtk) into `dir`, output into dir/out, with `extra`
/// appended (e.g. a [checks] table). Frames every `every` steps (csv and vtk). `ball_speed`
/// [m/s] downwards (0: the ball only spins, for long runs).
inline std::filesystem::path write_pile_scene(const std::filesystem::path& dir, long steps, long every,
                                              const std::string& extra = "", double ball_speed = 0.3) {
  std::filesystem::create_directories(dir);
  write_particles_csv(dir / "pile.csv", pile_particles(), "reliability test pile");
  write_vtk_structured_points(dir / "ball.vtk", ball_field(ball_grid(), ball_centre(), kBallRadius));
  const RigidMotion m = ball_motion(ball_speed);
  std::ofstream toml(dir / "pile.toml");
  toml.precision(17);
  toml << "[simulation]\ndt = " << kPileDt << "\nsteps = " << steps << "\ngravity = [0.0, 0.0, -9.81]\n"
       << "[material]\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.3\nrestitution = 0.5\nfriction = 0.5\n"
       << "[contact]\nmodel = \"hertz-mindlin\"\n[particles]\nfile = \"pile.csv\"\n"
       << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
       << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
       << "[[wall]]\npoint = [" << kPileBox << ", 0.0, 0.0]\nnormal = [-1.0, 0.0, 0.0]\nvelocity = [-5e-3, 0.0, 0.0]\n"
       << "[[wall]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n"
       << "[[wall]]\npoint = [0.0, " << kPileBox << ", 0.0]\nnormal = [0.0, -1.0, 0.0]\n"
       << "[[object]]\nname = \"ball\"\ndistance = \"ball.vtk\"\nvelocity = " << vec_toml(m.velocity)
       << "\naxis = [1.0, 0.0, 0.0]\nomega = 40.0\ncentroid = " << vec_toml(m.centroid) << "\n"
       << "[output]\ndir = \"out\"\nevery = " << every << "\nformats = [\"csv\", \"vtk\"]\nprogress = false\n"
       << extra;
  return dir / "pile.toml";
}

}  // namespace ppohdem::dem::test
