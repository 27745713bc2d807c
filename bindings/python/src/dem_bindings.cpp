// Scenes and engines (docs/python.md "Scenes and engines"). Particle arrays are strided views
// into the engine's particles() (construction order), refreshed in place by run().
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

#include "common.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/particle_compare.hpp"
#include "ppohdem/dem/reference/cell_list.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"
#include "ppohdem/dem/run.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::python {
namespace {

namespace fs = std::filesystem;
using dem::Particle;
using dem::Particles;

struct PyScene {
  std::shared_ptr<dem::Scene> scene;
};

struct PyEngine {
  std::shared_ptr<const dem::Scene> scene;  // its objects' fields are the engine's boundaries
  std::unique_ptr<dem::DemEngine> engine;
  int threads = 0;  // OpenMP threads for run() (0: the process default)
};

// The particle columns of the CSV format (particle_csv.hpp) as arrays; vx..wz default to 0.
Particles particles_from_columns(const py::dict& columns) {
  auto column = [&](const char* name, bool required) -> std::optional<py::array_t<double, py::array::forcecast>> {
    if (!columns.contains(name)) {
      if (required) throw InputError(std::string("Scene.from_dict: [particles] has arrays but no '") + name + "' column");
      return std::nullopt;
    }
    return py::array_t<double, py::array::forcecast>::ensure(columns[name]);
  };
  const auto ids = py::array_t<std::int64_t, py::array::forcecast>::ensure(columns["id"]);
  if (!ids || ids.ndim() != 1) throw InputError("Scene.from_dict: particles column 'id' must be a 1-d integer array");
  const std::size_t n = static_cast<std::size_t>(ids.shape(0));
  Particles p(n);
  for (std::size_t k = 0; k < n; ++k) p[k].id = ids.at(static_cast<py::ssize_t>(k));
  struct Target {
    const char* name;
    bool required;
    std::function<double&(Particle&)> field;
  };
  const std::vector<Target> targets = {
      {"x", true, [](Particle& q) -> double& { return q.position.x(); }},
      {"y", true, [](Particle& q) -> double& { return q.position.y(); }},
      {"z", true, [](Particle& q) -> double& { return q.position.z(); }},
      {"vx", false, [](Particle& q) -> double& { return q.velocity.x(); }},
      {"vy", false, [](Particle& q) -> double& { return q.velocity.y(); }},
      {"vz", false, [](Particle& q) -> double& { return q.velocity.z(); }},
      {"wx", false, [](Particle& q) -> double& { return q.angular_velocity.x(); }},
      {"wy", false, [](Particle& q) -> double& { return q.angular_velocity.y(); }},
      {"wz", false, [](Particle& q) -> double& { return q.angular_velocity.z(); }},
      {"radius", true, [](Particle& q) -> double& { return q.radius; }}};
  for (const Target& t : targets) {
    const auto a = column(t.name, t.required);
    if (!a) continue;
    if (a->ndim() != 1 || static_cast<std::size_t>(a->shape(0)) != n) {
      throw InputError(std::string("Scene.from_dict: particles column '") + t.name + "' must be a 1-d array of " +
                       std::to_string(n) + " values (as many as 'id')");
    }
    for (std::size_t k = 0; k < n; ++k) t.field(p[k]) = a->at(static_cast<py::ssize_t>(k));
  }
  if (columns.contains("material")) {
    const auto m = py::array_t<std::int64_t, py::array::forcecast>::ensure(columns["material"]);
    if (!m || m.ndim() != 1 || static_cast<std::size_t>(m.shape(0)) != n) {
      throw InputError("Scene.from_dict: particles column 'material' must hold " + std::to_string(n) +
                       " material indices or names");
    }
    for (std::size_t k = 0; k < n; ++k) {
      const std::int64_t index = m.at(static_cast<py::ssize_t>(k));
      if (index < 0 || index > 65535) throw InputError("Scene.from_dict: material index out of range");
      p[k].material = static_cast<std::uint16_t>(index);
    }
  }
  return p;
}

std::unique_ptr<dem::DemEngine> make_engine(const std::string& name, const dem::SimulationSetup& setup) {
  if (name == "fast" || name == "optimized") return std::make_unique<dem::fast::FastEngine>(setup);
  if (name == "reference") return std::make_unique<dem::reference::ReferenceEngine>(setup);
  throw InputError("Engine: engine must be \"fast\" or \"reference\", got \"" + name + "\"");
}

// Runs `body` with `threads` OpenMP threads in this thread, then restores the count.
template <class F>
void with_threads(int threads, F&& body) {
#ifdef PPOHDEM_WITH_OPENMP
  const int before = omp_get_max_threads();
  if (threads > 0) omp_set_num_threads(threads);
  try {
    body();
  } catch (...) {
    omp_set_num_threads(before);
    throw;
  }
  omp_set_num_threads(before);
#else
  (void)threads;
  body();
#endif
}

// A (N,3) float64 view of one Vec3 member of every particle.
py::array vec3_view(const PyEngine& e, const Vec3 Particle::*member, py::handle owner) {
  const Particles& p = e.engine->particles();
  const double* first = p.empty() ? nullptr : (p.front().*member).data();
  return readonly_view<double>(first, {static_cast<py::ssize_t>(p.size()), 3},
                               {static_cast<py::ssize_t>(sizeof(Particle)), sizeof(double)}, owner);
}

py::dict energies_dict(const dem::DemEngine& e) {
  const dem::Energies en = e.energies();
  py::dict d;  // the columns of energy.csv (output_writers.hpp), in that order
  d["step"] = e.step_count();
  d["time"] = e.time();
  d["kinetic"] = en.kinetic;
  d["rotational"] = en.rotational;
  d["gravitational"] = en.gravitational;
  d["elastic"] = en.elastic;
  d["dissipated"] = en.dissipated;
  d["boundary_work"] = en.boundary_work;
  return d;
}

}  // namespace

void bind_dem(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A DEM scene (the TOML scene format, scene.hpp)")
      .def_static(
          "from_toml", [](const fs::path& file) { return PyScene{std::make_shared<dem::Scene>(dem::read_scene(file))}; },
          py::arg("path"), "Read a TOML scene; relative paths in it resolve against the file's directory")
      .def_static(
          "_from_text",
          [](std::string text, const std::string& name, const fs::path& base_dir, std::optional<py::dict> columns) {
            std::optional<Particles> particles;
            if (columns) particles = particles_from_columns(*columns);
            return PyScene{std::make_shared<dem::Scene>(
                dem::read_scene_text(std::move(text), name, base_dir, std::move(particles)))};
          },
          py::arg("text"), py::arg("name"), py::arg("base_dir"), py::arg("columns") = py::none())
      .def_property(
          "steps", [](const PyScene& s) { return s.scene->steps; },
          [](PyScene& s, long steps) {
            if (steps < 0) throw InputError("Scene.steps must be >= 0");
            s.scene->steps = steps;
          },
          "[simulation] steps")
      .def_property_readonly("dt", [](const PyScene& s) { return s.scene->setup.dt; }, "[simulation] dt [s]")
      .def_property_readonly("particle_count", [](const PyScene& s) { return s.scene->setup.particles.size(); })
      .def_property_readonly("boundary_count", [](const PyScene& s) { return s.scene->setup.boundaries.size(); })
      .def_property_readonly("object_count", [](const PyScene& s) { return s.scene->objects.size(); })
      .def_property_readonly("output_dir", [](const PyScene& s) { return s.scene->output.dir; })
      .def_property_readonly("source", [](const PyScene& s) { return s.scene->setup.source; })
      .def("__repr__", [](const PyScene& s) {
        return "<ppohdem.Scene " + s.scene->setup.source + ": " + std::to_string(s.scene->setup.particles.size()) +
               " particles, " + std::to_string(s.scene->setup.boundaries.size()) + " boundaries, dt " +
               std::to_string(s.scene->setup.dt) + " s>";
      });

  py::class_<PyEngine>(m, "Engine", "A DEM engine stepping a scene (engine.hpp)")
      .def(py::init([](const PyScene& scene, const std::string& engine, int threads) {
             if (threads < 0) throw InputError("Engine: threads must be >= 0 (0: the OpenMP default)");
             auto e = std::make_unique<PyEngine>();
             e->scene = scene.scene;
             e->threads = threads;
             with_threads(threads, [&] { e->engine = make_engine(engine, scene.scene->setup); });
             e->engine->particles();  // assembled once, so the first views see the initial state
             return e;
           }),
           py::arg("scene"), py::arg("engine") = "fast", py::arg("threads") = 0)
      .def(
          "run",
          [](PyEngine& e, long steps) {
            if (steps < 0) throw InputError("Engine.run: steps must be >= 0");
            // Blocks of steps without the GIL; Ctrl-C is honoured between blocks.
            const long block = 1000;
            for (long done = 0; done < steps;) {
              const long n = std::min(block, steps - done);
              {
                py::gil_scoped_release release;
                with_threads(e.threads, [&] {
                  e.engine->advance(n);
                  e.engine->particles();  // refresh the arrays the views point into
                });
              }
              done += n;
              if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            }
          },
          py::arg("steps"), "Advance by `steps` time steps (in C++, without the GIL)")
      .def(
          "run_scene",
          [](PyEngine& e, bool progress) {
            // As `ppohdem simulate`: to the scene's last step, writing its [output] files.
            dem::Scene scene = *e.scene;
            scene.output.progress = progress;
            const std::string header = provenance_line(1, e.threads) + "; engine " + e.engine->name();
            std::ostringstream log;
            dem::RunSummary s;
            {
              py::gil_scoped_release release;
              with_threads(e.threads, [&] {
                s = dem::run_scene(*e.engine, scene, header, log);
                e.engine->particles();
              });
            }
            py::dict d;
            d["steps"] = s.steps;
            d["wall_seconds"] = s.wall_seconds;
            d["frames"] = s.frames;
            d["escaped"] = s.escaped;
            d["inserted"] = s.inserted;            // [[insert]] (docs/objects.md "Particle insertion")
            d["insert_failed"] = s.insert_failed;
            d["output_dir"] = scene.output.dir;
            d["log"] = log.str();
            return d;
          },
          py::arg("progress") = false,
          "Run to the scene's last step writing final.csv, energy.csv and frames into its [output] dir, as "
          "`ppohdem simulate`")
      .def_property_readonly("name", [](const PyEngine& e) { return e.engine->name(); })
      .def_property_readonly("threads", [](const PyEngine& e) { return e.threads; })
      .def_property_readonly("dt", [](const PyEngine& e) { return e.scene->setup.dt; })
      .def_property_readonly("step_count", [](const PyEngine& e) { return e.engine->step_count(); })
      .def_property_readonly("time", [](const PyEngine& e) { return e.engine->time(); })
      .def_property_readonly("escaped_count", [](const PyEngine& e) { return e.engine->escaped_count(); })
      .def("__len__", [](const PyEngine& e) { return e.engine->particles().size(); })
      .def_property_readonly("positions", [](py::object self) {
        return vec3_view(self.cast<const PyEngine&>(), &Particle::position, self);
      })
      .def_property_readonly("velocities", [](py::object self) {
        return vec3_view(self.cast<const PyEngine&>(), &Particle::velocity, self);
      })
      .def_property_readonly("angular_velocities", [](py::object self) {
        return vec3_view(self.cast<const PyEngine&>(), &Particle::angular_velocity, self);
      })
      .def_property_readonly("forces", [](py::object self) {
        return vec3_view(self.cast<const PyEngine&>(), &Particle::force, self);
      })
      .def_property_readonly("torques", [](py::object self) {
        return vec3_view(self.cast<const PyEngine&>(), &Particle::torque, self);
      })
      .def_property_readonly("ids", [](py::object self) {
        const Particles& p = self.cast<const PyEngine&>().engine->particles();
        return readonly_view<std::int64_t>(p.empty() ? nullptr : &p.front().id, {static_cast<py::ssize_t>(p.size())},
                                           {static_cast<py::ssize_t>(sizeof(Particle))}, self);
      })
      .def_property_readonly("radii", [](py::object self) {
        const Particles& p = self.cast<const PyEngine&>().engine->particles();
        return readonly_view<double>(p.empty() ? nullptr : &p.front().radius, {static_cast<py::ssize_t>(p.size())},
                                     {static_cast<py::ssize_t>(sizeof(Particle))}, self);
      })
      .def("energies", [](const PyEngine& e) { return energies_dict(*e.engine); },
           "The energy.csv columns now: step, time, kinetic, ..., boundary_work [J]")
      .def("contact_counts", [](const PyEngine& e) {
        const dem::ContactCounts c = e.engine->contact_counts();
        py::dict d;
        d["particle_pairs"] = c.particle_pairs;
        d["particle_boundary"] = c.particle_boundary;
        return d;
      })
      .def(
          "touching_pairs",
          [](const PyEngine& e, const std::string& method) {
            const Particles& p = e.engine->particles();
            std::vector<std::pair<std::size_t, std::size_t>> pairs;
            {
              py::gil_scoped_release release;
              if (method == "cells") pairs = dem::reference::touching_pairs(p);
              else if (method == "brute_force") pairs = dem::reference::touching_pairs_brute_force(p);
              else throw InputError("touching_pairs: method must be \"cells\" or \"brute_force\", got \"" + method + "\"");
            }
            py::array_t<std::int64_t> out({static_cast<py::ssize_t>(pairs.size()), py::ssize_t{2}});
            auto w = out.mutable_unchecked<2>();
            for (std::size_t k = 0; k < pairs.size(); ++k) {
              w(static_cast<py::ssize_t>(k), 0) = static_cast<std::int64_t>(pairs[k].first);
              w(static_cast<py::ssize_t>(k), 1) = static_cast<std::int64_t>(pairs[k].second);
            }
            return out;
          },
          py::arg("method") = "cells",
          "Index pairs (a, b) of overlapping particles, by the reference cell list or by all pairs")
      .def("__repr__", [](const PyEngine& e) {
        return "<ppohdem.Engine " + e.engine->name() + ": " + std::to_string(e.engine->particles().size()) +
               " particles, step " + std::to_string(e.engine->step_count()) + ">";
      });

  m.def(
      "compare",
      [](const PyEngine& a, const PyEngine& b) {
        if (a.engine->step_count() != b.engine->step_count()) {
          throw InputError("compare: the engines are at different steps (" + std::to_string(a.engine->step_count()) +
                           " and " + std::to_string(b.engine->step_count()) + ")");
        }
        const dem::ParticleDifference d = dem::compare_particles(a.engine->particles(), b.engine->particles());
        py::dict out;  // keyed like the Engine's arrays
        out["positions"] = d.max_position;
        out["velocities"] = d.max_velocity;
        out["angular_velocities"] = d.max_angular_velocity;
        out["forces"] = d.max_force;
        out["torques"] = d.max_torque;
        out["radii"] = d.max_radius;
        out["bitwise"] = d.bitwise;
        return out;
      },
      py::arg("a"), py::arg("b"), "Max |difference| per particle array of two engines, and whether all bits agree");
}

}  // namespace ppohdem::python
