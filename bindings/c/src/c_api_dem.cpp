// The C API's DEM scenes and engines (ppohdem.h "DEM scenes and engines"): a Scene from TOML
// or from arrays, the reference or fast engine, particle read-out, energies, checkpoints.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "c_api_handles.hpp"
#include "ppohdem/dem/checkpoint.hpp"
#include "ppohdem/dem/contact_law.hpp"
#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "ppohdem/geometry/motion_program.hpp"

using namespace ppohdem;
using namespace ppohdem::c_api;

namespace {

Vec3 vec_or_zero(const double* v) { return v == nullptr ? Vec3::Zero() : Vec3(v[0], v[1], v[2]); }

dem::Material material_of(double density, double young, double poisson, double restitution, double friction) {
  dem::Material m;
  m.density = density;
  m.young = young;
  m.poisson = poisson;
  m.restitution = restitution;
  m.friction = friction;
  dem::validate(m, true, "material");
  return m;
}

const dem::DemEngine& engine_of(const ppohdem_engine* e) {
  const ppohdem_engine& h = require(e, "engine");
  if (!h.engine) throw StateError("the engine handle holds no engine");
  return *h.engine;
}

dem::DemEngine& engine_of(ppohdem_engine* e) {
  ppohdem_engine& h = require(e, "engine");
  if (!h.engine) throw StateError("the engine handle holds no engine");
  return *h.engine;
}

/// segments[k] of the C struct as a MotionSegment (the types and fields of ppohdem.h).
MotionSegment segment_of(const ppohdem_motion_segment& c, std::size_t k) {
  const std::string where = "segments[" + std::to_string(k) + "]";
  const Vec3 velocity(c.velocity[0], c.velocity[1], c.velocity[2]);
  auto unit_axis = [&] {
    const Vec3 axis(c.axis[0], c.axis[1], c.axis[2]);
    if (!(axis.norm() > 0.0) || !std::isfinite(axis.norm())) throw ArgumentError(where + ".axis: expected a non-zero finite vector");
    return Vec3(axis.normalized());
  };
  auto oscillation = [&](MotionPart& part) {
    if (!(c.frequency > 0.0) || !std::isfinite(c.frequency)) throw ArgumentError(where + ".frequency: expected a finite number > 0 [Hz]");
    part.profile = MotionProfile::sine;
    part.angular_frequency = 2.0 * std::numbers::pi * c.frequency;
    part.phase = c.phase;
  };
  MotionSegment seg;
  seg.start = c.start;
  const bool has_point = c.has_point != 0;
  switch (c.type) {
    case PPOHDEM_MOTION_REST:
      break;
    case PPOHDEM_MOTION_TRANSLATE:
      seg.translation = {MotionProfile::linear, velocity};
      break;
    case PPOHDEM_MOTION_TRANSLATE_ROTATE:
      seg.translation = {MotionProfile::linear, velocity};
      [[fallthrough]];
    case PPOHDEM_MOTION_ROTATE:
      seg.rotation = {MotionProfile::linear, unit_axis() * c.omega};
      if (has_point) seg.point = Vec3(c.point[0], c.point[1], c.point[2]);
      break;
    case PPOHDEM_MOTION_VIBRATE_TRANSLATE:
      seg.translation.vector = Vec3(c.amplitude[0], c.amplitude[1], c.amplitude[2]);
      oscillation(seg.translation);
      break;
    case PPOHDEM_MOTION_VIBRATE_ROTATE:
      seg.rotation.vector = unit_axis() * c.amplitude[0];
      oscillation(seg.rotation);
      if (has_point) seg.point = Vec3(c.point[0], c.point[1], c.point[2]);
      break;
    default:
      throw ArgumentError(where + ".type: expected a ppohdem_motion_type (0 to 5), got " + std::to_string(c.type));
  }
  return seg;
}

}  // namespace

extern "C" {

ppohdem_status ppohdem_scene_read_toml(const char* path, ppohdem_scene** scene) {
  return guarded(__func__, [&] {
    require(scene, "scene") = nullptr;
    auto handle = std::make_unique<ppohdem_scene>();
    handle->scene = dem::read_scene(require_text(path, "path"));
    *scene = handle.release();
  });
}

ppohdem_status ppohdem_scene_create(double dt, const double gravity[3], double density, double young,
                                    double poisson, double restitution, double friction, ppohdem_scene** scene) {
  return guarded(__func__, [&] {
    require(scene, "scene") = nullptr;
    if (!(dt > 0.0) || !std::isfinite(dt)) throw ArgumentError("dt must be finite and > 0");
    auto handle = std::make_unique<ppohdem_scene>();
    dem::SimulationSetup& s = handle->scene.setup;
    s.dt = dt;
    s.gravity = vec_or_zero(gravity);
    s.material = material_of(density, young, poisson, restitution, friction);
    s.law = dem::HertzMindlin::from_material(s.material);
    s.source = "C API scene";
    *scene = handle.release();
  });
}

ppohdem_status ppohdem_scene_add_material(ppohdem_scene* scene, double density, double young, double poisson,
                                          double restitution, double friction, int32_t* index) {
  return guarded(__func__, [&] {
    dem::SimulationSetup& s = require(scene, "scene").scene.setup;
    if (s.material_count() >= dem::kMaxMaterials) throw ArgumentError("a scene holds at most 64 materials");
    s.more_materials.push_back(material_of(density, young, poisson, restitution, friction));
    if (!s.material_names.empty()) s.material_names.push_back("material" + std::to_string(s.material_count() - 1));
    if (index != nullptr) *index = static_cast<int32_t>(s.material_count() - 1);
  });
}

ppohdem_status ppohdem_scene_add_particles(ppohdem_scene* scene, size_t count, const int64_t* ids,
                                           const double* positions, const double* velocities, const double* radius,
                                           const int32_t* material) {
  return guarded(__func__, [&] {
    dem::SimulationSetup& s = require(scene, "scene").scene.setup;
    require(positions, "positions");
    require(radius, "radius");
    std::int64_t next_id = 1;
    for (const dem::Particle& p : s.particles) next_id = std::max(next_id, p.id + 1);
    for (std::size_t n = 0; n < count; ++n) {
      dem::Particle p;
      p.id = ids != nullptr ? ids[n] : next_id++;
      p.position = Vec3(positions[3 * n], positions[3 * n + 1], positions[3 * n + 2]);
      p.velocity = velocities == nullptr ? Vec3::Zero() : Vec3(velocities[3 * n], velocities[3 * n + 1], velocities[3 * n + 2]);
      if (!(radius[n] > 0.0)) throw ArgumentError("radius[" + std::to_string(n) + "] must be > 0");
      p.radius = radius[n];
      const int32_t m = material == nullptr ? 0 : material[n];
      if (m < 0 || static_cast<std::size_t>(m) >= s.material_count()) {
        throw ArgumentError("material[" + std::to_string(n) + "] = " + std::to_string(m) + ": the scene has " +
                            std::to_string(s.material_count()) + " materials");
      }
      p.material = static_cast<std::uint16_t>(m);
      s.particles.push_back(p);
    }
  });
}

ppohdem_status ppohdem_scene_add_wall(ppohdem_scene* scene, const double point[3], const double normal[3],
                                      const double velocity[3]) {
  return guarded(__func__, [&] {
    dem::SimulationSetup& s = require(scene, "scene").scene.setup;
    s.boundaries.push_back(std::make_shared<dem::PlaneWall>((require(point, "point"), vec_or_zero(point)),
                                                            (require(normal, "normal"), vec_or_zero(normal)),
                                                            vec_or_zero(velocity)));
  });
}

ppohdem_status ppohdem_scene_add_object(ppohdem_scene* scene, const ppohdem_field* field, const char* name,
                                        const double velocity[3], const double angular_velocity[3],
                                        const double centroid[3]) {
  return guarded(__func__, [&] {
    dem::Scene& sc = require(scene, "scene").scene;
    const ppohdem_field& f = require(field, "field");
    RigidMotion motion;
    motion.velocity = vec_or_zero(velocity);
    motion.angular_velocity = vec_or_zero(angular_velocity);
    motion.centroid = vec_or_zero(centroid);
    auto object = std::make_shared<const dem::DistanceFieldObject>(f.field, motion, name == nullptr ? "object" : name);
    sc.objects.push_back({object, sc.setup.boundaries.size()});
    sc.setup.boundaries.push_back(object);
  });
}

ppohdem_status ppohdem_scene_add_object_program(ppohdem_scene* scene, const ppohdem_field* field, const char* name,
                                                const double centroid[3], const ppohdem_motion_segment* segments,
                                                size_t segment_count) {
  return guarded(__func__, [&] {
    dem::Scene& sc = require(scene, "scene").scene;
    const ppohdem_field& f = require(field, "field");
    if (segment_count == 0) throw ArgumentError("segment_count: expected at least one segment");
    require(segments, "segments");
    std::vector<MotionSegment> program;
    for (std::size_t k = 0; k < segment_count; ++k) {
      program.push_back(segment_of(segments[k], k));
      if (k > 0 && !(program[k].start > program[k - 1].start)) {
        throw ArgumentError("segments[" + std::to_string(k) + "].start: expected a time after the previous segment's start");
      }
    }
    MotionProgram motion = [&] {
      try {
        return MotionProgram(std::move(program), vec_or_zero(centroid));
      } catch (const std::invalid_argument& e) {  // a non-finite start or vector
        throw ArgumentError(e.what());
      }
    }();
    auto object = std::make_shared<const dem::DistanceFieldObject>(f.field, std::move(motion), name == nullptr ? "object" : name);
    sc.objects.push_back({object, sc.setup.boundaries.size()});
    sc.setup.boundaries.push_back(object);
  });
}

ppohdem_status ppohdem_scene_particle_count(const ppohdem_scene* scene, size_t* count) {
  return guarded(__func__, [&] { require(count, "count") = require(scene, "scene").scene.setup.particles.size(); });
}

ppohdem_status ppohdem_scene_steps(const ppohdem_scene* scene, long* steps) {
  return guarded(__func__, [&] { require(steps, "steps") = require(scene, "scene").scene.steps; });
}

ppohdem_status ppohdem_scene_destroy(ppohdem_scene* scene) {
  delete scene;
  return PPOHDEM_OK;
}

ppohdem_status ppohdem_engine_create(const ppohdem_scene* scene, const char* engine_name, ppohdem_engine** engine) {
  return guarded(__func__, [&] {
    require(engine, "engine") = nullptr;
    const dem::Scene& sc = require(scene, "scene").scene;
    const std::string name = engine_name == nullptr ? "reference" : engine_name;
    auto handle = std::make_unique<ppohdem_engine>();
    if (name == "reference") {
      handle->engine = dem::reference::ReferenceEngine::make(sc.setup);
    } else if (name == "fast") {
      handle->engine = dem::fast::FastEngine::make(sc.setup);
    } else {
      throw ArgumentError("engine_name: expected \"reference\" or \"fast\", got \"" + name + "\"");
    }
    handle->scene_source = sc.setup.source;
    *engine = handle.release();
  });
}

ppohdem_status ppohdem_engine_destroy(ppohdem_engine* engine) {
  delete engine;
  return PPOHDEM_OK;
}

ppohdem_status ppohdem_engine_step(ppohdem_engine* engine) {
  return guarded(__func__, [&] { engine_of(engine).step(); });
}

ppohdem_status ppohdem_engine_advance(ppohdem_engine* engine, long steps) {
  return guarded(__func__, [&] {
    dem::DemEngine& e = engine_of(engine);
    if (steps < 0) throw ArgumentError("steps must be >= 0, got " + std::to_string(steps));
    e.advance(steps);
  });
}

ppohdem_status ppohdem_engine_step_count(const ppohdem_engine* engine, long* steps) {
  return guarded(__func__, [&] { require(steps, "steps") = engine_of(engine).step_count(); });
}

ppohdem_status ppohdem_engine_time(const ppohdem_engine* engine, double* time) {
  return guarded(__func__, [&] { require(time, "time") = engine_of(engine).time(); });
}

ppohdem_status ppohdem_engine_particle_count(const ppohdem_engine* engine, size_t* count) {
  return guarded(__func__, [&] { require(count, "count") = engine_of(engine).particles().size(); });
}

ppohdem_status ppohdem_engine_read(const ppohdem_engine* engine, ppohdem_quantity quantity, double* out,
                                   size_t count) {
  return guarded(__func__, [&] {
    const dem::Particles& ps = engine_of(engine).particles();
    require(out, "out");
    if (quantity < PPOHDEM_POSITION || quantity > PPOHDEM_TORQUE) {
      throw ArgumentError("quantity: expected PPOHDEM_POSITION .. PPOHDEM_TORQUE, got " + std::to_string(quantity));
    }
    require_capacity(count, ps.size(), "out (count)");
    for (std::size_t n = 0; n < ps.size(); ++n) {
      const dem::Particle& p = ps[n];
      const Vec3& v = quantity == PPOHDEM_POSITION         ? p.position
                      : quantity == PPOHDEM_VELOCITY       ? p.velocity
                      : quantity == PPOHDEM_ANGULAR_VELOCITY ? p.angular_velocity
                      : quantity == PPOHDEM_FORCE          ? p.force
                                                           : p.torque;
      for (int a = 0; a < 3; ++a) out[3 * n + static_cast<std::size_t>(a)] = v[a];
    }
  });
}

ppohdem_status ppohdem_engine_read_ids(const ppohdem_engine* engine, int64_t* ids, size_t count) {
  return guarded(__func__, [&] {
    const dem::Particles& ps = engine_of(engine).particles();
    require(ids, "ids");
    require_capacity(count, ps.size(), "ids (count)");
    for (std::size_t n = 0; n < ps.size(); ++n) ids[n] = ps[n].id;
  });
}

ppohdem_status ppohdem_engine_energies(const ppohdem_engine* engine, ppohdem_energies* energies) {
  return guarded(__func__, [&] {
    ppohdem_energies& out = require(energies, "energies");
    const dem::Energies e = engine_of(engine).energies();
    out = {e.kinetic, e.rotational, e.gravitational, e.elastic, e.dissipated, e.boundary_work, e.total()};
  });
}

ppohdem_status ppohdem_engine_checkpoint(const ppohdem_engine* engine, const char* path) {
  return guarded(__func__, [&] {
    const dem::DemEngine& e = engine_of(engine);
    dem::Checkpoint cp;
    cp.engine = e.save_state();
    cp.scene = engine->scene_source;
    dem::write_checkpoint(require_text(path, "path"), cp);
  });
}

ppohdem_status ppohdem_engine_restart(ppohdem_engine* engine, const char* path) {
  return guarded(__func__, [&] {
    dem::DemEngine& e = engine_of(engine);
    const dem::Checkpoint cp = dem::read_checkpoint(require_text(path, "path"));
    e.restore_state(cp.engine);
  });
}

}  // extern "C"
