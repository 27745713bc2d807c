// The C API's ppohDEM-1.0 DEM stages (ppohdem.h "ppohDEM-1.0 library stages"): the original
// sample program's library (ppohDEM_pre, ppohDEM_check_update, ppohDEM_integrate_system,
// ppohDEM_dataout, ppohDEM_check_objects) for the Fortran module ppohDEM_util (DEM).
// Physics "ppohdem-1.0" is reference/compat's transcription (bit for bit the original);
// "corrected" runs ppohdem's reference engine on the same sample (docs/compat.md section 2).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "c_api_guard.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"
#include "ppohdem/dem/legacy_scene.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "ppohdem/io/atomic_file.hpp"

using namespace ppohdem;
using namespace ppohdem::c_api;
namespace fs = std::filesystem;
using Constants = compat::Ppohdem10DemConstants;

struct ppohdem_legacy_dem {
  fs::path work_dir;
  std::unique_ptr<compat::Ppohdem10Dem> compat;  // physics "ppohdem-1.0"
  std::unique_ptr<dem::DemEngine> corrected;     // physics "corrected"
  long itime = 0;                                // corrected: steps done
  double rtime = 0.0;                            // corrected: sum of dt
  int file_index = 0;                            // corrected: frames written
  bool sorted = false;                           // update_index has run
};

namespace {

ppohdem_legacy_dem& dem_of(ppohdem_legacy_dem* d) { return require(d, "dem"); }

void write_text(const fs::path& path, const std::string& text) {
  AtomicFileWriter out(path);
  out.stream() << text;
  out.commit();
}

std::string frame_name(const char* prefix, int frame, const char* suffix) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s%03d%s", prefix, frame, suffix);  // the original's i3.3
  return buf;
}

void require_sorted(const ppohdem_legacy_dem& d, const char* stage) {
  if (!d.sorted) throw StateError(std::string(stage) + " needs ppohDEM_update_index first");
}

// The data length for the corrected scene: h_window = Lx / (Obj_n - 1) and the data's node
// count from distance_0000.dat's header (read_legacy_scene checks that the two spacings agree).
double data_length_of(const fs::path& work_dir, const UpdateParamsInput& params) {
  std::ifstream in(work_dir / "distance_0000.dat");
  int nx = 0;
  if (!(in >> nx) || nx < 2) throw InputError((work_dir / "distance_0000.dat").string(), 1, "expected gridX gridY gridZ nprocs");
  return params.domain_length.x() / (params.window_nodes[0] - 1) * nx;
}

}  // namespace

extern "C" {

ppohdem_status ppohdem_legacy_read_parameters(const char* params_file, ppohdem_legacy_parameters* parameters) {
  return guarded(__func__, [&] {
    ppohdem_legacy_parameters& p = require(parameters, "parameters");
    const UpdateParamsInput in = read_update_params_input(require_text(params_file, "params_file"));
    // ppohDEM_setparameters: the file's values plus the hard-coded ones (float-rounded, Q9).
    p = {};
    p.tstep = Constants::kTimeStep;
    p.tfin = in.time_finish;
    p.dstep = static_cast<int32_t>(Constants::kStepsPerFrame);
    p.pnum = Constants::kParticles;
    for (int a = 0; a < 3; ++a) {
      p.length[a] = in.domain_length[a];
      p.cells[a] = Constants::kCellsPerAxis;
      p.obj_n[a] = in.window_nodes[static_cast<std::size_t>(a)];
      p.winstart[a] = in.window_start[static_cast<std::size_t>(a)];
      p.obj_velocity[a] = in.velocity[a];
      p.obj_omega[a] = in.rotation_axis[a];
      p.centroid[a] = in.centroid[a];
    }
    p.obj_omega[3] = in.omega_pi_rad_per_w;
    p.pi = Constants::kPi;
    p.radius = Constants::kRadius;
    p.mass = Constants::kMass;
    p.im = Constants::kInertia;
    p.kn = Constants::kNormalStiffness;
    p.kt = Constants::kTangentialStiffness;
    p.en = Constants::kNormalDamping;
    p.et = Constants::kTangentialDamping;
    p.fric_const = Constants::kFriction;
    p.gravity = Constants::kGravity;
    p.obj_kn = Constants::kObjectStiffness;
    p.obj_en = Constants::kObjectDamping;
    p.size_contact_list = Constants::kContactListSize;
    p.size_contact_list_wall = Constants::kWallContactListSize;
  });
}

ppohdem_status ppohdem_legacy_dem_create(const char* params_file, const char* work_dir, const char* physics,
                                         size_t count, const double* positions, const double* radius,
                                         ppohdem_legacy_dem** dem) {
  return guarded(__func__, [&] {
    require(dem, "dem") = nullptr;
    require(params_file, "params_file");
    require(positions, "positions");
    require(radius, "radius");
    if (count == 0) throw ArgumentError("count is 0: the sample needs particles");
    const std::string mode = physics == nullptr ? "ppohdem-1.0" : physics;
    auto handle = std::make_unique<ppohdem_legacy_dem>();
    handle->work_dir = work_dir == nullptr ? fs::path(".") : fs::path(work_dir);
    if (mode == "ppohdem-1.0") {
      compat::Ppohdem10DemInput input =
          compat::read_ppohdem10_dem_input(params_file, handle->work_dir, std::nullopt);
      input.initial = {};
      input.initial.particles.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        compat::Ppohdem10ParticleRecord& r = input.initial.particles[i];
        r.id = static_cast<int>(i + 1);
        r.pos = {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
        r.radius = radius[i];
      }
      handle->compat = std::make_unique<compat::Ppohdem10Dem>(input, /*sort_by_cell=*/false);
      // ppohDEM_prepare_objects_fromfile writes the initial field (the data grid's corner).
      write_text(handle->work_dir / "objects_distance.csv", handle->compat->object_field_csv());
    } else if (mode == "corrected") {
      const UpdateParamsInput params = read_update_params_input(params_file);
      dem::LegacySceneOptions options;
      if (!fs::exists(fs::path(params_file).parent_path() / "input_constants_voxelizer.dat")) {
        options.data_length = data_length_of(handle->work_dir, params);
      }
      dem::Scene scene = dem::read_legacy_scene(params_file, options);
      scene.setup.particles.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        dem::Particle& p = scene.setup.particles[i];
        p = dem::Particle{};
        p.id = static_cast<std::int64_t>(i + 1);
        p.position = Vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        p.radius = radius[i];
      }
      handle->corrected = dem::reference::ReferenceEngine::make(scene.setup);
    } else {
      throw ArgumentError("physics: expected \"ppohdem-1.0\" or \"corrected\", got \"" + mode + "\"");
    }
    *dem = handle.release();
  });
}

ppohdem_status ppohdem_legacy_dem_destroy(ppohdem_legacy_dem* dem) {
  delete dem;
  return PPOHDEM_OK;
}

ppohdem_status ppohdem_legacy_dem_update_index(ppohdem_legacy_dem* dem) {
  return guarded(__func__, [&] {
    ppohdem_legacy_dem& d = dem_of(dem);
    if (d.compat) d.compat->update_index();
    d.sorted = true;
  });
}

ppohdem_status ppohdem_legacy_dem_check_update(ppohdem_legacy_dem* dem, int32_t* done) {
  return guarded(__func__, [&] {
    ppohdem_legacy_dem& d = dem_of(dem);
    require_sorted(d, "ppohDEM_check_update");
    const bool resorted = d.compat ? d.compat->check_update() : false;  // the engine keeps its own cells
    if (done != nullptr) *done = resorted ? 1 : 0;
  });
}

ppohdem_status ppohdem_legacy_dem_integrate(ppohdem_legacy_dem* dem) {
  return guarded(__func__, [&] {
    ppohdem_legacy_dem& d = dem_of(dem);
    require_sorted(d, "ppohDEM_integrate_system");
    if (d.compat) {
      d.compat->integrate_system();
    } else {
      d.corrected->step();
    }
  });
}

ppohdem_status ppohdem_legacy_dem_dataout(ppohdem_legacy_dem* dem, int32_t* done) {
  return guarded(__func__, [&] {
    ppohdem_legacy_dem& d = dem_of(dem);
    require_sorted(d, "ppohDEM_dataout");
    bool frame = false;
    std::string text;
    if (d.compat) {
      frame = d.compat->advance_counters();
      if (frame) text = d.compat->frame_text();
    } else {
      d.itime = d.itime + 1;
      d.rtime = d.rtime + Constants::kTimeStep;
      frame = d.itime % Constants::kStepsPerFrame == 0;
      if (frame) {
        d.file_index = d.file_index + 1;
        std::vector<compat::Rvec3> positions;
        std::vector<double> radius;
        for (const dem::Particle& p : d.corrected->particles()) {
          positions.push_back({p.position.x(), p.position.y(), p.position.z()});
          radius.push_back(p.radius);
        }
        text = compat::ppohdem10_frame_text(positions, radius);
      }
    }
    if (frame) {
      const int file_index = d.compat ? d.compat->counter().file_index : d.file_index;
      write_text(d.work_dir / "data" / frame_name("out", file_index, ".dat"), text);
    }
    if (done != nullptr) *done = frame ? 1 : 0;
  });
}

ppohdem_status ppohdem_legacy_dem_check_objects(ppohdem_legacy_dem* dem, int32_t* done) {
  return guarded(__func__, [&] {
    ppohdem_legacy_dem& d = dem_of(dem);
    require_sorted(d, "ppohDEM_check_objects");
    bool updated = false;
    // The corrected engine moves the object continuously; it has no per-frame field to write.
    if (d.compat && d.compat->check_objects()) {
      updated = true;
      const int f = d.compat->counter().file_index;
      write_text(d.work_dir / "distance" / frame_name("objects_distance", f, ".csv"), d.compat->object_field_csv());
      write_text(d.work_dir / "obj" / frame_name("obj", f, ".pov"), d.compat->object_pov());
    }
    if (done != nullptr) *done = updated ? 1 : 0;
  });
}

ppohdem_status ppohdem_legacy_dem_counter(const ppohdem_legacy_dem* dem, int64_t* itime, double* rtime,
                                          int32_t* file_index, double* pos_accum) {
  return guarded(__func__, [&] {
    const ppohdem_legacy_dem& d = require(dem, "dem");
    if (d.compat) {
      const compat::Ppohdem10Counter& c = d.compat->counter();
      if (itime != nullptr) *itime = c.itime;
      if (rtime != nullptr) *rtime = c.rtime;
      if (file_index != nullptr) *file_index = c.file_index;
      if (pos_accum != nullptr) *pos_accum = c.pos_accum;
    } else {
      if (itime != nullptr) *itime = d.itime;
      if (rtime != nullptr) *rtime = d.rtime;
      if (file_index != nullptr) *file_index = d.file_index;
      if (pos_accum != nullptr) *pos_accum = 0.0;
    }
  });
}

ppohdem_status ppohdem_legacy_dem_max_radius(const ppohdem_legacy_dem* dem, double* max_radius) {
  return guarded(__func__, [&] {
    const ppohdem_legacy_dem& d = require(dem, "dem");
    double r = 0.0;
    if (d.compat) {
      for (const double x : d.compat->particles().radius) r = std::max(r, x);
    } else {
      for (const dem::Particle& p : d.corrected->particles()) r = std::max(r, p.radius);
    }
    require(max_radius, "max_radius") = r;
  });
}

ppohdem_status ppohdem_legacy_dem_particles(const ppohdem_legacy_dem* dem, double* positions, double* velocities,
                                            double* angular_velocities, double* radius, size_t count) {
  return guarded(__func__, [&] {
    const ppohdem_legacy_dem& d = require(dem, "dem");
    auto put = [](double* out, std::size_t i, double x, double y, double z) {
      if (out == nullptr) return;
      out[3 * i] = x;
      out[3 * i + 1] = y;
      out[3 * i + 2] = z;
    };
    if (d.compat) {
      const compat::Ppohdem10Particles& p = d.compat->particles();
      require_capacity(count, p.size(), "count");
      for (std::size_t i = 0; i < p.size(); ++i) {
        put(positions, i, p.pos[i].x, p.pos[i].y, p.pos[i].z);
        put(velocities, i, p.vel[i].x, p.vel[i].y, p.vel[i].z);
        put(angular_velocities, i, p.omega[i].x, p.omega[i].y, p.omega[i].z);
        if (radius != nullptr) radius[i] = p.radius[i];
      }
    } else {
      const dem::Particles& ps = d.corrected->particles();
      require_capacity(count, ps.size(), "count");
      for (std::size_t i = 0; i < ps.size(); ++i) {
        put(positions, i, ps[i].position.x(), ps[i].position.y(), ps[i].position.z());
        put(velocities, i, ps[i].velocity.x(), ps[i].velocity.y(), ps[i].velocity.z());
        put(angular_velocities, i, ps[i].angular_velocity.x(), ps[i].angular_velocity.y(), ps[i].angular_velocity.z());
        if (radius != nullptr) radius[i] = ps[i].radius;
      }
    }
  });
}

ppohdem_status ppohdem_legacy_dem_write_state(const ppohdem_legacy_dem* dem, const char* path) {
  return guarded(__func__, [&] {
    const ppohdem_legacy_dem& d = require(dem, "dem");
    require(path, "path");
    if (!d.compat) throw StateError("the full-precision state dump exists for physics ppohdem-1.0 only");
    write_text(path, compat::format_ppohdem10_state(d.compat->state()));
  });
}

}  // extern "C"
