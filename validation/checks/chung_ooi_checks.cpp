// Chung & Ooi (2011, Granular Matter 13:643-656): the eight particle-impact benchmarks, run
// through the DemEngine interface for every engine in CheckContext::engines, against the
// closed-form Hertz and linear solutions and the two-body solution of the Hertz-Mindlin spring
// model (hertz_theory.hpp). docs/validation.md lists each check and where every published
// parameter below was read (the paper's tables as implemented by three independent codes:
// YADE's benchmark scripts, Kratos DEMApplication's basic_benchmarks, PySPH's DEM examples).
//
//  test  materials (E [Pa], nu, rho [kg/m^3])                 R [m]        speeds            mu     e
//  1     glass 4.8e10 .20 2800; limestone 2.0e10 .25 2500      0.010 (two)  +-10 m/s          -      1
//  2     Al alloy 7.0e10 .30 2699; Mg alloy 4.0e10 .35 1800    0.10 / plane 0.2 m/s           -      1
//  3     Al oxide 3.8e11 .23 4000; cast iron 1.0e11 .25 7000   0.0025/plane 3.9 m/s           -      0.2-1
//  4     Al oxide; Al alloy 7.0e10 .33 2700                    0.0025/plane 3.9 m/s, 5-85 deg 0.092  0.98
//  5     steel 2.08e11 .30 7850; polyethylene 1.0e9 .40 1400   1e-5 / plane v_n 5, v_t varied 0.3    1
//  6     Al alloy (.33); nylon 2.5e9 .40 1000                  0.10 / plane v_n 0.2, spin varied 0.4  0.5
//  7     Al alloy (.33); copper 1.2e11 .35 8900                0.10 (two)   +-0.2, spins +-w    0.4    0.5
//  8     Al alloy (.33); nylon                                 0.10 on 0.50 0.2, spin varied    0.4    0.5
//
// A rigid plane: the engines' walls share the particle material, so the sphere is given
// Young's modulus 2E: then E* = E/(1-nu^2) and G* = G/(2-nu), the sphere-on-rigid-plane values
// (Johnson 1985, eq. 4.22; Mindlin 1949) -- the contact law sees only E*, G*, R*, m*.
// One material per scene here: in test 8 the large sphere has the small one's material
// (Kratos and PySPH make it 1000x stiffer and denser; docs/validation.md, Known gaps).
#include "chung_ooi_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "engines.hpp"
#include "hertz_theory.hpp"
#include "plot.hpp"
#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/contact_law.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/units.hpp"

namespace ppohdem::validation {
namespace {

using dem::Material;
using dem::Particle;
using dem::Particles;
using dem::SimulationSetup;

struct NamedMaterial {
  const char* name;
  double young, poisson, density;  ///< [Pa], [-], [kg/m^3]
};
// Published materials (see the table above and docs/validation.md for the sources).
constexpr NamedMaterial kGlass{"glass", 4.8e10, 0.20, 2800.0};
constexpr NamedMaterial kLimestone{"limestone", 2.0e10, 0.25, 2500.0};
constexpr NamedMaterial kAlAlloyTest2{"Al alloy", 7.0e10, 0.30, 2699.0};  // test 2's values
constexpr NamedMaterial kMgAlloy{"Mg alloy", 4.0e10, 0.35, 1800.0};
constexpr NamedMaterial kAlOxide{"Al oxide", 3.8e11, 0.23, 4000.0};
constexpr NamedMaterial kCastIron{"cast iron", 1.0e11, 0.25, 7000.0};
constexpr NamedMaterial kAlAlloy{"Al alloy", 7.0e10, 0.33, 2700.0};  // tests 4, 6-8
constexpr NamedMaterial kSteel{"steel", 2.08e11, 0.30, 7850.0};
constexpr NamedMaterial kPolyethylene{"polyethylene", 1.0e9, 0.40, 1400.0};
constexpr NamedMaterial kNylon{"nylon", 2.5e9, 0.40, 1000.0};
constexpr NamedMaterial kCopper{"copper", 1.2e11, 0.35, 8900.0};

/// Steps per (elastic) contact duration. Verlet's error is ~(dt/t_c)^2 = 6e-8, the sampled
/// maxima lie within (pi dt/t_c)^2/2 = 3e-7 of the peak: the 1e-4 tolerances below are set by
/// the published tables' 3-4 digits, not by the integrator.
constexpr double kStepsPerContact = 4000.0;

double sphere_mass(const NamedMaterial& m, double r) {
  return m.density * 4.0 / 3.0 * units::kPi * r * r * r;
}
double shear(const NamedMaterial& m) { return m.young / (2.0 * (1.0 + m.poisson)); }

/// Effective constants of a contact: against a rigid plane or between two spheres of `m`.
struct Effective {
  double m_eff, r_eff, e_star, g_star;
};
Effective plane_effective(const NamedMaterial& m, double r) {
  return {sphere_mass(m, r), r, m.young / (1.0 - m.poisson * m.poisson), shear(m) / (2.0 - m.poisson)};
}
Effective pair_effective(const NamedMaterial& m, double ra, double rb) {
  const double ma = sphere_mass(m, ra), mb = sphere_mass(m, rb);
  return {ma * mb / (ma + mb), ra * rb / (ra + rb), m.young / (2.0 * (1.0 - m.poisson * m.poisson)),
          shear(m) / (2.0 * (2.0 - m.poisson))};
}

struct BodyInit {
  double radius = 0.0;                   ///< [m]
  Vec3 velocity = Vec3::Zero();          ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< [rad/s]
};

struct ImpactRun {
  Particles after;
  double max_overlap = 0.0, max_force = 0.0, duration = 0.0;  ///< [m], [N], [s]
  std::vector<std::vector<double>> curve;  ///< (overlap, normal force) samples
  bool ended = false;
};

/// Sphere A (above, z > 0) hits a rigid plane z = 0 (no B) or sphere B (below). The normal is
/// z; tangential motion is along x, spins about y.
ImpactRun run_impact(const std::string& engine_name, const NamedMaterial& nm, double friction, double restitution,
                     const std::optional<dem::ContactLaw>& law_override, const BodyInit& a,
                     const std::optional<BodyInit>& b, double contact_time, bool keep_curve) {
  Material m;
  m.density = nm.density;
  m.young = b ? nm.young : 2.0 * nm.young;  // rigid plane: see the file comment
  m.poisson = nm.poisson;
  m.restitution = restitution;
  m.friction = friction;
  SimulationSetup s;
  s.dt = contact_time / kStepsPerContact;
  s.material = m;
  s.law = law_override ? *law_override : dem::ContactLaw(dem::HertzMindlin::from_material(m));
  const double v_rel = a.velocity.z() - (b ? b->velocity.z() : 0.0);  // < 0: approaching
  const double gap = -v_rel * s.dt * 20.5;  // contact starts after ~20 steps [m]
  Particle pa;
  pa.id = 1;
  pa.radius = a.radius;
  pa.velocity = a.velocity;
  pa.angular_velocity = a.angular_velocity;
  if (b) {
    pa.position = Vec3(0, 0, a.radius + 0.5 * gap);
    Particle pb;
    pb.id = 2;
    pb.radius = b->radius;
    pb.position = Vec3(0, 0, -b->radius - 0.5 * gap);
    pb.velocity = b->velocity;
    pb.angular_velocity = b->angular_velocity;
    s.particles = {pa, pb};
  } else {
    pa.position = Vec3(0, 0, a.radius + gap);
    s.particles = {pa};
    s.boundaries = {std::make_shared<dem::PlaneWall>(Vec3::Zero(), Vec3::UnitZ())};
  }
  auto engine = make_engine(engine_name, s);
  auto gap_of = [&](const Particles& p) {
    return b ? (p[0].position - p[1].position).norm() - p[0].radius - p[1].radius
             : p[0].position.z() - p[0].radius;
  };
  ImpactRun run;
  double previous_gap = gap_of(engine->particles()), previous_time = engine->time(), start = -1.0;
  const long max_steps = static_cast<long>(200.0 * kStepsPerContact);
  for (long n = 0; n < max_steps; ++n) {
    engine->step();
    const Particles& p = engine->particles();
    const double g = gap_of(p), t = engine->time();
    run.max_overlap = std::max(run.max_overlap, -g);
    run.max_force = std::max(run.max_force, p[0].force.z());
    if (keep_curve && g < 0.0 && n % 20 == 0) run.curve.push_back({-g, p[0].force.z()});
    const double crossing = previous_time + (t - previous_time) * previous_gap / (previous_gap - g);
    if (start < 0.0 && previous_gap > 0.0 && g <= 0.0) start = crossing;
    if (start >= 0.0 && previous_gap <= 0.0 && g > 0.0) {
      run.duration = crossing - start;
      run.after = p;
      run.ended = true;
      return run;
    }
    previous_gap = g;
    previous_time = t;
  }
  run.after = engine->particles();
  return run;
}

std::string sci(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string csv_path(const CheckContext& ctx, const std::string& name) {
  return (std::filesystem::path(ctx.work_dir) / name).string();
}

// ---- Tests 1 and 2: elastic normal impacts vs Hertz --------------------------------------

std::vector<CheckRow> normal_impact_rows(const CheckContext& ctx, const std::string& test,
                                         const NamedMaterial& nm, double radius, double speed,
                                         bool pair, const std::string& engine,
                                         std::vector<std::vector<double>>& curve_out) {
  const Effective eff = pair ? pair_effective(nm, radius, radius) : plane_effective(nm, radius);
  const double v_rel = pair ? 2.0 * speed : speed;
  const HertzImpactTheory h = hertz_impact(eff.m_eff, eff.r_eff, eff.e_star, v_rel);
  BodyInit a{radius, Vec3(0, 0, -speed), Vec3::Zero()};
  std::optional<BodyInit> b;
  if (pair) b = BodyInit{radius, Vec3(0, 0, speed), Vec3::Zero()};
  const ImpactRun run = run_impact(engine, nm, 0.0, 1.0, std::nullopt, a, b, h.duration, true);
  curve_out = run.curve;
  const std::string where = test + " " + nm.name;
  const std::string src = "Johnson 1985 sec. 11.4; 1e-4 = the published 3-4 digits (Verlet error 6e-8)";
  std::vector<CheckRow> rows;
  rows.push_back(compare_rel(where + ": max force", engine, run.max_force, h.max_force, 1e-4, "N", src));
  rows.push_back(compare_rel(where + ": max overlap", engine, run.max_overlap, h.max_overlap, 1e-4, "m", src));
  rows.push_back(compare_rel(where + ": contact duration", engine, run.duration, h.duration, 1e-4, "s", src));
  const double rebound = pair ? run.after[0].velocity.z() - run.after[1].velocity.z()
                              : run.after[0].velocity.z();
  rows.push_back(compare_rel(where + ": rebound/impact speed (e = 1)", engine, rebound / v_rel, 1.0, 1e-5,
                             "", "elastic: energy conserved; 1e-5 >> Verlet's O(dt^2) = 6e-8"));
  (void)ctx;
  return rows;
}

/// Linear spring-dashpot with the Hertz duration: closed-form oscillator (contact_law.hpp).
std::vector<CheckRow> linear_normal_rows(const NamedMaterial& nm, double radius, double speed,
                                         const std::string& engine) {
  const Effective eff = pair_effective(nm, radius, radius);
  const double v_rel = 2.0 * speed;
  const double t_c = hertz_impact(eff.m_eff, eff.r_eff, eff.e_star, v_rel).duration;
  const auto law = dem::LinearSpringDashpot::from_collision_time(t_c, eff.m_eff, 1.0, 0.0);
  const double omega0 = std::sqrt(law.normal_stiffness() / eff.m_eff);  // [rad/s]
  BodyInit a{radius, Vec3(0, 0, -speed), Vec3::Zero()};
  BodyInit b{radius, Vec3(0, 0, speed), Vec3::Zero()};
  const ImpactRun run = run_impact(engine, nm, 0.0, 1.0, dem::ContactLaw(law), a, b, t_c, false);
  const std::string where = std::string("test 1 ") + nm.name + " linear";
  const std::string src = "undamped oscillator: delta_max = v/omega0, F = k delta, t_c = pi/omega0; 1e-4 as Hertz";
  std::vector<CheckRow> rows;
  rows.push_back(compare_rel(where + ": max overlap", engine, run.max_overlap, v_rel / omega0, 1e-4, "m", src));
  rows.push_back(compare_rel(where + ": max force", engine, run.max_force,
                             law.normal_stiffness() * v_rel / omega0, 1e-4, "N", src));
  rows.push_back(compare_rel(where + ": contact duration", engine, run.duration, units::kPi / omega0, 1e-4, "s", src));
  return rows;
}

CheckGroup test1_and_2() {
  CheckGroup g;
  g.name = "Chung & Ooi tests 1-2: elastic normal impacts vs Hertz";
  g.in_quick = true;
  g.plots = {"validation_chung_ooi_t1_t2.png"};
  g.run = [](const CheckContext& ctx) {
    std::vector<CheckRow> rows;
    std::vector<std::vector<double>> all;  // case, overlap, force, hertz force
    int case_index = 0;
    for (const auto& engine : ctx.engines) {
      struct Case {
        const char* test;
        NamedMaterial m;
        double r, v;
        bool pair;
      };
      // Test 1: two identical spheres R = 0.010 m at +-10 m/s; test 2: R = 0.10 m at 0.2 m/s
      // on a rigid plane (Chung & Ooi's inputs).
      for (const Case& c : {Case{"test 1", kGlass, 0.010, 10.0, true}, Case{"test 1", kLimestone, 0.010, 10.0, true},
                            Case{"test 2", kAlAlloyTest2, 0.10, 0.2, false}, Case{"test 2", kMgAlloy, 0.10, 0.2, false}}) {
        std::vector<std::vector<double>> curve;
        auto r = normal_impact_rows(ctx, c.test, c.m, c.r, c.v, c.pair, engine, curve);
        rows.insert(rows.end(), r.begin(), r.end());
        const Effective eff = c.pair ? pair_effective(c.m, c.r, c.r) : plane_effective(c.m, c.r);
        for (const auto& s : curve)
          all.push_back({double(case_index), s[0], s[1],
                         4.0 / 3.0 * eff.e_star * std::sqrt(eff.r_eff) * std::pow(s[0], 1.5)});
        if (engine == ctx.engines.front()) ++case_index;
      }
      for (const auto& m : {kGlass, kLimestone}) {
        auto r = linear_normal_rows(m, 0.010, 10.0, engine);
        rows.insert(rows.end(), r.begin(), r.end());
      }
    }
    const std::string csv = csv_path(ctx, "t1_t2.csv");
    write_csv(csv, {"case", "overlap", "force", "hertz"}, all);
    run_plot(ctx, "force_overlap", csv, "validation_chung_ooi_t1_t2.png",
             {"test 1 glass", "test 1 limestone", "test 2 Al alloy", "test 2 Mg alloy"});
    return rows;
  };
  return g;
}

// ---- Test 3: restitution 0.2 ... 1.0 -----------------------------------------------------

CheckGroup test3() {
  CheckGroup g;
  g.name = "Chung & Ooi test 3: output restitution = input restitution";
  g.in_quick = true;
  g.plots = {"validation_chung_ooi_t3.png"};
  g.run = [](const CheckContext& ctx) {
    std::vector<CheckRow> rows;
    std::vector<std::vector<double>> data;  // material index, law (0 HM, 1 linear), e_in, e_out
    const double radius = 0.0025, speed = 3.9;  // m, m/s (Chung & Ooi's inputs)
    for (const auto& engine : ctx.engines) {
      int mi = 0;
      for (const auto& nm : {kAlOxide, kCastIron}) {
        const Effective eff = plane_effective(nm, radius);
        const double t_el = hertz_impact(eff.m_eff, eff.r_eff, eff.e_star, speed).duration;
        double worst_hm = 0.0, worst_lin = 0.0, worst_e_hm = 0.0, worst_e_lin = 0.0;
        for (double e : {0.2, 0.4, 0.6, 0.8, 1.0}) {
          Material m;
          m.density = nm.density;
          m.young = 2.0 * nm.young;
          m.poisson = nm.poisson;
          m.restitution = e;
          BodyInit a{radius, Vec3(0, 0, -speed), Vec3::Zero()};
          // Hertz-Mindlin with Tsuji damping: the damped contact lasts longer (1.1 t_el at e=0.5).
          const ImpactRun hm = run_impact(engine, nm, 0.0, e, dem::ContactLaw(dem::HertzMindlin::from_material(m)),
                                          a, std::nullopt, t_el, false);
          const double e_hm = hm.after[0].velocity.z() / speed;
          // Linear law with the elastic Hertz duration as collision time (m_ref = m*).
          const auto lin = dem::LinearSpringDashpot::from_collision_time(t_el, eff.m_eff, e, 0.0);
          const ImpactRun ln = run_impact(engine, nm, 0.0, e, dem::ContactLaw(lin), a, std::nullopt, t_el, false);
          const double e_lin = ln.after[0].velocity.z() / speed;
          if (std::abs(e_hm - e) > worst_hm) { worst_hm = std::abs(e_hm - e); worst_e_hm = e; }
          if (std::abs(e_lin - e) > worst_lin) { worst_lin = std::abs(e_lin - e); worst_e_lin = e; }
          if (engine == ctx.engines.front()) {
            data.push_back({double(mi), 0.0, e, e_hm});
            data.push_back({double(mi), 1.0, e, e_lin});
          }
        }
        const std::string where = std::string("test 3 ") + nm.name;
        rows.push_back(compare_le(where + " Hertz-Mindlin: max |e_out - e_in| over e = 0.2..1 (at e=" +
                                      sci(worst_e_hm) + ")",
                                  engine, worst_hm, 1e-4, "",
                                  "alpha(e) solved to 1e-10 (e to < 1e-6), Verlet O(dt^2) ~ 1e-7 at 4000 steps/contact"));
        rows.push_back(compare_le(where + " linear: max |e_out - e_in| (at e=" + sci(worst_e_lin) + ")", engine,
                                  worst_lin, 1e-4, "",
                                  "closed form e = exp(-gamma t_c / 2m*) (Schwager & Poeschel 2005); Verlet O(dt^2)"));
        ++mi;
      }
    }
    const std::string csv = csv_path(ctx, "t3.csv");
    write_csv(csv, {"material", "law", "e_in", "e_out"}, data);
    run_plot(ctx, "restitution", csv, "validation_chung_ooi_t3.png", {"Al oxide", "cast iron"});
    return rows;
  };
  return g;
}

// ---- Tests 4-8: oblique impacts vs the two-body Hertz-Mindlin solution -------------------

/// Tsuji's alpha(e) of the law the engines build for restitution e (a law parameter, not an
/// output: hertz_damping.hpp solves the dimensionless normal impact for it; test 3 checks that
/// the engines' measured restitution equals e).
double damping_ratio(const NamedMaterial& nm, double e) {
  Material m;
  m.density = nm.density;
  m.young = nm.young;
  m.poisson = nm.poisson;
  m.restitution = e;
  return dem::HertzMindlin::from_material(m).damping_ratio();
}

/// One oblique impact and the engine's outcome, compared in the two-body coordinates.
struct ObliqueOutcome {
  ObliqueProblem problem;
  ObliqueReference ref;
  Particles after;
  double v_t_after = 0.0;     ///< engine: V' (A's centre relative to B's, along x) [m/s]
  double slip_after = 0.0;    ///< engine: u' with the lever arms R at separation [m/s]
  double j_t = 0.0, j_n = 0.0;  ///< engine: impulses on A [N s]
  double impulse_error = 0.0;   ///< |J_t - J_t,ref| / (mu J_n,ref) [-]
  /// Two spheres whose centres move tangentially relative to each other: their line of
  /// centres turns during the contact by phi <= max(|V|, |V'|) t_c / (R_A + R_B) [rad], which
  /// the two-body solution (fixed normal) leaves out; it moves <= phi J_n between the normal and
  /// tangential impulses, i.e. phi/mu of mu J_n. Zero against a plane.
  double normal_rotation = 0.0;
};

/// Slip velocity of A's contact point relative to B's (plane: B at rest), along x, with the
/// lever arms R (at separation) [m/s].
double slip_velocity(const Particles& p, bool pair) {
  double v = p[0].velocity.x() - p[0].angular_velocity.y() * p[0].radius;
  if (pair) v -= p[1].velocity.x() + p[1].angular_velocity.y() * p[1].radius;
  return v;
}

ObliqueOutcome oblique_case(const std::string& engine, const NamedMaterial& nm, double mu, double e,
                            const BodyInit& a, const std::optional<BodyInit>& b) {
  const bool pair = b.has_value();
  const Effective eff = pair ? pair_effective(nm, a.radius, b->radius) : plane_effective(nm, a.radius);
  ObliqueOutcome o;
  ObliqueProblem& p = o.problem;
  auto body = [&](double r) {
    const double m = sphere_mass(nm, r);
    return ImpactBody{m, 0.4 * m * r * r, r};  // solid sphere I = (2/5) m R^2
  };
  p.a = body(a.radius);
  if (pair) p.b = body(b->radius);
  p.plane = !pair;
  p.e_star = eff.e_star;
  p.g_star = eff.g_star;
  p.mu = mu;
  p.alpha = damping_ratio(nm, e);
  p.v_n = -(a.velocity.z() - (pair ? b->velocity.z() : 0.0));
  p.v_t = a.velocity.x() - (pair ? b->velocity.x() : 0.0);
  p.spin_a = a.angular_velocity.y();
  p.spin_b = pair ? b->angular_velocity.y() : 0.0;
  o.ref = oblique_reference(p);
  const double t_c = hertz_impact(eff.m_eff, eff.r_eff, eff.e_star, p.v_n).duration;
  const ImpactRun run = run_impact(engine, nm, mu, e, std::nullopt, a, b, t_c, false);
  o.after = run.after;
  const Particles& q = run.after;
  o.v_t_after = q[0].velocity.x() - (pair ? q[1].velocity.x() : 0.0);
  o.slip_after = slip_velocity(q, pair);
  o.j_t = p.a.mass * (q[0].velocity.x() - a.velocity.x());
  o.j_n = p.a.mass * (q[0].velocity.z() - a.velocity.z());
  o.impulse_error = std::abs(o.j_t - o.ref.tangential_impulse) / (mu * o.ref.normal_impulse);
  if (pair)
    o.normal_rotation = std::max(std::abs(p.v_t), std::abs(o.ref.tangential_velocity_after)) * o.ref.duration /
                        (a.radius + b->radius);
  return o;
}

/// chi of Maw et al. for one material: (1 + mR^2/I)(1 - nu)/(2 - nu) = 7 G*/E*.
double chi(const NamedMaterial& nm) { return 3.5 * (1.0 - nm.poisson) / (2.0 - nm.poisson); }

/// 2e-3 of mu J_n: the two-body solution integrates the same equations with the same lever
/// arms, so what is left is the engines' time discretisation: Verlet O((dt/t_c)^2) = 6e-8, and
/// each stick/slip switch of the Coulomb cap, which the engines make at a step boundary: one
/// step of force, <= 1.5 mu F_mean dt = 1.5/4000 = 4e-4 of mu J_n per switch; the contacts
/// here switch at most 3 times (stick - slip - stick - slip, Maw et al. 1976) -> 1.1e-3;
/// rounded up to 2e-3. (RK4 with 100,000 steps: < 1e-8.)
constexpr double kImpulseTolerance = 2e-3;
const char* kImpulseSource =
    "two-body RK4 solution of the same law and lever arms; 2e-3 mu J_n = 3 stick/slip switches x 1.5 dt/t_c";
/// Sliding throughout (rigid-body limit): |J_t/(mu m* (1+e) v_n) - 1|. 5e-3: the engines'
/// contact sticks for its first steps while k_t xi builds up (~1% of t_c at the smallest
/// sliding incidences, where the force is ~1e-3 of its peak), plus the measured restitution's
/// 1e-4 (test 3). With damping (e < 1) the law itself sticks longer at first touch -- Tsuji's
/// damping force ~ delta^{1/4} delta' makes mu F_n large while k_t xi ~ delta^{1/2} is still
/// small -- so J_t stays below mu J_n by a deficit that decays slowly with Psi1 (1.2% just
/// above the sliding threshold at e = 0.5, 0.7% at twice it); rigid-body theory has no such
/// phase. That deficit, taken from the two-body solution at the same point, is added to the
/// bound (it is ~1e-12 for e = 1).
constexpr double kSlidingTolerance = 5e-3;

/// Published incidence sweep: x from X/n to X in n steps (n = 12 quick, 48 full).
std::vector<double> sweep(double x_max, bool quick) {
  const int n = quick ? 12 : 48;
  std::vector<double> x;
  for (int k = 1; k <= n; ++k) x.push_back(x_max * k / n);
  return x;
}

CheckGroup test4() {
  CheckGroup g;
  g.name = "Chung & Ooi test 4: oblique impact at 3.9 m/s, angles 5-85 deg";
  g.in_quick = true;
  g.plots = {"validation_chung_ooi_t4.png"};
  g.run = [](const CheckContext& ctx) {
    std::vector<CheckRow> rows;
    std::vector<std::vector<double>> data;  // mat, theta, e_t, e_t_ref, omega, omega_ref, angle, angle_ref
    // Chung & Ooi's inputs (after Kharaz, Gorham & Salman 2001): R 2.5 mm, 3.9 m/s, mu 0.092, e 0.98.
    const double radius = 0.0025, speed = 3.9, mu = 0.092, e = 0.98;
    const double step = ctx.quick ? 5.0 : 2.5;
    for (const auto& engine : ctx.engines) {
      int mi = 0;
      for (const auto& nm : {kAlOxide, kAlAlloy}) {
        double worst_j = 0.0, worst_theta = 0.0, worst_slide = 0.0;
        double worst_et = 0.0, worst_w = 0.0, worst_angle = 0.0;
        for (double deg = 5.0; deg <= 85.0 + 1e-9; deg += step) {
          const double th = deg * units::kDegree;
          const double v_t = speed * std::sin(th), v_n = speed * std::cos(th);
          const ObliqueOutcome o =
              oblique_case(engine, nm, mu, e, BodyInit{radius, Vec3(v_t, 0, -v_n), Vec3::Zero()}, std::nullopt);
          const double e_t = o.after[0].velocity.x() / v_t;
          const double e_t_ref = o.ref.tangential_velocity_after / v_t;
          const double w = o.after[0].angular_velocity.y();
          const double w_ref = o.ref.spin_a_after;
          // Rebound angle of the contact point: atan(v_c' / v_n') [deg] (Chung & Ooi's fig. 10).
          const double angle = std::atan2(o.slip_after, o.after[0].velocity.z()) / units::kDegree;
          const double angle_ref = std::atan2(o.ref.slip_velocity_after, o.ref.normal_velocity_after) / units::kDegree;
          if (o.impulse_error > worst_j) { worst_j = o.impulse_error; worst_theta = deg; }
          worst_et = std::max(worst_et, std::abs(e_t - e_t_ref));
          worst_w = std::max(worst_w, std::abs(w - w_ref) * radius / speed);
          worst_angle = std::max(worst_angle, std::abs(angle - angle_ref));
          // Gross sliding throughout (rigid-body limit, Maw et al. 1976): tan(theta) >= 3.5 mu (1 + e).
          if (std::tan(th) >= 3.5 * mu * (1.0 + e)) {
            const double j_slide = mu * o.problem.a.mass * (1.0 + e) * v_n;  // mu J_n [N s]
            worst_slide = std::max(worst_slide, std::abs(-o.j_t - j_slide) / j_slide);
          }
          if (engine == ctx.engines.front())
            data.push_back({double(mi), deg, e_t, e_t_ref, w, w_ref, angle, angle_ref});
        }
        const std::string where = std::string("test 4 ") + nm.name;
        rows.push_back(compare_le(where + ": max |J_t - J_t,ref|/(mu J_n) (at " + sci(worst_theta) + " deg)", engine,
                                  worst_j, kImpulseTolerance, "", kImpulseSource));
        // mu J_n / (m v_t) = mu (1 + e) / tan(theta) <= 2.1 (at 5 deg): e_t errs by <= 2.1 x the impulse's.
        rows.push_back(compare_le(where + ": max |e_t - e_t,ref| (tangential restitution)", engine, worst_et,
                                  2.1 * kImpulseTolerance, "", "= (J_t error)/(m v_t) <= mu(1+e)/tan 5deg x 2e-3 mu J_n"));
        // R dw = (5/2) J_t / m and mu J_n / (m v) <= mu (1 + e) = 0.18.
        rows.push_back(compare_le(where + ": max |omega' - omega'_ref| R / v", engine, worst_w,
                                  2.5 * 0.18 * kImpulseTolerance, "", "= 2.5 (J_t error)/(m v) <= 2.5 x 0.18 x 2e-3"));
        // The slip velocity moves by 3.5 (J_t error)/m <= 3.5 x 2e-3 x mu (1 + e) v_n = 1.3e-3 v_n;
        // atan(u/v_n') with v_n' = e v_n moves by at most that over e v_n: 1.3e-3 rad = 0.074 deg.
        rows.push_back(compare_le(where + ": max |rebound angle - ref| [deg]", engine, worst_angle, 0.1, "deg",
                                  "3.5 (J_t error)/m over v_n' = e v_n: <= 0.074 deg"));
        rows.push_back(compare_le(where + ": sliding (tan theta >= 3.5 mu (1+e)): max |J_t/(mu m (1+e) v_n) - 1|",
                                  engine, worst_slide, kSlidingTolerance, "",
                                  "Coulomb impulse, rigid-body limit (Maw et al. 1976); 0.5%: initial stick"));
        ++mi;
      }
    }
    const std::string csv = csv_path(ctx, "t4.csv");
    write_csv(csv, {"material", "theta", "e_t", "e_t_ref", "omega", "omega_ref", "angle", "angle_ref"}, data);
    run_plot(ctx, "oblique", csv, "validation_chung_ooi_t4.png", {"Al oxide", "Al alloy"});
    return rows;
  };
  return g;
}

/// Shared body of tests 5-8: for each incidence x, `make_case(x)` gives the bodies; the
/// normalised recoil Psi2 and the impulse are compared with the two-body solution, and with the
/// rigid-body sliding limit where it applies. Psi = 4 G* u / (mu E* v_n) for slip u.
struct PsiCase {
  BodyInit a;
  std::optional<BodyInit> b;
};
template <class MakeCase>
std::vector<CheckRow> psi_rows(const CheckContext& ctx, const std::string& where, const NamedMaterial& nm, double mu,
                               double e, const std::vector<double>& xs, MakeCase make_case,
                               std::vector<std::vector<double>>& data, double test_id, double material_id) {
  std::vector<CheckRow> rows;
  const double slide = 2.0 * chi(nm) * (1.0 + e);  // Psi1 - Psi2 when sliding throughout
  for (const auto& engine : ctx.engines) {
    double worst_j = 0.0, worst_psi = 0.0, at = 0.0, worst_slide = 0.0, max_turn = 0.0, slide_at = 0.0;
    double ref_slide = 0.0;  // the reference's own |J_t/(mu m* (1+e) v_n) - 1| there
    for (double x : xs) {
      const PsiCase c = make_case(x);
      const ObliqueOutcome o = oblique_case(engine, nm, mu, e, c.a, c.b);
      const double kappa = 4.0 * o.problem.g_star / (o.problem.e_star * mu * o.problem.v_n);  // Psi per m/s
      const double u0 = o.problem.v_t - o.problem.a.radius * o.problem.spin_a - o.problem.b.radius * o.problem.spin_b;
      const double psi1 = kappa * u0, psi2 = kappa * o.slip_after, psi2_ref = kappa * o.ref.slip_velocity_after;
      max_turn = std::max(max_turn, o.normal_rotation / mu);
      if (o.impulse_error > worst_j) { worst_j = o.impulse_error; at = psi1; }
      worst_psi = std::max(worst_psi, std::abs(psi2 - psi2_ref));
      if (psi1 >= slide) {  // J_t = mu J_n, J_n = m* (1 + e) v_n [N s] (see kSlidingTolerance)
        const double m_eff = o.problem.plane ? o.problem.a.mass
                                             : o.problem.a.mass * o.problem.b.mass / (o.problem.a.mass + o.problem.b.mass);
        const double j_slide = mu * m_eff * (1.0 + e) * o.problem.v_n;
        const double err = std::abs(std::abs(o.j_t) - j_slide) / j_slide;
        const double ref = std::abs(std::abs(o.ref.tangential_impulse) - j_slide) / j_slide;
        if (slide_at == 0.0 || err - ref > worst_slide - ref_slide) {  // the point closest to failing
          worst_slide = err;
          slide_at = psi1;
          ref_slide = ref;
        }
      }
      if (engine == ctx.engines.front()) data.push_back({test_id, material_id, psi1, psi2, psi2_ref, slide});
    }
    const std::string turn =
        max_turn > 1e-6 ? " + line-of-centres rotation phi/mu <= " + sci(max_turn) : "";
    rows.push_back(compare_le(where + ": max |J_t - J_t,ref|/(mu J_n) (at Psi1=" + sci(at) + ")", engine, worst_j,
                              kImpulseTolerance + max_turn, "", std::string(kImpulseSource) + turn));
    // u moves by J_t/m_t = 3.5 J_t/m*; Psi2 per mu J_n: kappa 3.5 mu (1+e) v_n = slide: same relative error.
    rows.push_back(compare_le(where + ": max |Psi2 - Psi2,ref| / (2chi(1+e))", engine, worst_psi / slide,
                              kImpulseTolerance + max_turn, "",
                              std::string("Psi2 moves by 2chi(1+e) per mu J_n of impulse: as the impulse") + turn));
    // Reported at the point where it exceeds the two-body solution's own deviation the most.
    rows.push_back(compare_le(where + ": sliding Psi1 >= 2chi(1+e): |J_t/(mu m* (1+e) v_n) - 1| (at Psi1=" +
                                  sci(slide_at) + ", sliding from " + sci(slide) + ")",
                              engine, worst_slide, kSlidingTolerance + ref_slide + max_turn, "",
                              "Maw, Barber & Fawcett 1976 sliding branch; 0.5% as test 4 + the law's initial-stick "
                              "deficit there (two-body solution: " + sci(ref_slide) + ")" + turn));
  }
  return rows;
}

CheckGroup test5_to_8() {
  CheckGroup g;
  g.name = "Chung & Ooi tests 5-8: oblique and spinning impacts vs two-body Hertz-Mindlin solution";
  g.in_quick = true;
  g.plots = {"validation_chung_ooi_t5_t8.png"};
  g.run = [](const CheckContext& ctx) {
    std::vector<CheckRow> rows;
    std::vector<std::vector<double>> data;  // test, material, psi1, psi2, psi2_ref, slide
    std::vector<std::vector<double>> spin;  // material, omega, omega_a', omega_b', v_t' (test 7)
    std::vector<std::string> labels;        // "test:material:name" for the plot
    auto add = [&rows](std::vector<CheckRow> r) { rows.insert(rows.end(), r.begin(), r.end()); };
    // Test 5: sphere on a rigid plane, R 10 um, v_n 5 m/s, tangential velocity v_t = x mu v_n
    // for x up to 14 (Chung & Ooi's abscissa v_t/(mu v_n)), mu 0.3, e 1.
    {
      const double radius = 1e-5, v_n = 5.0, mu = 0.3, e = 1.0;
      int mi = 0;
      for (const auto& nm : {kSteel, kPolyethylene}) {
        auto make = [&](double x) {
          return PsiCase{BodyInit{radius, Vec3(x * mu * v_n, 0, -v_n), Vec3::Zero()}, std::nullopt};
        };
        add(psi_rows(ctx, std::string("test 5 ") + nm.name + " (v_n 5 m/s, varied v_t)", nm, mu, e,
                     sweep(14.0, ctx.quick), make, data, 5, mi));
        labels.push_back("5:" + std::to_string(mi++) + ":" + nm.name);
      }
    }
    // Test 6: sphere (R 0.1 m) on a rigid plane at v_n 0.2 m/s with initial spin only, the
    // contact point's speed |v_c| = x v_n for x up to 11 (Kratos: incidence up to 85 deg),
    // mu 0.4, e 0.5.
    {
      const double radius = 0.10, v_n = 0.2, mu = 0.4, e = 0.5;
      int mi = 0;
      for (const auto& nm : {kAlAlloy, kNylon}) {
        auto make = [&](double x) {
          return PsiCase{BodyInit{radius, Vec3(0, 0, -v_n), Vec3(0, -x * v_n / radius, 0)}, std::nullopt};
        };
        add(psi_rows(ctx, std::string("test 6 ") + nm.name + " sphere-plane with spin", nm, mu, e,
                     sweep(11.0, ctx.quick), make, data, 6, mi));
        labels.push_back("6:" + std::to_string(mi++) + ":" + nm.name);
      }
    }
    // Test 7: two identical spheres (R 0.1 m) at +-0.2 m/s with spins w and -w about the same
    // axis, w = 0.175 ... 22 rad/s (Kratos benchmark 7, PySPH test 7). Their contact points then
    // move together: no slip, so no tangential force -- the spins must come out unchanged and
    // the centres with no tangential velocity, exactly (mirror symmetry), and the normal rebound
    // at e. Then, to exercise friction with the same inputs, spins w and +w (slip 2 w R).
    {
      const double radius = 0.10, v = 0.2, mu = 0.4, e = 0.5;
      const std::vector<double> omegas = ctx.quick ? std::vector<double>{0.175, 0.5, 2.0, 5.0, 12.0, 22.0}
                                                   : std::vector<double>{0.175, 0.2, 0.3, 0.5, 0.7, 0.9, 1.3, 2.0,
                                                                         3.0, 4.0, 5.0, 7.0, 9.0, 12.0, 22.0};
      int mi = 0;
      for (const auto& nm : {kAlAlloy, kCopper}) {
        for (const auto& engine : ctx.engines) {
          double worst_w = 0.0, worst_vt = 0.0, worst_e = 0.0;
          for (double w : omegas) {
            const ObliqueOutcome o = oblique_case(engine, nm, mu, e, BodyInit{radius, Vec3(0, 0, -v), Vec3(0, w, 0)},
                                                  BodyInit{radius, Vec3(0, 0, v), Vec3(0, -w, 0)});
            const Particles& q = o.after;
            worst_w = std::max({worst_w, std::abs(q[0].angular_velocity.y() - w) / w,
                                std::abs(q[1].angular_velocity.y() + w) / w});
            worst_vt = std::max({worst_vt, std::abs(q[0].velocity.x()) / v, std::abs(q[1].velocity.x()) / v});
            worst_e = std::max(worst_e, std::abs((q[0].velocity.z() - q[1].velocity.z()) / (2.0 * v) - e));
            if (engine == ctx.engines.front())
              spin.push_back({double(mi), w, q[0].angular_velocity.y(), -q[1].angular_velocity.y(), q[0].velocity.x()});
          }
          const std::string where = std::string("test 7 ") + nm.name + " spins +-w (no slip)";
          rows.push_back(compare_le(where + ": max |w' - w|/w", engine, worst_w, 1e-12, "",
                                    "mirror symmetry: the contact points' velocities cancel exactly; round-off"));
          rows.push_back(compare_le(where + ": max |v_t'|/v", engine, worst_vt, 1e-12, "",
                                    "no tangential force (as above); round-off"));
          rows.push_back(compare_le(where + ": max |e_out - e|", engine, worst_e, 1e-4, "",
                                    "normal restitution: alpha(e) + Verlet, as test 3"));
        }
        auto make = [&](double x) {
          const double w = x * 2.0 * v / (2.0 * radius);  // slip 2 w R = x v_n, v_n = 2 v
          return PsiCase{BodyInit{radius, Vec3(0, 0, -v), Vec3(0, -w, 0)},
                         BodyInit{radius, Vec3(0, 0, v), Vec3(0, -w, 0)}};
        };
        add(psi_rows(ctx, std::string("test 7 ") + nm.name + " spins +w +w (slip 2wR)", nm, mu, e,
                     sweep(11.0, ctx.quick), make, data, 7, mi));
        labels.push_back("7:" + std::to_string(mi++) + ":" + nm.name);
      }
    }
    // Test 8: sphere A (R 0.1 m) with spin hits sphere B (R 0.5 m, at rest) at 0.2 m/s, the
    // contact point's speed x v_n for x up to 11, mu 0.4, e 0.5.
    {
      const double ra = 0.10, rb = 0.50, v_n = 0.2, mu = 0.4, e = 0.5;
      int mi = 0;
      for (const auto& nm : {kAlAlloy, kNylon}) {
        auto make = [&](double x) {
          return PsiCase{BodyInit{ra, Vec3(0, 0, -v_n), Vec3(0, -x * v_n / ra, 0)},
                         BodyInit{rb, Vec3::Zero(), Vec3::Zero()}};
        };
        add(psi_rows(ctx, std::string("test 8 ") + nm.name + " R 0.1 m on R 0.5 m", nm, mu, e,
                     sweep(11.0, ctx.quick), make, data, 8, mi));
        labels.push_back("8:" + std::to_string(mi++) + ":" + nm.name);
        // The large sphere's recoil: its spin and normal velocity follow from (J_n, J_t).
        for (const auto& engine : ctx.engines) {
          const ObliqueOutcome o = oblique_case(engine, nm, mu, e, make(2.0).a, make(2.0).b);
          const double mb = o.problem.b.mass;
          rows.push_back(compare_abs("test 8 " + std::string(nm.name) + ": large sphere's spin w_B' (x = 2)", engine,
                                     o.after[1].angular_velocity.y(), o.ref.spin_b_after,
                                     kImpulseTolerance * mu * o.ref.normal_impulse * rb / o.problem.b.inertia, "rad/s",
                                     "I_B dw_B = -a_B J_t; 2e-3 mu J_n as the impulse"));
          rows.push_back(compare_rel("test 8 " + std::string(nm.name) + ": large sphere's recoil v_Bz' (x = 2)", engine,
                                     o.after[1].velocity.z(), -o.ref.normal_impulse / mb, 1e-4, "m/s",
                                     "J_n = m* (1 + e) v_n from the two-body solution; 1e-4 as tests 1-3"));
        }
      }
    }
    const std::string csv = csv_path(ctx, "t5_t8.csv");
    write_csv(csv, {"test", "material", "psi1", "psi2", "psi2_ref", "slide"}, data);
    const std::string spin_csv = csv_path(ctx, "t7_spin.csv");
    write_csv(spin_csv, {"material", "omega", "omega_a", "omega_b", "v_t"}, spin);
    labels.insert(labels.begin(), spin_csv);
    run_plot(ctx, "psi", csv, "validation_chung_ooi_t5_t8.png", labels);
    return rows;
  };
  return g;
}

}  // namespace

std::vector<CheckGroup> make_chung_ooi_checks() { return {test1_and_2(), test3(), test4(), test5_to_8()}; }

}  // namespace ppohdem::validation
