// Scene reader (TOML via toml++, a private dependency of ppohdem_core: no toml++ type
// appears in a public header).
#include "ppohdem/dem/scene.hpp"

#include "toml_hardened.hpp"  // toml++, safe on malformed input (see there)

#include <cmath>
#include <cstring>
#include <cstdio>
#include <algorithm>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <optional>
#include <string_view>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/dem/particle_csv.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/dem/particle_generator.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem {
namespace {

namespace fs = std::filesystem;

/// Every particle's radius in file order, on every rank: of a shared setup, gathered (the
/// mean radius a linear law's collision time needs: summed in file order, the same bits as
/// on one rank).
std::vector<double> all_radii(const SimulationSetup& s) {
  std::vector<double> radii;
  if (!s.shared()) {
    for (const Particle& p : s.particles) radii.push_back(p.radius);
    return radii;
  }
  Bytes mine(s.particles.size() * sizeof(double));
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    std::memcpy(mine.data() + i * sizeof(double), &s.particles[i].radius, sizeof(double));
  }
  for (const Bytes& b : s.share.comm->allgather(mine)) {  // in rank order: file order
    const std::size_t at = radii.size();
    radii.resize(at + b.size() / sizeof(double));
    if (!b.empty()) std::memcpy(radii.data() + at, b.data(), b.size());
  }
  return radii;
}

class SceneParser {
 public:
  explicit SceneParser(fs::path file, const Comm* comm = nullptr)
      : file_(std::move(file)), name_(file_.string()), base_dir_(file_.parent_path()), comm_(comm) {}
  /// A scene given as text (read_scene_text): `name` stands for the file in messages.
  SceneParser(std::string text, std::string name, fs::path base_dir, std::optional<Particles> particles)
      : name_(std::move(name)), base_dir_(std::move(base_dir)), text_(std::move(text)),
        given_particles_(std::move(particles)) {}

  Scene parse() {
    toml::table root = parse_toml();
    check_keys(root, "", {"simulation", "material", "material_pair", "contact", "particles", "wall", "object", "insert",
                          "output", "checks", "parallel"});
    Scene scene;
    SimulationSetup& s = scene.setup;
    s.source = name_;

    const toml::table& sim = require_table(root, "simulation");
    check_keys(sim, "simulation", {"dt", "steps", "gravity", "energy_balance"});
    s.dt = require_number(sim, "simulation", "dt");
    scene.steps = require_integer(sim, "simulation", "steps");
    if (scene.steps < 0) fail(sim.get("steps"), "[simulation] steps must be >= 0");
    s.gravity = optional_vec3(sim, "simulation", "gravity").value_or(Vec3::Zero());
    s.energy_balance = optional_bool(sim, "simulation", "energy_balance").value_or(true);

    const toml::table& contact = require_table(root, "contact");
    check_keys(contact, "contact", {"model", "stiffness", "collision_time", "tangential_stiffness_ratio", "rolling",
                                    "characteristic_velocity", "tangential_damping"});
    const std::string model = require_string(contact, "contact", "model");
    if (contact.contains("rolling")) {
      const std::string rolling = require_string(contact, "contact", "rolling");
      if (rolling == "cdt") s.rolling = RollingModel::kCdt;
      else if (rolling == "epsd2") s.rolling = RollingModel::kEpsd2;
      else if (rolling != "none") fail(contact.get("rolling"), "[contact] rolling: expected \"none\", \"cdt\" or \"epsd2\", found \"" + rolling + "\"");
    }
    read_materials(root, model == "hertz-mindlin" || model == "hooke", s);
    if (given_particles_) {
      read_given_particles(root, s);
    } else if (root.contains("particles") || !root.contains("insert")) {
      read_particles(require_table(root, "particles"), s);
    }  // else: a scene that starts empty and fills by [[insert]]
    if (const toml::node* inserts = root.get("insert")) {
      const toml::array* list = inserts->as_array();
      if (!list) fail(inserts, "[[insert]] must be an array of tables");
      for (const toml::node& item : *list) {
        const toml::table* t = item.as_table();
        if (!t) fail(&item, "[[insert]] entries must be tables");
        scene.inserts.push_back(read_insert(*t, s, scene.inserts.size()));
      }
      s.insert_probes = insert_size_probes(scene.inserts);
    }

    if (model == "hertz-mindlin") {
      validate(s.material, true, name_);
      for (const char* key : {"stiffness", "collision_time", "tangential_stiffness_ratio", "characteristic_velocity"}) {
        if (contact.contains(key)) fail(contact.get(key), std::string("[contact] ") + key + " does not apply to model = \"hertz-mindlin\"");
      }
      s.law = HertzMindlin::from_material(s.material);
    } else if (model == "hooke") {
      validate(s.material, true, name_);
      for (const char* key : {"stiffness", "collision_time"}) {
        if (contact.contains(key)) fail(contact.get(key), std::string("[contact] ") + key + " does not apply to model = \"hooke\" (its k_n comes from E, nu and characteristic_velocity)");
      }
      const double v_c = require_number(contact, "contact", "characteristic_velocity");
      if (!(v_c > 0.0) || !std::isfinite(v_c)) fail(contact.get("characteristic_velocity"), "[contact] characteristic_velocity must be > 0 m/s");
      const double ratio = optional_number(contact, "contact", "tangential_stiffness_ratio").value_or(1.0);
      if (!(ratio >= 0.0) || !std::isfinite(ratio)) fail(contact.get("tangential_stiffness_ratio"), "[contact] tangential_stiffness_ratio must be >= 0");
      s.law = LinearSpringDashpot::hooke(s.material.effective_young(), v_c, s.material.restitution, s.material.friction, ratio);
    } else if (model == "linear") {
      if (contact.contains("characteristic_velocity")) fail(contact.get("characteristic_velocity"), "[contact] characteristic_velocity applies to model = \"hooke\" only");
      validate(s.material, false, name_);
      const auto k_n = optional_number(contact, "contact", "stiffness");
      const auto t_c = optional_number(contact, "contact", "collision_time");
      const double ratio = optional_number(contact, "contact", "tangential_stiffness_ratio").value_or(2.0 / 7.0);
      if (k_n.has_value() == t_c.has_value()) {
        fail(&contact, "[contact] model = \"linear\" needs exactly one of stiffness [N/m] or collision_time [s]");
      }
      if (k_n) {
        s.law = LinearSpringDashpot::from_stiffness(*k_n, s.material.restitution, s.material.friction, ratio);
      } else {
        // Reference pair: two particles of the mean radius (of the first material), m* = m(R_mean)/2.
        const std::vector<double> radii = all_radii(s);
        double r_sum = 0.0;
        for (const double r : radii) r_sum += r;
        double r_mean = radii.empty() ? 1.0 : r_sum / static_cast<double>(radii.size());
        if (radii.empty() && !scene.inserts.empty()) r_mean = mean_insert_radius(scene.inserts);  // a fill
        s.law = LinearSpringDashpot::from_collision_time(*t_c, s.material.mass(r_mean) / 2.0,
                                                         s.material.restitution, s.material.friction, ratio);
      }
    } else {
      fail(contact.get("model"), "[contact] model: expected \"hertz-mindlin\", \"linear\" or \"hooke\", found \"" + model + "\"");
    }
    // Tangential dashpot: LIGGGHTS' default for hooke; off for the others (their scenes are
    // unchanged bit for bit).
    const bool damping = optional_bool(contact, "contact", "tangential_damping").value_or(model == "hooke");
    std::visit([&](auto& law) { law.set_tangential_damping(damping); }, s.law);

    if (const toml::node* walls = root.get("wall")) {
      const toml::array* list = walls->as_array();
      if (!list) fail(walls, "[[wall]] must be an array of tables");
      for (const toml::node& w : *list) {
        const toml::table* t = w.as_table();
        if (!t) fail(&w, "[[wall]] entries must be tables");
        check_keys(*t, "wall", {"point", "normal", "velocity", "material"});
        set_boundary_material(*t, "wall", s.boundaries.size(), s);
        const Vec3 point = *require_vec3(*t, "wall", "point");
        const Vec3 normal = *require_vec3(*t, "wall", "normal");
        const Vec3 velocity = optional_vec3(*t, "wall", "velocity").value_or(Vec3::Zero());
        if (!(normal.norm() > 0.0)) fail(t->get("normal"), "[[wall]] normal must not be zero");
        s.boundaries.push_back(std::make_shared<PlaneWall>(point, normal, velocity));
      }
    }

    if (const toml::node* objects = root.get("object")) {
      const toml::array* list = objects->as_array();
      if (!list) fail(objects, "[[object]] must be an array of tables");
      for (const toml::node& o : *list) {
        const toml::table* t = o.as_table();
        if (!t) fail(&o, "[[object]] entries must be tables");
        set_boundary_material(*t, "object", s.boundaries.size(), s);
        scene.objects.push_back({read_object(*t, s, scene.objects.size()), s.boundaries.size()});
        s.boundaries.push_back(scene.objects.back().object);
      }
    }

    if (const toml::node* out_node = root.get("output")) {
      const toml::table* out = out_node->as_table();
      if (!out) fail(out_node, "[output] must be a table");
      check_keys(*out, "output", {"dir", "every", "formats", "progress", "loads_every", "loads_average"});
      scene.output.dir = relative_to_scene(require_string(*out, "output", "dir"));
      scene.output.every = optional_integer(*out, "output", "every").value_or(0);
      if (scene.output.every < 0) fail(out->get("every"), "[output] every must be >= 0");
      scene.output.progress = optional_bool(*out, "output", "progress").value_or(true);
      scene.output.loads_every = optional_integer(*out, "output", "loads_every").value_or(0);
      if (scene.output.loads_every < 0) fail(out->get("loads_every"), "[output] loads_every must be >= 0");
      scene.output.loads_average = optional_bool(*out, "output", "loads_average").value_or(false);
      if (scene.output.loads_average && scene.output.loads_every == 0) {
        fail(out->get("loads_average"), "[output] loads_average needs loads_every = N (steps) > 0");
      }
      if (const toml::node* f = out->get("formats")) {
        const toml::array* formats = f->as_array();
        if (!formats) fail(f, "[output] formats: expected an array of strings");
        for (const toml::node& item : *formats) {
          const auto name = item.value<std::string>();
          if (name == "csv") scene.output.csv = true;
          else if (name == "vtk") scene.output.vtk = true;
          else if (name == "pov") scene.output.pov = true;
          else if (name == "vtu") scene.output.vtu = true;
          else fail(&item, "[output] formats: expected \"csv\", \"vtk\", \"vtu\" or \"pov\", found " + name.value_or("a non-string"));
        }
      }
    } else {
      scene.output.dir = relative_to_scene("out");
    }

    if (const toml::node* parallel_node = root.get("parallel")) {  // docs/dem.md "Load balance"
      const toml::table* parallel = parallel_node->as_table();
      if (!parallel) fail(parallel_node, "[parallel] must be a table");
      check_keys(*parallel, "parallel", {"balance", "balance_threshold"});
      if (parallel->contains("balance")) {
        const std::string balance = require_string(*parallel, "parallel", "balance");
        if (balance != "rcb" && balance != "off") {
          fail(parallel->get("balance"), "[parallel] balance: expected \"rcb\" or \"off\", found \"" + balance + "\"");
        }
        scene.parallel.balance = balance == "rcb";
      }
      const auto threshold = optional_number(*parallel, "parallel", "balance_threshold");
      if (threshold && !(*threshold >= 1.0)) {
        fail(parallel->get("balance_threshold"), "[parallel] balance_threshold: expected a number >= 1 (max/mean particles per rank)");
      }
      scene.parallel.balance_threshold = threshold.value_or(scene.parallel.balance_threshold);
    }

    if (const toml::node* checks_node = root.get("checks")) {  // run_diagnostics.hpp
      const toml::table* checks = checks_node->as_table();
      if (!checks) fail(checks_node, "[checks] must be a table");
      check_keys(*checks, "checks", {"max_overlap", "max_energy_growth", "stop_on_escape", "domain_min", "domain_max"});
      RunChecks& c = scene.checks;
      c.max_overlap = optional_number(*checks, "checks", "max_overlap").value_or(c.max_overlap);
      if (!(c.max_overlap > 0.0)) fail(checks->get("max_overlap"), "[checks] max_overlap: expected > 0 (a fraction of the radius)");
      c.max_energy_growth = optional_number(*checks, "checks", "max_energy_growth").value_or(c.max_energy_growth);
      if (!(c.max_energy_growth > 0.0)) fail(checks->get("max_energy_growth"), "[checks] max_energy_growth: expected > 0");
      c.stop_on_escape = optional_bool(*checks, "checks", "stop_on_escape").value_or(c.stop_on_escape);
      c.domain_min = optional_vec3(*checks, "checks", "domain_min");
      c.domain_max = optional_vec3(*checks, "checks", "domain_max");
      if (c.domain_min.has_value() != c.domain_max.has_value() ||
          (c.domain_min && !(c.domain_min->array() < c.domain_max->array()).all())) {
        fail(checks, "[checks] domain_min and domain_max: expected both, with domain_min < domain_max");
      }
    }
    return scene;
  }

 private:
  /// The file parsed by toml++, after the guards of toml_hardened.hpp: non-ASCII bytes are
  /// refused outside comments, and a toml++ precondition failure becomes an InputError.
  toml::table parse_toml() const {
    const std::string text = text_ ? *text_ : read_file_bytes(file_);
    const detail::NonAsciiByte bad = detail::first_non_ascii_outside_comments(text);
    if (bad.line != 0) {
      char byte[8];
      std::snprintf(byte, sizeof byte, "0x%02X", bad.byte);
      std::string what = "non-ASCII byte ";
      what.append(byte).append(" at column ").append(std::to_string(bad.column))
          .append(": scene files must be ASCII outside comments (keys, values, strings and file names)");
      throw InputError(name_, bad.line, what);
    }
    try {
      return toml::parse(text, name_);
    } catch (const toml::parse_error& e) {
      throw InputError(name_, e.source().begin.line, std::string(e.description()));
    } catch (const detail::TomlInvariantViolation& e) {
      throw InputError(name_, line_of_invariant_violation(text), e.what());
    }
  }

  /// toml++ gives no position with a precondition failure: find the first line at which the
  /// text up to and including that line fails the same way (error path only; scenes are small).
  std::size_t line_of_invariant_violation(std::string_view text) const {
    std::size_t line = 0;
    for (std::size_t end = 0; end < text.size(); ++end) {
      if (text[end] != '\n' && end + 1 != text.size()) continue;
      ++line;
      try {
        (void)toml::parse(text.substr(0, end + 1), name_);
      } catch (const detail::TomlInvariantViolation&) {
        return line;
      } catch (const toml::parse_error&) {
        // an incomplete prefix may be malformed in an ordinary way: keep going
      }
    }
    return 0;
  }

  [[noreturn]] void fail(const toml::node* node, const std::string& what) const {
    throw InputError(name_, node ? static_cast<std::size_t>(node->source().begin.line) : 0, what);
  }

  void check_keys(const toml::table& t, std::string_view table, std::initializer_list<std::string_view> allowed) const {
    for (const auto& [key, node] : t) {
      bool known = false;
      for (std::string_view a : allowed) known = known || key.str() == a;
      if (!known) {
        std::string list;
        for (std::string_view a : allowed) {
          if (!list.empty()) list += ", ";
          list += a;
        }
        std::string where = "top level";
        if (!table.empty()) {
          where = "[";
          where += table;
          where += "]";
        }
        fail(&node, "unknown key '" + std::string(key.str()) + "' in " + where + " (expected one of: " + list + ")");
      }
    }
  }

  const toml::table& require_table(const toml::table& root, const char* key) const {
    const toml::node* n = root.get(key);
    if (!n) throw InputError(name_, 0, std::string("missing table [") + key + "]");
    if (!n->is_table()) fail(n, std::string("[") + key + "] must be a table");
    return *n->as_table();
  }

  /// A TOML number as a double. toml++'s value<double>() is empty for an integer that a double
  /// does not hold exactly (|i| > 2^53, e.g. 9223372036854775807: fuzz_scene_toml, finding 7 of
  /// docs/reliability.md), so integers are converted here to the nearest double and left to the
  /// callers' range checks. Callers have checked is_number().
  static double number_value(const toml::node& n) {
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    return n.as_floating_point()->get();
  }

  std::optional<double> optional_number(const toml::table& t, const char* table, const char* key) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_number()) fail(n, std::string("[") + table + "] " + key + ": expected a number");
    const double v = number_value(*n);
    if (!std::isfinite(v)) fail(n, std::string("[") + table + "] " + key + ": expected a finite number");
    return v;
  }
  double require_number(const toml::table& t, const char* table, const char* key) const {
    if (!t.contains(key)) fail(&t, std::string("[") + table + "] missing key '" + key + "'");
    return *optional_number(t, table, key);
  }
  std::optional<long> optional_integer(const toml::table& t, const char* table, const char* key) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_integer()) fail(n, std::string("[") + table + "] " + key + ": expected an integer");
    return static_cast<long>(n->value<std::int64_t>().value());
  }
  long require_integer(const toml::table& t, const char* table, const char* key) const {
    if (!t.contains(key)) fail(&t, std::string("[") + table + "] missing key '" + key + "'");
    return *optional_integer(t, table, key);
  }
  std::optional<bool> optional_bool(const toml::table& t, const char* table, const char* key) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_boolean()) fail(n, std::string("[") + table + "] " + key + ": expected true or false");
    return n->value<bool>().value();
  }
  std::string require_string(const toml::table& t, const char* table, const char* key) const {
    const toml::node* n = t.get(key);
    if (!n) fail(&t, std::string("[") + table + "] missing key '" + key + "'");
    if (!n->is_string()) fail(n, std::string("[") + table + "] " + key + ": expected a string");
    return n->value<std::string>().value();
  }
  std::optional<Vec3> optional_vec3(const toml::table& t, const char* table, const char* key) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3) fail(n, std::string("[") + table + "] " + key + ": expected an array of 3 numbers");
    Vec3 v;
    for (std::size_t i = 0; i < 3; ++i) {
      const toml::node& item = *a->get(i);
      if (!item.is_number()) fail(&item, std::string("[") + table + "] " + key + ": expected an array of 3 numbers");
      v[static_cast<Eigen::Index>(i)] = number_value(item);
    }
    if (!v.allFinite()) fail(n, std::string("[") + table + "] " + key + ": expected finite numbers");
    return v;
  }
  std::optional<Vec3> require_vec3(const toml::table& t, const char* table, const char* key) const {
    if (!t.contains(key)) fail(&t, std::string("[") + table + "] missing key '" + key + "'");
    return optional_vec3(t, table, key);
  }

  fs::path relative_to_scene(const std::string& path) const {
    const fs::path p(path);
    return p.is_absolute() ? p : base_dir_ / p;
  }

  // Particles given by the caller (read_scene_text): [particles] may hold allow_overlap only.
  void read_given_particles(const toml::table& root, SimulationSetup& s) const {
    if (const toml::node* n = root.get("particles")) {
      const toml::table* t = n->as_table();
      if (!t) fail(n, "[particles] must be a table");
      check_keys(*t, "particles (the particles are given as arrays)", {"allow_overlap"});
      s.allow_initial_overlap = optional_bool(*t, "particles", "allow_overlap").value_or(false);
    }
    s.particles = *given_particles_;
    for (const Particle& p : s.particles) {
      const std::size_t count = std::max<std::size_t>(1, s.material_names.size());
      if (p.material >= count) {
        throw InputError(name_, 0, "particle id " + std::to_string(p.id) + ": material index " +
                                       std::to_string(p.material) + " but the scene has " +
                                       std::to_string(count) + " material(s)");
      }
    }
  }

  void read_particles(const toml::table& t, SimulationSetup& s) const {
    check_keys(t, "particles", {"file", "generator", "box_min", "box_max", "count", "radius",
                                "radius_max", "seed", "velocity", "jitter", "allow_overlap", "material"});
    s.allow_initial_overlap = optional_bool(t, "particles", "allow_overlap").value_or(false);
    const bool has_file = t.contains("file");
    const bool has_generator = t.contains("generator");
    if (has_file == has_generator) fail(&t, "[particles] needs exactly one of file = \"...\" or generator = \"lattice\"|\"random\"");
    if (has_file) {
      for (const char* key : {"box_min", "box_max", "count", "radius", "radius_max", "seed", "velocity", "jitter", "material"}) {
        if (t.contains(key)) {
          fail(t.get(key), std::string("[particles] ") + key + " applies to a generator, not to file =" +
                               (std::string_view(key) == "material" ? " (the file's material column gives it)" : ""));
        }
      }
      const fs::path file = relative_to_scene(require_string(t, "particles", "file"));
      if (comm_ != nullptr) {
        SharedParticles mine = read_particles_csv(file, s.material_names, *comm_);
        s.particles = std::move(mine.particles);
        s.share = mine.share;
      } else {
        s.particles = read_particles_csv(file, s.material_names);
      }
      return;
    }
    GeneratorSpec spec;
    const std::string kind = require_string(t, "particles", "generator");
    if (kind == "lattice") spec.kind = GeneratorKind::kLattice;
    else if (kind == "random") spec.kind = GeneratorKind::kRandom;
    else fail(t.get("generator"), "[particles] generator: expected \"lattice\" or \"random\", found \"" + kind + "\"");
    spec.box_min = *require_vec3(t, "particles", "box_min");
    spec.box_max = *require_vec3(t, "particles", "box_max");
    spec.count = require_integer(t, "particles", "count");
    spec.radius = require_number(t, "particles", "radius");
    if (!(spec.radius > 0.0)) fail(t.get("radius"), "[particles] radius must be > 0 m");
    spec.radius_max = optional_number(t, "particles", "radius_max").value_or(spec.radius);
    if (spec.radius_max < spec.radius) fail(t.get("radius_max"), "[particles] radius_max must be >= radius");
    const long seed = optional_integer(t, "particles", "seed").value_or(1);
    spec.seed = static_cast<std::uint64_t>(seed);
    spec.velocity = optional_vec3(t, "particles", "velocity").value_or(Vec3::Zero());
    spec.jitter = optional_number(t, "particles", "jitter").value_or(0.0);
    if (spec.jitter < 0.0 || spec.jitter > 1.0) fail(t.get("jitter"), "[particles] jitter must be in [0, 1] (fraction of the radius)");
    s.particles = generate_particles(spec, name_);
    // material = "name" for every particle, or ["a", "b", ...]: id k gets entry (k - 1) mod n.
    if (const toml::node* m = t.get("material")) {
      std::vector<std::uint16_t> cycle;
      if (m->is_string()) {
        cycle.push_back(material_index(m, *m->value<std::string>(), s, "[particles] material"));
      } else if (const toml::array* list = m->as_array(); list && !list->empty()) {
        for (const toml::node& item : *list) {
          if (!item.is_string()) fail(&item, "[particles] material: expected a name or an array of names");
          cycle.push_back(material_index(&item, *item.value<std::string>(), s, "[particles] material"));
        }
      } else {
        fail(m, "[particles] material: expected a name or a non-empty array of names");
      }
      for (Particle& p : s.particles) {
        p.material = cycle[static_cast<std::size_t>(p.id - 1) % cycle.size()];
      }
    }
  }

  /// [material] (one material; optional name, default "default") or [[material]] entries
  /// (several, each with a unique name), and [[material_pair]] entries.
  void read_materials(const toml::table& root, bool elastic, SimulationSetup& s) const {
    const toml::node* node = root.get("material");
    if (!node) throw InputError(name_, 0, "missing table [material] (or [[material]] entries with names)");
    std::vector<const toml::table*> tables;
    const bool several = node->is_array();
    if (const toml::table* one = node->as_table()) {
      tables.push_back(one);
    } else if (const toml::array* list = node->as_array()) {
      if (list->empty()) fail(node, "[[material]]: expected at least one entry");
      for (const toml::node& item : *list) {
        if (!item.is_table()) fail(&item, "[[material]] entries must be tables");
        tables.push_back(item.as_table());
      }
    } else {
      fail(node, "[material] must be a table (or [[material]] an array of tables)");
    }
    if (tables.size() > kMaxMaterials) {
      fail(node, "[[material]]: " + std::to_string(tables.size()) + " entries, at most " +
                     std::to_string(kMaxMaterials) + " are supported");
    }
    for (const toml::table* t : tables) {
      check_keys(*t, "material", {"name", "density", "young", "poisson", "restitution", "friction", "rolling_friction"});
      std::string name = "default";
      if (several || t->contains("name")) {
        name = require_string(*t, "material", "name");
        if (name.empty() || name.find_first_of(",\"") != std::string::npos) {
          fail(t->get("name"), "[material] name: expected a non-empty name without ',' or '\"'");
        }
      }
      for (const std::string& other : s.material_names) {
        if (other == name) fail(t->get("name"), "[[material]] name '" + name + "' is used twice");
      }
      Material m;
      m.density = require_number(*t, "material", "density");
      m.young = optional_number(*t, "material", "young").value_or(0.0);
      m.poisson = optional_number(*t, "material", "poisson").value_or(0.0);
      m.restitution = require_number(*t, "material", "restitution");
      m.friction = optional_number(*t, "material", "friction").value_or(0.0);
      m.rolling_friction = optional_number(*t, "material", "rolling_friction").value_or(0.0);
      if (tables.size() > 1) {  // name the entry and its line (one material: checked with the model)
        try {
          validate(m, elastic, name_);
        } catch (const InputError& e) {
          fail(t, "[[material]] '" + name + "': " + e.message());
        }
      }
      if (s.material_names.empty()) s.material = m;
      else s.more_materials.push_back(m);
      s.material_names.push_back(name);
    }
    if (const toml::node* pairs = root.get("material_pair")) {
      const toml::array* list = pairs->as_array();
      if (!list) fail(pairs, "[[material_pair]] must be an array of tables");
      for (const toml::node& item : *list) {
        const toml::table* t = item.as_table();
        if (!t) fail(&item, "[[material_pair]] entries must be tables");
        check_keys(*t, "material_pair", {"materials", "restitution", "friction", "rolling_friction"});
        const toml::node* names = t->get("materials");
        const toml::array* two = names ? names->as_array() : nullptr;
        if (!two || two->size() != 2 || !two->get(0)->is_string() || !two->get(1)->is_string()) {
          fail(names ? names : t, "[[material_pair]] materials: expected two names, e.g. [\"glass\", \"steel\"]");
        }
        MaterialPairRule r;
        r.a = material_index(two->get(0), *two->get(0)->value<std::string>(), s, "[[material_pair]] materials");
        r.b = material_index(two->get(1), *two->get(1)->value<std::string>(), s, "[[material_pair]] materials");
        if (r.a == r.b) fail(names, "[[material_pair]] materials: two different materials expected (a material's own pair uses its own values)");
        for (const MaterialPairRule& o : s.material_pairs) {
          if ((o.a == r.a && o.b == r.b) || (o.a == r.b && o.b == r.a)) fail(names, "[[material_pair]]: this pair is given twice");
        }
        r.restitution = optional_number(*t, "material_pair", "restitution");
        r.friction = optional_number(*t, "material_pair", "friction");
        r.rolling_friction = optional_number(*t, "material_pair", "rolling_friction");
        if (!r.restitution && !r.friction && !r.rolling_friction) {
          fail(t, "[[material_pair]]: expected restitution, friction and/or rolling_friction");
        }
        if (r.rolling_friction && !(*r.rolling_friction >= 0.0 && std::isfinite(*r.rolling_friction))) {
          fail(t->get("rolling_friction"), "[[material_pair]] rolling_friction must be >= 0");
        }
        if (r.restitution && !(*r.restitution > 0.0 && *r.restitution <= 1.0)) {
          fail(t->get("restitution"), "[[material_pair]] restitution must be in (0, 1]");
        }
        if (r.friction && !(*r.friction >= 0.0)) fail(t->get("friction"), "[[material_pair]] friction must be >= 0");
        s.material_pairs.push_back(r);
      }
    }
  }

  std::uint16_t material_index(const toml::node* node, const std::string& name, const SimulationSetup& s,
                               const std::string& what) const {
    for (std::size_t k = 0; k < s.material_names.size(); ++k) {
      if (s.material_names[k] == name) return static_cast<std::uint16_t>(k);
    }
    std::string known;
    for (const std::string& n : s.material_names) known += (known.empty() ? "" : ", ") + n;
    fail(node, what + ": unknown material '" + name + "' (the scene has: " + known + ")");
  }

  /// The mean radius by number of the [[insert]] tables' distributions, averaged over the
  /// tables (the reference pair of collision_time in a scene that starts empty) [m].
  static double mean_insert_radius(const std::vector<InsertSpec>& specs) {
    double sum = 0.0;
    for (const InsertSpec& spec : specs) {
      const InsertSizes& z = spec.sizes;
      double mean = 0.5 * (z.r_min + z.r_max);
      if (z.kind == InsertSizes::Kind::kDiscrete) {
        mean = 0.0;
        for (const InsertSize& e : z.entries) mean += e.probability * e.radius;
      }
      sum += mean;
    }
    return sum / static_cast<double>(specs.size());
  }

  /// One [[insert]] table (insertion.hpp; docs/formats.md "Scene tables `[[insert]]` and `insertions.csv`").
  InsertSpec read_insert(const toml::table& t, const SimulationSetup& s, std::size_t index) const {
    check_keys(t, "insert", {"name", "region", "lo", "hi", "point", "axis", "radius", "length", "count", "rate", "start",
                             "every", "every_steps", "stop", "total", "radius_min", "radius_max", "sizes", "material",
                             "velocity", "angular_velocity", "seed", "attempts"});
    InsertSpec spec;
    spec.name = t.contains("name") ? require_string(t, "insert", "name") : "insert " + std::to_string(index);
    auto positive = [&](const char* key, double v) {
      if (!(v > 0.0)) fail(t.get(key), std::string("[[insert]] ") + key + ": expected > 0");
      return v;
    };
    // Region.
    const std::string region = require_string(t, "insert", "region");
    InsertRegion& r = spec.region;
    if (region == "box") {
      for (const char* key : {"point", "axis", "length"}) {
        if (t.contains(key)) fail(t.get(key), std::string("[[insert]] ") + key + " applies to region = \"cylinder\"");
      }
      r.kind = InsertRegion::Kind::kBox;
      r.lo = *require_vec3(t, "insert", "lo");
      r.hi = *require_vec3(t, "insert", "hi");
      if (!(r.lo.array() < r.hi.array()).all()) fail(t.get("hi"), "[[insert]] box: expected lo < hi on every axis");
    } else if (region == "cylinder") {
      for (const char* key : {"lo", "hi"}) {
        if (t.contains(key)) fail(t.get(key), std::string("[[insert]] ") + key + " applies to region = \"box\"");
      }
      r.kind = InsertRegion::Kind::kCylinder;
      r.point = *require_vec3(t, "insert", "point");
      const Vec3 axis = *require_vec3(t, "insert", "axis");
      if (!(axis.norm() > 0.0)) fail(t.get("axis"), "[[insert]] axis must not be zero");
      r.axis = axis.normalized();
      r.radius = positive("radius", require_number(t, "insert", "radius"));
      r.length = positive("length", require_number(t, "insert", "length"));
    } else {
      fail(t.get("region"), "[[insert]] region: expected \"box\" or \"cylinder\", found \"" + region + "\"");
    }
    // Sizes: radius (a number here, the cylinder's in a cylinder), radius_min/radius_max, or sizes.
    InsertSizes& z = spec.sizes;
    auto material_of = [&](const toml::table& table, const char* what) -> std::uint16_t {
      const toml::node* m = table.get("material");
      if (!m) return 0;
      if (!m->is_string()) fail(m, std::string(what) + " material: expected a name");
      return material_index(m, *m->value<std::string>(), s, what);
    };
    const bool has_uniform = t.contains("radius_min") || t.contains("radius_max");
    const bool has_sizes = t.contains("sizes");
    const bool has_constant = r.kind == InsertRegion::Kind::kBox && t.contains("radius");
    if (int(has_uniform) + int(has_sizes) + int(has_constant) != 1) {
      fail(&t, "[[insert]] needs exactly one size distribution: radius = R (box regions; a cylinder's radius is "
               "its own), radius_min and radius_max (uniform), or sizes = [{radius, probability, material}, ...]");
    }
    if (has_constant) {
      z.kind = InsertSizes::Kind::kConstant;
      z.r_min = z.r_max = positive("radius", require_number(t, "insert", "radius"));
      z.material = material_of(t, "[[insert]]");
    } else if (has_uniform) {
      z.kind = InsertSizes::Kind::kUniform;
      z.r_min = positive("radius_min", require_number(t, "insert", "radius_min"));
      z.r_max = positive("radius_max", require_number(t, "insert", "radius_max"));
      if (!(z.r_max >= z.r_min)) fail(t.get("radius_max"), "[[insert]] radius_max must be >= radius_min");
      z.material = material_of(t, "[[insert]]");
    } else {
      if (t.contains("material")) fail(t.get("material"), "[[insert]] material: with sizes, give each entry its material");
      z.kind = InsertSizes::Kind::kDiscrete;
      const toml::array* list = t.get("sizes")->as_array();
      if (!list || list->empty()) fail(t.get("sizes"), "[[insert]] sizes: expected a non-empty array of tables");
      double sum = 0.0;
      for (const toml::node& item : *list) {
        const toml::table* e = item.as_table();
        if (!e) fail(&item, "[[insert]] sizes: expected tables {radius, probability, material}");
        check_keys(*e, "insert.sizes", {"radius", "probability", "material"});
        InsertSize size;
        size.radius = require_number(*e, "insert.sizes", "radius");
        if (!(size.radius > 0.0)) fail(e->get("radius"), "[[insert]] sizes: radius must be > 0 m");
        size.probability = require_number(*e, "insert.sizes", "probability");
        if (!(size.probability > 0.0)) fail(e->get("probability"), "[[insert]] sizes: probability must be > 0");
        size.material = material_of(*e, "[[insert]] sizes");
        sum += size.probability;
        z.entries.push_back(size);
      }
      // 1e-6: probabilities written with six digits still pass; a typo (0.3 + 0.6) does not.
      if (!(std::abs(sum - 1.0) <= 1e-6)) {
        fail(t.get("sizes"), "[[insert]] sizes: the probabilities sum to " + std::to_string(sum) + ", expected 1");
      }
    }
    if (!r.fits(z.largest())) fail(&t, "[[insert]] the region is too small for a sphere of the largest radius");
    // Schedule.
    InsertSchedule& q = spec.schedule;
    const auto to_steps = [&](const char* key) {
      const double v = require_number(t, "insert", key);
      if (!(v >= 0.0)) fail(t.get(key), std::string("[[insert]] ") + key + ": expected >= 0 s");
      return std::llround(v / s.dt);  // the nearest step
    };
    if (t.contains("count") == t.contains("rate")) fail(&t, "[[insert]] needs exactly one of count (per event) or rate [particles/s]");
    if (t.contains("count")) {
      q.count = require_integer(t, "insert", "count");
      if (q.count < 0) fail(t.get("count"), "[[insert]] count must be >= 0");
    } else {
      q.rate = positive("rate", require_number(t, "insert", "rate"));
    }
    q.first_step = t.contains("start") ? to_steps("start") : 0;
    if (t.contains("every") && t.contains("every_steps")) fail(t.get("every_steps"), "[[insert]] give every [s] or every_steps, not both");
    if (t.contains("every")) q.every_steps = to_steps("every");
    if (t.contains("every_steps")) q.every_steps = require_integer(t, "insert", "every_steps");
    if ((t.contains("every") || t.contains("every_steps")) && q.every_steps < 1) {
      fail(t.contains("every") ? t.get("every") : t.get("every_steps"), "[[insert]] every: expected at least one time step");
    }
    if (q.rate > 0.0 && q.every_steps == 0) fail(t.get("rate"), "[[insert]] rate needs every [s] or every_steps");
    if (t.contains("stop")) {
      q.last_step = to_steps("stop");
      if (q.last_step < q.first_step) fail(t.get("stop"), "[[insert]] stop must be >= start");
    }
    if (t.contains("total")) {
      q.total = require_integer(t, "insert", "total");
      if (q.total < 0) fail(t.get("total"), "[[insert]] total must be >= 0");
    }
    spec.velocity = optional_vec3(t, "insert", "velocity").value_or(Vec3::Zero());
    spec.angular_velocity = optional_vec3(t, "insert", "angular_velocity").value_or(Vec3::Zero());
    const long seed = optional_integer(t, "insert", "seed").value_or(static_cast<long>(index) + 1);
    if (seed < 0) fail(t.get("seed"), "[[insert]] seed must be >= 0");
    spec.seed = static_cast<std::uint64_t>(seed);
    spec.attempts = optional_integer(t, "insert", "attempts").value_or(100);
    if (spec.attempts < 1) fail(t.get("attempts"), "[[insert]] attempts must be >= 1");
    return spec;
  }

  /// Optional material = "name" of a [[wall]] or [[object]] (boundary index b).
  void set_boundary_material(const toml::table& t, const char* table, std::size_t b, SimulationSetup& s) const {
    const toml::node* m = t.get("material");
    if (!m) return;
    if (!m->is_string()) fail(m, std::string("[") + table + "] material: expected a material name");
    s.boundary_materials.resize(b + 1, -1);
    s.boundary_materials[b] = material_index(m, *m->value<std::string>(), s, std::string("[") + table + "] material");
  }

  std::optional<Index3> optional_index3(const toml::table& t, const char* table, const char* key) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    const toml::array* a = n->as_array();
    const std::string what = std::string("[") + table + "] " + key + ": expected an array of 3 integers >= 1";
    if (!a || a->size() != 3) fail(n, what);
    Index3 v;
    for (std::size_t i = 0; i < 3; ++i) {
      const toml::node& item = *a->get(i);
      if (!item.is_integer()) fail(&item, what);
      const std::int64_t c = item.value<std::int64_t>().value();
      if (c < 1 || c > 100000) fail(&item, what + " (and <= 100000)");
      v[i] = static_cast<int>(c);
    }
    return v;
  }

  // One [[object]] block: the distance field (file or voxelized mesh) and the motion.
  std::shared_ptr<const DistanceFieldObject> read_object(const toml::table& t, const SimulationSetup& s,
                                                         std::size_t index) const {
    check_keys(t, "object", {"name", "distance", "mesh", "cells", "margin", "velocity", "axis", "omega",
                             "centroid", "start", "stop", "material", "motion", "contact"});
    const std::string name = t.contains("name") ? require_string(t, "object", "name")
                                                : "object " + std::to_string(index + 1);
    const bool has_distance = t.contains("distance");
    const bool has_mesh = t.contains("mesh");
    if (has_distance == has_mesh) fail(&t, "[[object]] needs exactly one of distance = \"phi.vtk\" or mesh = \"m.stl\"");
    // contact = "mesh" (default for mesh =): the mesh's faces, edges and vertices
    // (mesh_contact.hpp); "field" (the only one for distance =): the seed's single trilinear
    // contact (docs/objects.md "Exact contacts for mesh objects").
    bool mesh_contacts = has_mesh;
    if (t.contains("contact")) {
      const std::string contact = require_string(t, "object", "contact");
      if (contact != "mesh" && contact != "field") {
        fail(t.get("contact"), "[object] contact: expected \"mesh\" or \"field\", found \"" + contact + "\"");
      }
      if (contact == "mesh" && !has_mesh) {
        fail(t.get("contact"), "[object] contact = \"mesh\" needs mesh = \"m.stl\" (a distance = object has only its field)");
      }
      mesh_contacts = contact == "mesh";
    }
    ScalarField field;
    std::optional<TriangleMesh> display_mesh;  // the mesh = itself, in the object frame
    if (has_distance) {
      for (const char* key : {"cells", "margin"}) {
        if (t.contains(key)) fail(t.get(key), std::string("[object] ") + key + " applies to mesh =, not to distance =");
      }
      field = read_vtk_structured_points(relative_to_scene(require_string(t, "object", "distance")));
    } else {
      const auto cells = optional_index3(t, "object", "cells");
      if (!cells) fail(&t, "[object] mesh = needs cells = [nx, ny, nz]");
      double r_max = 0.0;
      for (const Particle& p : s.particles) r_max = std::max(r_max, p.radius);
      if (s.shared()) r_max = s.share.comm->max_over_ranks(r_max);  // exact: a maximum
      for (const Particle& p : s.insert_probes) r_max = std::max(r_max, p.radius);  // particles to come
      const double margin = optional_number(t, "object", "margin").value_or(2.0 * r_max);
      if (!(margin >= 0.0)) fail(t.get("margin"), "[object] margin must be >= 0 m");
      const TriangleMesh mesh = read_stl(relative_to_scene(require_string(t, "object", "mesh")));
      const BoundingBox box = bounding_box(mesh);
      if (box.empty()) fail(t.get("mesh"), "[object] mesh has no triangles");
      const Vec3 pad = Vec3::Constant(margin);
      const Index3 nodes = {(*cells)[0] + 1, (*cells)[1] + 1, (*cells)[2] + 1};
      const GridSpec grid = GridSpec::spanning(box.min - pad, box.max + pad, nodes);
      field = sdf::fast::FastSdfBuilder().build(mesh, grid);  // exact distance (fast_sdf_builder.hpp)
      display_mesh = mesh;
    }
    const Vec3 centroid = optional_vec3(t, "object", "centroid").value_or(0.5 * (field.grid.origin + field.grid.upper_corner()));
    std::shared_ptr<DistanceFieldObject> object;
    if (const toml::node* program = t.get("motion")) {  // a motion program (docs/objects.md)
      for (const char* key : {"velocity", "axis", "omega", "start", "stop"}) {
        if (t.contains(key)) {
          fail(t.get(key), std::string("[object] ") + key + " is a single-motion key: with [[object.motion]] segments "
                           "give the motion in the segments");
        }
      }
      object = std::make_shared<DistanceFieldObject>(std::move(field), read_motion_program(*program, centroid),
                                                     name_ + ": " + name);
    } else {
      RigidMotion motion;
      motion.velocity = optional_vec3(t, "object", "velocity").value_or(Vec3::Zero());
      motion.centroid = centroid;
      const double omega = optional_number(t, "object", "omega").value_or(0.0);
      const auto axis = optional_vec3(t, "object", "axis");
      if (omega != 0.0) {
        if (!axis) fail(t.get("omega"), "[object] omega needs axis = [ax, ay, az]");
        if (!(axis->norm() > 0.0)) fail(t.get("axis"), "[object] axis must not be zero");
        motion.angular_velocity = axis->normalized() * omega;  // [rad/s]
      }
      const double start = optional_number(t, "object", "start").value_or(0.0);
      const double stop = optional_number(t, "object", "stop").value_or(std::numeric_limits<double>::infinity());
      if (stop < start) fail(t.get("stop"), "[object] stop must be >= start");
      object = std::make_shared<DistanceFieldObject>(std::move(field), motion, name_ + ": " + name, start, stop);
    }
    if (mesh_contacts) object->use_mesh_contacts(*display_mesh);
    if (display_mesh) object->set_display_mesh(std::move(*display_mesh));
    return object;
  }

  // [[object.motion]] segments: one table per segment, in increasing start times.
  MotionProgram read_motion_program(const toml::node& node, const Vec3& reference_point) const {
    const toml::array* list = node.as_array();
    if (!list || list->empty()) fail(&node, "[[object.motion]] must be a non-empty array of tables");
    std::vector<MotionSegment> segments;
    for (const toml::node& item : *list) {
      const toml::table* m = item.as_table();
      if (!m) fail(&item, "[[object.motion]] entries must be tables");
      segments.push_back(read_motion_segment(*m));
      if (segments.size() > 1 && !(segments.back().start > segments[segments.size() - 2].start)) {
        fail(m->get("start"), "[object.motion] start: expected a time after the previous segment's start (" +
                                  number_text(segments[segments.size() - 2].start) + " s)");
      }
    }
    try {
      return MotionProgram(std::move(segments), reference_point);
    } catch (const std::invalid_argument& e) {  // the checks above should have caught it
      fail(&node, std::string("[[object.motion]] ") + e.what());
    }
  }

  static std::string number_text(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
  }

  /// One segment: start [s], type and the type's keys (SI units; docs/objects.md).
  MotionSegment read_motion_segment(const toml::table& m) const {
    const char* table = "object.motion";
    const std::string type = require_string(m, table, "type");
    MotionSegment seg;
    seg.start = require_number(m, table, "start");
    // The rotation of a linear or sine part: a non-zero axis (normalised).
    auto unit_axis = [&] {
      const Vec3 axis = *require_vec3(m, table, "axis");
      if (!(axis.norm() > 0.0) || !std::isfinite(axis.norm())) fail(m.get("axis"), "[object.motion] axis: expected a non-zero finite vector");
      return Vec3(axis.normalized());
    };
    // w = 2 pi f from exactly one of frequency [Hz] or period [s]; phase [rad], default 0.
    auto oscillation = [&](MotionPart& part) {
      const bool has_f = m.contains("frequency");
      if (has_f == m.contains("period")) fail(&m, "[object.motion] type = \"" + type + "\" needs exactly one of frequency = f [Hz] or period = T [s]");
      const double value = require_number(m, table, has_f ? "frequency" : "period");
      if (!(value > 0.0)) fail(m.get(has_f ? "frequency" : "period"), std::string("[object.motion] ") + (has_f ? "frequency" : "period") + ": expected a number > 0");
      part.angular_frequency = 2.0 * std::numbers::pi * (has_f ? value : 1.0 / value);
      if (!std::isfinite(part.angular_frequency) || !(part.angular_frequency > 0.0)) {
        fail(m.get(has_f ? "frequency" : "period"), "[object.motion] the angular frequency 2 pi f is not a finite number > 0");
      }
      part.phase = optional_number(m, table, "phase").value_or(0.0);
    };
    if (type == "rest") {
      check_keys(m, table, {"start", "type"});
    } else if (type == "translate") {
      check_keys(m, table, {"start", "type", "velocity"});
      seg.translation = {MotionProfile::linear, *require_vec3(m, table, "velocity")};
    } else if (type == "rotate" || type == "translate_rotate") {
      if (type == "rotate") check_keys(m, table, {"start", "type", "axis", "omega", "point"});
      else check_keys(m, table, {"start", "type", "velocity", "axis", "omega", "point"});
      if (type == "translate_rotate") seg.translation = {MotionProfile::linear, *require_vec3(m, table, "velocity")};
      const Vec3 axis = unit_axis();
      seg.rotation = {MotionProfile::linear, axis * require_number(m, table, "omega")};  // [rad/s]
      seg.point = optional_vec3(m, table, "point");
    } else if (type == "vibrate_translate") {
      check_keys(m, table, {"start", "type", "amplitude", "frequency", "period", "phase"});
      seg.translation.profile = MotionProfile::sine;
      seg.translation.vector = *require_vec3(m, table, "amplitude");  // [m]
      oscillation(seg.translation);
    } else if (type == "vibrate_rotate") {
      check_keys(m, table, {"start", "type", "axis", "amplitude", "frequency", "period", "phase", "point"});
      seg.rotation.profile = MotionProfile::sine;
      seg.rotation.vector = unit_axis() * require_number(m, table, "amplitude");  // [rad]
      oscillation(seg.rotation);
      seg.point = optional_vec3(m, table, "point");
    } else {
      fail(m.get("type"), "[object.motion] type: expected \"rest\", \"translate\", \"rotate\", \"translate_rotate\", "
                          "\"vibrate_translate\" or \"vibrate_rotate\", found \"" + type + "\"");
    }
    return seg;
  }

  fs::path file_;
  std::string name_;
  fs::path base_dir_;
  std::optional<std::string> text_;
  std::optional<Particles> given_particles_;
  const Comm* comm_ = nullptr;  ///< the ranks that share the particle file's parse
};

}  // namespace

Scene read_scene(const std::filesystem::path& file, const Comm* comm) {
  if (!fs::exists(file)) throw InputError(file.string(), 0, "scene file does not exist");
  return SceneParser(file, comm).parse();
}

Scene read_scene_text(std::string text, const std::string& name, const std::filesystem::path& base_dir,
                      std::optional<Particles> particles) {
  return SceneParser(std::move(text), name, base_dir, std::move(particles)).parse();
}

}  // namespace ppohdem::dem
