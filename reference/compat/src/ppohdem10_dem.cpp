// The original DEM's set-up, integrator and time loop (ppohDEM_pre, ppohDEM_Symplectic1,
// sample_main01); see ppohdem10_dem.hpp.
#include "ppohdem/compat/ppohdem10_dem.hpp"

#include <algorithm>
#include <string>

#include "ppohdem/error.hpp"

namespace ppohdem::compat {
namespace {

using C = Ppohdem10DemConstants;

Ppohdem10Particles particles_from_state(const Ppohdem10State& s) {
  Ppohdem10Particles p;
  const std::size_t n = s.particles.size();
  p.pos.resize(n);
  p.vel.resize(n);
  p.omega.resize(n);
  p.force.resize(n);
  p.rforce.resize(n);
  p.radius.resize(n);
  p.cellindex.assign(n, 0);
  p.id.resize(n);
  p.contact_list.assign(n, {});
  p.contact_list_wall.assign(n, {});
  for (std::size_t i = 0; i < n; ++i) {  // id order = the original's creation order
    const Ppohdem10ParticleRecord& r = s.particles[i];
    p.pos[i] = r.pos;
    p.vel[i] = r.vel;
    p.omega[i] = r.omega;
    p.radius[i] = r.radius;
    p.id[i] = r.id;
  }
  return p;
}

Ppohdem10Object make_object(const Ppohdem10DemInput& in) {
  const UpdateParamsInput& prm = in.params;
  Ppohdem10Object o;
  o.gridnum = prm.window_nodes;
  if (o.gridnum[0] < 2 || o.gridnum[1] < 2 || o.gridnum[2] < 2) {
    throw InputError("--compat ppohdem-1.0: Obj_n_x_y_z: expected at least 2 nodes per axis");
  }
  // gridsize = L / (Obj_n - 1) [m]: a double divided by an integer.
  o.gridsize = {prm.domain_length.x() / (o.gridnum[0] - 1), prm.domain_length.y() / (o.gridnum[1] - 1),
                prm.domain_length.z() / (o.gridnum[2] - 1)};
  o.winstart = prm.window_start;
  o.vel = {prm.velocity.x(), prm.velocity.y(), prm.velocity.z()};
  o.omega_axis = {prm.rotation_axis.x(), prm.rotation_axis.y(), prm.rotation_axis.z()};
  if (o.omega_axis.x == 0.0 && o.omega_axis.y == 0.0 && o.omega_axis.z == 0.0) {
    throw InputError("--compat ppohdem-1.0: Obj_omega_x_y_z: the original divides by the axis length; expected a "
                     "nonzero axis");
  }
  // omega%w = -Pi / Obj_omega_Pi_rad_per_w [rad per frame] with the float-rounded Pi (Q9).
  o.omega_w = -C::kPi / prm.omega_pi_rad_per_w;
  o.centroid = {prm.centroid.x(), prm.centroid.y(), prm.centroid.z()};
  o.data_nodes = in.data.nodes;
  o.read_distance_3D = in.data.values;
  // Q6: README "until the first update at step 500, the field holds read_distance(1:20,1:20,1:20)":
  // the window starts as the data grid's corner, not at winstart.
  const int nx = o.gridnum[0];
  const int ny = o.gridnum[1];
  o.distance.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * static_cast<std::size_t>(o.gridnum[2]),
                    0.0);
  for (int k = 1; k <= o.gridnum[2]; ++k) {
    for (int j = 1; j <= ny; ++j) {
      for (int i = 1; i <= nx; ++i) {
        o.distance[static_cast<std::size_t>((k - 1) * nx * ny + (j - 1) * ny + i - 1)] = o.data(i, j, k);
      }
    }
  }
  if (in.mesh_vertices.size() % 3 != 0) {
    throw InputError("object_mesh.stl: expected a multiple of 3 vertex lines, found " +
                     std::to_string(in.mesh_vertices.size()));
  }
  for (std::size_t v = 0; v + 2 < in.mesh_vertices.size(); v += 3) {
    o.mesh_v1.push_back(in.mesh_vertices[v]);
    o.mesh_v2.push_back(in.mesh_vertices[v + 1]);
    o.mesh_v3.push_back(in.mesh_vertices[v + 2]);
  }
  return o;
}

}  // namespace

std::vector<Ppohdem10Wall> ppohdem10_make_walls(const Vec3& L) {
  const Rvec3 origin{0.0, 0.0, 0.0};
  const Rvec3 far{L.x(), L.y(), L.z()};
  return {{origin, {1.0, 0.0, 0.0}}, {origin, {0.0, 1.0, 0.0}}, {origin, {0.0, 0.0, 1.0}},
          {far, {-1.0, 0.0, 0.0}},   {far, {0.0, -1.0, 0.0}},   {far, {0.0, 0.0, -1.0}}};
}

void ppohdem10_symplectic(Ppohdem10Particles& p) {
  // Q8: README "symplectic Euler update: v += dt F/m (gravity subtracted in z); x += dt v;
  // omega += dt/Im * radius * rforce (note the factor of radius)". First order in dt (the
  // default engine uses velocity Verlet, second order). rforce = sum n x F_t, so r rforce is
  // the torque [N m]; dividing by Im = 0.1 (not by the moment of inertia 2/5 m r^2 = 0.004..0.006)
  // makes the particles spin 17-25 times too slowly.
  const double t_step = C::kTimeStep;
  const double t_step1 = t_step / C::kMass;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vel[i].x = p.vel[i].x + t_step1 * (p.force[i].x);
    p.vel[i].y = p.vel[i].y + t_step1 * p.force[i].y;
    p.vel[i].z = p.vel[i].z + t_step1 * (p.force[i].z - C::kGravity);
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.pos[i].x = p.pos[i].x + t_step * p.vel[i].x;
    p.pos[i].y = p.pos[i].y + t_step * p.vel[i].y;
    p.pos[i].z = p.pos[i].z + t_step * p.vel[i].z;
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double t_step2 = t_step / C::kInertia * p.radius[i];
    p.omega[i].x = p.omega[i].x + t_step2 * p.rforce[i].x;
    p.omega[i].y = p.omega[i].y + t_step2 * p.rforce[i].y;
    p.omega[i].z = p.omega[i].z + t_step2 * p.rforce[i].z;
  }
}

Ppohdem10Dem::Ppohdem10Dem(const Ppohdem10DemInput& in, bool sort_by_cell) {
  params_.input = in.params;
  if (in.initial.particles.empty()) throw InputError("--compat ppohdem-1.0: the initial state has no particles");
  for (std::size_t i = 0; i < in.initial.particles.size(); ++i) {
    if (in.initial.particles[i].id != static_cast<int>(i + 1)) {
      throw InputError("--compat ppohdem-1.0: the initial state must list ids 1..n in order; row " +
                       std::to_string(i + 1) + " has id " + std::to_string(in.initial.particles[i].id));
    }
  }
  particles_ = particles_from_state(in.initial);
  cells_ = ppohdem10_make_cells(in.params.domain_length);
  walls_ = ppohdem10_make_walls(in.params.domain_length);
  object_ = make_object(in);
  // MaxRadius = max_radius(particles): the largest radius, scanned from particle 1.
  params_.max_radius = particles_.radius[0];
  for (std::size_t i = 1; i < particles_.size(); ++i) {
    if (params_.max_radius < particles_.radius[i]) params_.max_radius = particles_.radius[i];
  }
  // ppohDEM_checkparameters: the cells must hold a particle diameter.
  if (cells_.cellsize.x - 2 * params_.max_radius < 0.) {
    throw InputError("--compat ppohdem-1.0: cell size is smaller than a particle diameter");
  }
  counter_.itime = in.initial.step;
  counter_.rtime = in.initial.rtime;
  counter_.file_index = static_cast<int>(in.initial.step / C::kStepsPerFrame);
  if (counter_.file_index > 0) ppohdem10_update_object_field(object_, counter_.file_index);
  // sample_main01 sorts the particles by cell once before the loop.
  if (sort_by_cell) update_index();
}

void Ppohdem10Dem::update_index() { ppohdem10_update_index(particles_, cells_, counter_.itime); }

bool Ppohdem10Dem::check_update() {
  const bool resorted = ppohdem10_check_update(particles_, cells_, counter_, params_);
  if (resorted) ++resort_count_;
  return resorted;
}

void Ppohdem10Dem::integrate_system() {
  ppohdem10_calcforce(particles_, cells_, walls_, counter_.itime);
  ppohdem10_embedding(particles_, object_, counter_.itime);
  ppohdem10_symplectic(particles_);
}

bool Ppohdem10Dem::advance_counters() {
  // ppohDEM_dataout: the counters (the file itself is written by the driver).
  counter_.itime = counter_.itime + 1;
  counter_.rtime = counter_.rtime + C::kTimeStep;
  if (counter_.itime % C::kStepsPerFrame != 0) return false;
  counter_.file_index = counter_.file_index + 1;
  return true;
}

bool Ppohdem10Dem::check_objects() {
  // ppohDEM_check_objects: the field for frame file_index (used from the next step on).
  if (counter_.itime % C::kStepsPerFrame != 0) return false;
  ppohdem10_update_object_field(object_, counter_.file_index);
  return true;
}

Ppohdem10StepEvents Ppohdem10Dem::step() {
  Ppohdem10StepEvents events;
  events.resorted = check_update();
  integrate_system();
  events.frame = advance_counters();
  if (events.frame) check_objects();
  return events;
}

Ppohdem10State Ppohdem10Dem::state() const {
  Ppohdem10State s;
  s.step = counter_.itime;
  s.rtime = counter_.rtime;
  s.particles.resize(particles_.size());
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const auto slot = static_cast<std::size_t>(particles_.id[i] - 1);
    Ppohdem10ParticleRecord& r = s.particles[slot];
    r.id = particles_.id[i];
    r.pos = particles_.pos[i];
    r.vel = particles_.vel[i];
    r.omega = particles_.omega[i];
    r.radius = particles_.radius[i];
    r.force = particles_.force[i];
    r.rforce = particles_.rforce[i];
    r.ncontact = static_cast<int>(particles_.contact_list[i].size());
    r.ncontact_wall = static_cast<int>(particles_.contact_list_wall[i].size());
  }
  return s;
}

}  // namespace ppohdem::compat
