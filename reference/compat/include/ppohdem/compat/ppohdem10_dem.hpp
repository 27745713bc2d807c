#pragma once
/// \file ppohdem10_dem.hpp
/// `ppohdem simulate --compat ppohdem-1.0`: the original ppOpen-APPL/DEM 1.0 sample program
/// `sample_main01` (600 spheres falling onto a cube that turns and rises, in an 11 m box) as it
/// really computes, number for number. docs/compat.md lists every place where the original is
/// wrong or fragile and what ppohdem's default engine does instead.
///
/// Source: ppohDEM (Fortran 90, Copyright (c) 2014 JAMSTEC, MIT licence), read from
/// Post-Peta-Crest/ppOpenHPC branch APPL/DEM and /work/shared/ppohdem-original/README.md §2.
/// Units are the original's (its "m", "s", "kg" with mass 1 per particle); see the constants.
///
/// The time loop (sample_main01), one pass per step:
///  1. `check_update`: pos_accum += max_i |v_i| (a speed, NOT multiplied by dt: quirk Q1); if
///     pos_accum > 0.5 (cellsize - 2 MaxRadius) the particles are re-sorted by cell (quicksort,
///     unstable) and pos_accum = 0;
///  2. `calcforce`: for each particle i, the pair forces with every particle of the 27 cells
///     around its cell (periodic cell neighbours, quirk Q2) and the forces of the 6 walls;
///     `embedding`: the object force from the 20^3 object field;
///  3. `Symplectic1`: v += dt F/m (gravity along -z), x += dt v, omega += (dt/Im) r rforce;
///  4. `dataout`: itime += 1, rtime += dt; every Dstep = 500 steps data/outNNN.dat;
///  5. `check_objects`: every 500 steps the object field is resampled for frame NNN and
///     distance/objects_distanceNNN.csv, obj/objNNN.pov are written;
///  the loop ends after the step where rtime > Tfin.
///
/// Quirks reproduced (each is commented where it is coded, with the README's description):
///  Q1 the re-sort trigger accumulates speeds, not distances (ppohdem10_dem_cells.cpp);
///  Q2 cell neighbours wrap around the box periodically, although the box has walls (harmless:
///     the pair distance across the box is large);
///  Q3 after a re-sort, the cell-index array is NOT permuted with the particles, so the cell
///     table and each particle's own cell come from the pre-sort order (ppohdem10_dem_cells.cpp);
///  Q4 after a re-sort, a contact's partner index is mapped through new-to-old instead of
///     old-to-new, so the tangential history of most contacts is lost or attached to another
///     pair (ppohdem10_dem_cells.cpp);
///  Q5 particle-particle contacts have a tangential spring (history rotated by dn_old x dn,
///     not renormalised) and a dashpot on the FULL relative velocity, and NO friction cap;
///     the wall contacts have the cap only when the contact persists from the previous step
///     (ppohdem10_dem_contacts.cpp);
///  Q6 the object moves once per output frame; until step 500 the field is the CORNER of the
///     data grid (sentinels ~440: no object) (ppohdem10_dem_object.cpp);
///  Q7 the object force interpolates with weights t = mod(x, h) in [0, h) instead of
///     [0, 1) (h = 0.5789), its damping is per component with En, not Obj_En;
///  Q8 symplectic Euler, and omega += (dt / Im) r rforce (the factor r);
///  Q9 constants written as single-precision literals (Tstep = 2.0e-3 is 0.0020000000949949026).
///
/// Mirroring: operands in the original's order, Fortran's 1-based indices where they change a
/// result (quicksort pivot, cell numbers), every zero contribution added as the original adds
/// it, no fused multiply-add (-ffp-contract=off). On the sample this reproduces the original's
/// full-precision dumps bit for bit (tests/compat/ppohdem10_dem_test.cpp, docs/compat.md §2).
///
/// A particle whose centre leaves the box (a fast one meeting the soft wall; it happens once in
/// the sample, near step 40300) gets the cell and object-grid numbers of neighbouring cells, as
/// in the original, which reads them anyway; so does this module (counted in outside_box_count).
/// Undefined behaviour of the original is not reproduced but refused: more than 20 contacts of
/// one particle (Size_contact_list) or 5 wall contacts, a cell or object-grid number outside its
/// array, an object node sampled outside the data grid. These throw InputError naming the step
/// and the particle (none happens on the sample).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/compat/ppohdem10_dem_vector.hpp"

namespace ppohdem::compat {

/// The constants of `ppohDEM_setparameters` (Q9). Several are single-precision literals
/// assigned to doubles; these are the doubles the original really uses (README §2 "Hard-coded
/// parameters"), written as float-to-double conversions so the rounding is visible.
struct Ppohdem10DemConstants {
  static constexpr int kParticles = 600;       ///< Pnum
  static constexpr int kCellsPerAxis = 40;     ///< Cn: cell grid 40^3, cell size L/40 [m]
  static constexpr long kStepsPerFrame = 500;  ///< Dstep: output every 500 steps
  static constexpr double kTimeStep = static_cast<double>(2.0e-3f);   ///< Tstep [s] = 0.0020000000949949026
  static constexpr double kPi = static_cast<double>(3.14159265385f);  ///< Pi = 3.1415927410125732
  static constexpr double kRadius = static_cast<double>(0.1f);        ///< Radius [m] = 0.10000000149011612
  static constexpr double kNormalStiffness = 30.0;                    ///< Kn [N/m]
  static constexpr double kNormalDamping = 1.0;                       ///< En [N s/m]
  static constexpr double kTangentialStiffness = 1.0;                 ///< Kt [N/m]
  static constexpr double kTangentialDamping = static_cast<double>(0.1f);  ///< Et [N s/m] = 0.10000000149011612
  static constexpr double kMass = 1.0;                                ///< Mass [kg], every particle
  static constexpr double kInertia = static_cast<double>(0.1f);       ///< Im = 0.10000000149011612 (see Q8)
  static constexpr double kFriction = static_cast<double>(0.5774f);   ///< Fric_const = 0.5774000287055969 (walls only)
  static constexpr double kGravity = static_cast<double>(0.01f);      ///< Gravity [m/s^2] = 0.009999999776482582
  static constexpr double kObjectStiffness = 30.0;                    ///< Obj_Kn [N/m]
  static constexpr double kObjectDamping = 1.0;                       ///< Obj_En (set, never used: Q7)
  static constexpr int kContactListSize = 20;                         ///< Size_contact_list
  static constexpr int kWallContactListSize = 5;                      ///< Size_contact_list_wall
};

/// One entry of a particle's contact list (type ppohDEM_clist): the partner (a particle index,
/// 1-based, or a wall number 1..6), the tangential spring force tforce [N] and the unit normal
/// dn from this particle to the partner, both as of the step that stored them.
struct Ppohdem10Contact {
  int pid = 0;
  Rvec3 tforce;
  Rvec3 dn;
};

/// type(ppohDEM_particles), structure of arrays as in the original. Index p = 0..n-1 here is the
/// original's p+1; `id` is the particle's creation index 1..600 (the patched original's "original
/// id", carried along by every re-sort; it changes no arithmetic).
struct Ppohdem10Particles {
  std::vector<Rvec3> pos;     ///< [m]
  std::vector<Rvec3> vel;     ///< [m/s]
  std::vector<Rvec3> omega;   ///< [rad/s]
  std::vector<Rvec3> force;   ///< [N] of the last force evaluation (gravity excluded)
  std::vector<Rvec3> rforce;  ///< "rforce" = dn x F_t summed [N] (a torque over the radius)
  std::vector<double> radius; ///< [m]
  std::vector<int> cellindex; ///< 1-based cell number, as of the last re-sort, in PRE-sort order (Q3)
  std::vector<int> id;
  std::vector<std::vector<Ppohdem10Contact>> contact_list;       ///< particles, 1-based pids
  std::vector<std::vector<Ppohdem10Contact>> contact_list_wall;  ///< walls 1..6
  // Trace counters (they change no arithmetic):
  long outside_box_count = 0;       ///< re-sorts x particles whose centre was outside the box
  long misattributed_histories = 0; ///< contact-list entries whose partner index a re-sort got wrong (Q4)
  std::size_t size() const { return pos.size(); }
};

/// type(ppohDEM_cells): the 40^3 cell grid, cell c (1-based) holding particles
/// start[c-1] .. end[c-1] (1-based, empty when end < start).
struct Ppohdem10Cells {
  Rvec3 cellsize;                  ///< L / Cn [m]
  Index3 cellnum = {0, 0, 0};      ///< Cn
  std::vector<int> start_partindex;
  std::vector<int> end_partindex;
  std::vector<int> nei_cellindex;  ///< 27 neighbour cells per cell (1-based), periodic (Q2)
};

/// One planar wall of the box: a point on it and its inward unit normal.
struct Ppohdem10Wall {
  Rvec3 point;
  Rvec3 nvec;
};

/// type(ppohDEM_objects): the moving object as a distance field on the 20^3 computational
/// window, resampled from the whole data grid once per output frame (Q6).
struct Ppohdem10Object {
  Index3 gridnum = {0, 0, 0};       ///< Obj_n nodes per axis
  Rvec3 gridsize;                   ///< L / (Obj_n - 1) [m]: node (i,j,k) at gridsize (i-1, j-1, k-1)
  std::vector<double> distance;     ///< window field [m], ijk = (k-1) nx ny + (j-1) ny + i (sic, ny)
  Index3 winstart = {0, 0, 0};      ///< Obj_winstart: window node 1 = data node winstart
  Rvec3 vel;                        ///< Obj_velocity [data nodes per frame]
  Rvec3 omega_axis;                 ///< Obj_omega_x_y_z (normalised where used)
  double omega_w = 0.0;             ///< -Pi / Obj_omega_Pi_rad_per_w [rad per frame]
  Rvec3 centroid;                   ///< Obj_centroid [m, data coordinates]
  Index3 data_nodes = {0, 0, 0};    ///< the data grid (76^3)
  std::vector<double> read_distance_3D;  ///< data values, GridSpec order (x fastest, 0-based)
  std::vector<Rvec3> mesh_v1, mesh_v2, mesh_v3;  ///< object_mesh.stl triangles (for obj/*.pov)
  double data(int i, int j, int k) const;        ///< read_distance_3D(i, j, k), 1-based
};

/// type(ppohDEM_counter).
struct Ppohdem10Counter {
  long itime = 0;          ///< steps done
  double rtime = 0.0;      ///< accumulated time [s] (sum of Tstep, rounded each step)
  int file_index = 0;      ///< output frames written
  double pos_accum = 0.0;  ///< accumulated max speed since the last re-sort (Q1) [m/s]
};

/// The run's parameters: input_params_update.dat plus the derived values of ppohDEM_pre.
struct Ppohdem10Parameters {
  UpdateParamsInput input;
  double max_radius = 0.0;  ///< MaxRadius: largest particle radius [m]
};

/// One particle of a full-precision dump (the patched original's fullprec/state_stepNNNNNN.dat).
struct Ppohdem10ParticleRecord {
  int id = 0;
  Rvec3 pos, vel, omega;
  double radius = 0.0;
  Rvec3 force, rforce;  ///< of the step that produced this state (zero at step 0)
  int ncontact = 0;     ///< length of the particle's contact list
  int ncontact_wall = 0;
};

/// A whole state, particles ordered by id.
struct Ppohdem10State {
  long step = 0;
  double rtime = 0.0;
  std::vector<Ppohdem10ParticleRecord> particles;
};

/// Reads a dump: two '#' header lines (`# step N rtime T n 600`, column names), then one line
/// per particle `id x y z vx vy vz wx wy wz radius fx fy fz tx ty tz ncontact ncontact_wall`
/// (the original writes (I6,16ES25.17,2I4)). InputError (file:line) on anything else.
Ppohdem10State read_ppohdem10_state(const std::filesystem::path& path);
Ppohdem10State parse_ppohdem10_state(const std::string& text, const std::string& source_name);
/// The same layout, byte for byte as the patched original writes it.
std::string format_ppohdem10_state(const Ppohdem10State& state);

/// The original's initial sheet (ppohDEM_locate_particles_2dbox), with ppohdem's own random
/// numbers (std::mt19937_64 seeded with `seed`): gfortran's generator is not reproduced, so this
/// has the original's layout but not its values. For number-for-number runs pass the original's
/// state_step000000.dat instead.
Ppohdem10State ppohdem10_initial_sheet(const UpdateParamsInput& input, unsigned long long seed);

/// Everything the program reads: input_params_update.dat, the distance data
/// (distance_NNNN.dat), object_mesh.stl, and the initial particles.
struct Ppohdem10DemInput {
  UpdateParamsInput params;
  DistanceDat data;
  std::vector<Rvec3> mesh_vertices;  ///< every `vertex` line of object_mesh.stl, in file order
  Ppohdem10State initial;
};

/// Reads `params_file`, and distance_0000.dat (+ the rank files it names) and object_mesh.stl
/// from `work_dir`; the initial state from `initial_state` or, if none, ppohdem10_initial_sheet.
Ppohdem10DemInput read_ppohdem10_dem_input(const std::filesystem::path& params_file,
                                           const std::filesystem::path& work_dir,
                                           const std::optional<std::filesystem::path>& initial_state);

/// Events of one step, for the driver.
struct Ppohdem10StepEvents {
  bool resorted = false;  ///< the particles were re-sorted by cell before this step's forces
  bool frame = false;     ///< itime is a multiple of 500: a frame (out, csv, pov) is due
};

/// The original program's state and time loop.
class Ppohdem10Dem {
 public:
  /// ppohDEM_pre + the first ppohDEM_update_index of sample_main01. The particles start in id
  /// order (the original's creation order). If input.initial.step > 0 the counters start there
  /// and the object field is that of frame step / 500; the contact history and the particle
  /// order of the original at that step are unknown, so only a step-0 start is bitwise (a start
  /// from a state without contacts, like step 500 of the sample, is bitwise too).
  explicit Ppohdem10Dem(const Ppohdem10DemInput& input) : Ppohdem10Dem(input, true) {}
  /// With sort_by_cell = false the particles stay in creation order until update_index()
  /// (the library's ppohDEM_pre, which the program follows with ppohDEM_update_index).
  Ppohdem10Dem(const Ppohdem10DemInput& input, bool sort_by_cell);

  /// One pass of the original's time loop (steps 1-5 of the file comment).
  Ppohdem10StepEvents step();

  // The same pass stage by stage, as the library's subroutines run it (bindings/fortran/dem):
  /// ppohDEM_update_index: sort the particles by cell.
  void update_index();
  /// ppohDEM_check_update (step 1); true if it re-sorted.
  bool check_update();
  /// ppohDEM_integrate_system (steps 2-3).
  void integrate_system();
  /// The counters of ppohDEM_dataout (step 4); true if a frame is due (file_index advanced).
  bool advance_counters();
  /// The field update of ppohDEM_check_objects (step 5) if itime is a multiple of 500; true if
  /// it updated.
  bool check_objects();
  /// The loop's exit test: rtime > Time_finish.
  bool finished() const { return counter_.rtime > params_.input.time_finish; }

  const Ppohdem10Counter& counter() const { return counter_; }
  const Ppohdem10Particles& particles() const { return particles_; }
  const Ppohdem10Object& object() const { return object_; }
  /// The state ordered by id, as the patched original dumps it.
  Ppohdem10State state() const;
  long resort_count() const { return resort_count_; }

  /// data/outNNN.dat of the current state: `x y z radius` per particle in the current
  /// (cell-sorted) order, format (7e16.6).
  std::string frame_text() const;
  /// distance/objects_distanceNNN.csv of the current object field.
  std::string object_field_csv() const;
  /// obj/objNNN.pov of the current frame.
  std::string object_pov() const;

 private:
  Ppohdem10Parameters params_;
  Ppohdem10Particles particles_;
  Ppohdem10Cells cells_;
  std::vector<Ppohdem10Wall> walls_;
  Ppohdem10Object object_;
  Ppohdem10Counter counter_;
  long resort_count_ = 0;
};

// The original's routines, one file each (used by Ppohdem10Dem; public for the tests).

/// ppohDEM_prepare_cells + make_search_cell.
Ppohdem10Cells ppohdem10_make_cells(const Vec3& box_length);
/// ppohDEM_prepare_walls: x = 0, y = 0, z = 0 with normals +x, +y, +z, then x = Lx, y = Ly,
/// z = Lz with normals -x, -y, -z.
std::vector<Ppohdem10Wall> ppohdem10_make_walls(const Vec3& box_length);
/// ppohDEM_iqsort2: Hoare quicksort of `keys` (1-based range first..last), applying every swap
/// to `values` too. Unstable: equal keys are swapped (the order among particles of one cell
/// changes at every re-sort).
void ppohdem10_iqsort2(std::vector<int>& keys, std::vector<int>& values, int first, int last);
/// ppohDEM_update_index: cell numbers, quicksort, rearrange (Q3, Q4), cell start/end.
void ppohdem10_update_index(Ppohdem10Particles& particles, Ppohdem10Cells& cells, long itime);
/// ppohDEM_check_update (Q1). Returns true if it re-sorted.
bool ppohdem10_check_update(Ppohdem10Particles& particles, Ppohdem10Cells& cells, Ppohdem10Counter& counter,
                            const Ppohdem10Parameters& params);
/// ppohDEM_calcforce: pair and wall forces (Q5), into force / rforce, and the new contact lists.
void ppohdem10_calcforce(Ppohdem10Particles& particles, const Ppohdem10Cells& cells,
                         const std::vector<Ppohdem10Wall>& walls, long itime);
/// ppohDEM_embedding: adds the object force of each particle (Q7).
void ppohdem10_embedding(Ppohdem10Particles& particles, const Ppohdem10Object& object, long itime);
/// ppohDEM_Symplectic1 (Q8).
void ppohdem10_symplectic(Ppohdem10Particles& particles);
/// The field part of ppohDEM_check_objects: resample the data for frame `omega_count` (Q6).
void ppohdem10_update_object_field(Ppohdem10Object& object, int omega_count);

/// data/outNNN.dat of any particles: `x y z radius` per line, format (7e16.6) (what
/// Ppohdem10Dem::frame_text writes; also used for the Fortran interface's corrected physics).
std::string ppohdem10_frame_text(const std::vector<Rvec3>& positions, const std::vector<double>& radius);

/// What `ppohdem simulate --compat ppohdem-1.0` does (apps/cmd_simulate_compat.cpp).
struct Ppohdem10RunOptions {
  std::filesystem::path work_dir = ".";             ///< inputs and outputs, as the original's cwd
  std::optional<std::filesystem::path> initial;     ///< --initial state file
  std::optional<long> steps;                        ///< stop after this many steps (default: Tfin)
  bool progress = true;                             ///< progress lines on stderr
};
struct Ppohdem10RunSummary {
  long steps = 0;
  double rtime = 0.0;
  int frames = 0;
  long resorts = 0;
  double wall_seconds = 0.0;
};
/// Runs the program: writes ./objects_distance.csv (the initial field), and per frame NNN
/// data/outNNN.dat, distance/objects_distanceNNN.csv, obj/objNNN.pov under work_dir (the
/// folders are created; the original needs them to exist).
Ppohdem10RunSummary run_ppohdem10_dem(const std::filesystem::path& params_file, const Ppohdem10RunOptions& options);

}  // namespace ppohdem::compat
