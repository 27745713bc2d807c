/* ppohdem.h - the C API of ppohdem (C99). docs/fortran.md section "The C API".
 *
 * Conventions
 *  - Every function returns a ppohdem_status. PPOHDEM_OK is 0; on any other value
 *    ppohdem_last_error() returns a message naming the cause (the file, the argument or the
 *    stage). No C++ exception crosses this boundary.
 *  - Objects are opaque handles, created by *_create / *_read functions and released by the
 *    matching *_destroy (destroying NULL is allowed and returns PPOHDEM_OK).
 *  - Arrays: the caller owns every array it passes. Input arrays are copied before the call
 *    returns (the caller may free them at once). Output arrays are caller buffers; the call
 *    writes exactly the count it documents and never keeps the pointer. A buffer that is too
 *    small gives PPOHDEM_ERR_BUFFER and writes nothing.
 *  - Vectors are stored xyz-interleaved: element 3*i+a is component a of item i.
 *  - Grids are node grids: node (i,j,k), 0-based, sits at origin + (i h_x, j h_y, k h_z);
 *    field values are stored with i fastest: index i + n_x (j + n_y k).
 *  - Units are SI: lengths m, times s, velocities m/s, angular velocities rad/s, forces N,
 *    torques N m, energies J, densities kg/m^3, Young's modulus Pa.
 *  - Handles are not thread-safe; ppohdem_last_error() is per thread.
 */
#ifndef PPOHDEM_PPOHDEM_H
#define PPOHDEM_PPOHDEM_H

#include <stddef.h>
#include <stdint.h>

/* Symbols of the shared library: only the functions below are exported. */
#if defined(__GNUC__)
#define PPOHDEM_API __attribute__((visibility("default")))
#else
#define PPOHDEM_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum ppohdem_status {
  PPOHDEM_OK = 0,
  PPOHDEM_ERR_ARGUMENT = 1, /* a NULL handle or pointer, a bad count or name */
  PPOHDEM_ERR_INPUT = 2,    /* an input file or value is invalid (message names file:line) */
  PPOHDEM_ERR_STATE = 3,    /* a stage was called before its prerequisite */
  PPOHDEM_ERR_BUFFER = 4,   /* an output buffer is smaller than the documented count */
  PPOHDEM_ERR_IO = 5,       /* a file could not be written */
  PPOHDEM_ERR_INTERNAL = 6  /* any other failure (out of memory, ...) */
} ppohdem_status;

/* The message of the last failed call on this thread ("" if none). Valid until the next call. */
PPOHDEM_API const char* ppohdem_last_error(void);
/* "0.1.0": the library version (static string). */
PPOHDEM_API const char* ppohdem_version(void);
/* The provenance line (version, git hash, compiler, build type) into buf (NUL-terminated).
 * *needed receives the size with the NUL; buf may be NULL with size 0 to ask for it. */
PPOHDEM_API ppohdem_status ppohdem_provenance(char* buf, size_t size, size_t* needed);

/* ---- signed distance fields --------------------------------------------------------------- */

typedef struct ppohdem_grid {
  double origin[3];   /* node (0,0,0) [m] */
  double spacing[3];  /* h per axis [m], > 0 */
  int32_t nodes[3];   /* node count per axis, >= 1 */
} ppohdem_grid;

/* The field of the closed triangle mesh in mesh_path (ASCII or binary STL) on grid, into
 * out[0 .. out_count) (out_count >= nodes product). method: "exact" (reference builder),
 * "fast" (default when NULL) or "seed"; phi < 0 inside [m]. */
PPOHDEM_API ppohdem_status ppohdem_sdf_build_from_file(const char* mesh_path, const ppohdem_grid* grid, const char* method,
                                           double* out, size_t out_count);
/* The same from arrays: vertices[3*vertex_count] [m], triangles[3*triangle_count] 0-based
 * vertex indices. */
PPOHDEM_API ppohdem_status ppohdem_sdf_build_from_arrays(const double* vertices, size_t vertex_count, const int32_t* triangles,
                                             size_t triangle_count, const ppohdem_grid* grid, const char* method,
                                             double* out, size_t out_count);

typedef struct ppohdem_field ppohdem_field;
/* A field handle holding a copy of values[nodes product] on grid. */
PPOHDEM_API ppohdem_status ppohdem_field_create(const ppohdem_grid* grid, const double* values, size_t value_count,
                                    ppohdem_field** field);
PPOHDEM_API ppohdem_status ppohdem_field_destroy(ppohdem_field* field);
/* Trilinear phi [m] and its exact gradient at points[3*count]. phi[count] and gradient[3*count]
 * (gradient may be NULL). A point outside the node box gives phi = NaN, gradient NaN, and
 * *outside (may be NULL) counts them. */
PPOHDEM_API ppohdem_status ppohdem_field_query(const ppohdem_field* field, const double* points, size_t count, double* phi,
                                   double* gradient, size_t* outside);

/* ---- DEM scenes and engines --------------------------------------------------------------- */

typedef struct ppohdem_scene ppohdem_scene;
typedef struct ppohdem_engine ppohdem_engine;

/* A scene from a TOML scene file (docs/dem.md). */
PPOHDEM_API ppohdem_status ppohdem_scene_read_toml(const char* path, ppohdem_scene** scene);
/* An empty scene: time step dt [s], gravity[3] [m/s^2] and material 0 (density [kg/m^3],
 * Young's modulus [Pa], Poisson ratio, restitution e in (0,1], friction mu >= 0). Contact law:
 * Hertz-Mindlin. */
PPOHDEM_API ppohdem_status ppohdem_scene_create(double dt, const double gravity[3], double density, double young,
                                    double poisson, double restitution, double friction, ppohdem_scene** scene);
/* Adds one more material; *index receives its index (1, 2, ...). */
PPOHDEM_API ppohdem_status ppohdem_scene_add_material(ppohdem_scene* scene, double density, double young, double poisson,
                                          double restitution, double friction, int32_t* index);
/* Adds count particles: ids (NULL: 1, 2, ... continuing), positions[3*count], velocities
 * (NULL: at rest), radius[count], material[count] (NULL: material 0). */
PPOHDEM_API ppohdem_status ppohdem_scene_add_particles(ppohdem_scene* scene, size_t count, const int64_t* ids,
                                           const double* positions, const double* velocities, const double* radius,
                                           const int32_t* material);
/* A plane wall through point[3] with normal[3] (towards the particles), moving at velocity[3]
 * (NULL: fixed). */
PPOHDEM_API ppohdem_status ppohdem_scene_add_wall(ppohdem_scene* scene, const double point[3], const double normal[3],
                                      const double velocity[3]);
/* A rigid object given by its distance field (copied) in its own frame at t = 0, moving with
 * velocity[3] [m/s] and angular velocity[3] [rad/s] about centroid[3] [m] (NULL: zero). */
PPOHDEM_API ppohdem_status ppohdem_scene_add_object(ppohdem_scene* scene, const ppohdem_field* field, const char* name,
                                        const double velocity[3], const double angular_velocity[3],
                                        const double centroid[3]);
/* A motion program (docs/objects.md "Motion programs"): segments in strictly increasing start
 * times, segment k acting from its start until the next one's (the last for ever); before the
 * first the object rests. Each type reads only its fields (the others are ignored):
 *   REST                -
 *   TRANSLATE           velocity [m/s]
 *   ROTATE              axis (non-zero; normalised), omega [rad/s], point if has_point
 *   TRANSLATE_ROTATE    velocity, axis, omega, point if has_point
 *   VIBRATE_TRANSLATE   amplitude[3] [m], frequency [Hz] > 0, phase [rad]
 *   VIBRATE_ROTATE      axis, amplitude[0] [rad], frequency, phase, point if has_point
 * point [m, world] is on the axis at the segment's start; without it the axis passes through
 * where the motion so far has carried the centroid. Vibrations: d = A (sin(2 pi f s + phase) -
 * sin(phase)), s the time since the segment's start. */
typedef enum ppohdem_motion_type {
  PPOHDEM_MOTION_REST = 0,
  PPOHDEM_MOTION_TRANSLATE = 1,
  PPOHDEM_MOTION_ROTATE = 2,
  PPOHDEM_MOTION_TRANSLATE_ROTATE = 3,
  PPOHDEM_MOTION_VIBRATE_TRANSLATE = 4,
  PPOHDEM_MOTION_VIBRATE_ROTATE = 5
} ppohdem_motion_type;

typedef struct ppohdem_motion_segment {
  int32_t type; /* a ppohdem_motion_type */
  double start; /* [s] */
  double velocity[3];
  double axis[3];
  double omega;
  double amplitude[3];
  double frequency;
  double phase;
  int32_t has_point;
  double point[3];
} ppohdem_motion_segment;

/* A rigid object given by its distance field (copied) in its own frame, moved by the motion
 * program segments[segment_count] (copied); torques are taken about centroid[3] [m] at rest
 * (NULL: the origin), which the motion carries. */
PPOHDEM_API ppohdem_status ppohdem_scene_add_object_program(ppohdem_scene* scene, const ppohdem_field* field,
                                                const char* name, const double centroid[3],
                                                const ppohdem_motion_segment* segments, size_t segment_count);
PPOHDEM_API ppohdem_status ppohdem_scene_particle_count(const ppohdem_scene* scene, size_t* count);
/* Steps the scene asks for (TOML [run] steps; 0 for a scene built from arrays). */
PPOHDEM_API ppohdem_status ppohdem_scene_steps(const ppohdem_scene* scene, long* steps);
PPOHDEM_API ppohdem_status ppohdem_scene_destroy(ppohdem_scene* scene);

/* An engine for the scene (copied; the scene may be destroyed afterwards). engine_name:
 * "reference" (default when NULL) or "fast". The scene is validated (time step, overlaps). */
PPOHDEM_API ppohdem_status ppohdem_engine_create(const ppohdem_scene* scene, const char* engine_name, ppohdem_engine** engine);
PPOHDEM_API ppohdem_status ppohdem_engine_destroy(ppohdem_engine* engine);
PPOHDEM_API ppohdem_status ppohdem_engine_step(ppohdem_engine* engine);
PPOHDEM_API ppohdem_status ppohdem_engine_advance(ppohdem_engine* engine, long steps);
PPOHDEM_API ppohdem_status ppohdem_engine_step_count(const ppohdem_engine* engine, long* steps);
PPOHDEM_API ppohdem_status ppohdem_engine_time(const ppohdem_engine* engine, double* time);
PPOHDEM_API ppohdem_status ppohdem_engine_particle_count(const ppohdem_engine* engine, size_t* count);

typedef enum ppohdem_quantity {
  PPOHDEM_POSITION = 0,          /* [m] */
  PPOHDEM_VELOCITY = 1,          /* [m/s] */
  PPOHDEM_ANGULAR_VELOCITY = 2,  /* [rad/s] */
  PPOHDEM_FORCE = 3,             /* contact force of the last evaluation, no gravity [N] */
  PPOHDEM_TORQUE = 4             /* contact torque about the centre [N m] */
} ppohdem_quantity;
/* out[3*count], count >= particle count, in the engine's particle order (see ids). */
PPOHDEM_API ppohdem_status ppohdem_engine_read(const ppohdem_engine* engine, ppohdem_quantity quantity, double* out,
                                   size_t count);
PPOHDEM_API ppohdem_status ppohdem_engine_read_ids(const ppohdem_engine* engine, int64_t* ids, size_t count);

typedef struct ppohdem_energies {
  double kinetic, rotational, gravitational, elastic; /* [J] */
  double dissipated, boundary_work;                   /* cumulative [J] */
  double total;                                       /* kinetic + ... - boundary_work */
} ppohdem_energies;
PPOHDEM_API ppohdem_status ppohdem_engine_energies(const ppohdem_engine* engine, ppohdem_energies* energies);
/* Checkpoint file (docs/reliability.md format); restart restores an engine of the same scene. */
PPOHDEM_API ppohdem_status ppohdem_engine_checkpoint(const ppohdem_engine* engine, const char* path);
PPOHDEM_API ppohdem_status ppohdem_engine_restart(ppohdem_engine* engine, const char* path);

/* ---- ppohDEM-1.0 library stages (used by the Fortran modules, docs/fortran.md) ------------ */

/* DEM-Util: STL -> distance_NNNN.dat, stage by stage, as the original computes it. Every rank
 * of an MPI run computes the whole field (the ranks' x-slabs are simulated, so the values
 * are the original's for nprocs ranks) and writes only its own file. */
typedef struct ppohdem_util ppohdem_util;
/* Reads input_constants_voxelizer.dat (the original's 6 lines). */
PPOHDEM_API ppohdem_status ppohdem_util_create(const char* input_file, int32_t nprocs, int32_t rank, ppohdem_util** util);
PPOHDEM_API ppohdem_status ppohdem_util_destroy(ppohdem_util* util);
/* nodes[3], length[3] [m], object size[3] and position[3] [m] of the input. */
PPOHDEM_API ppohdem_status ppohdem_util_input(const ppohdem_util* util, int32_t nodes[3], double length[3], double size[3],
                                  double position[3]);
/* Stages, in this order: read_mesh (the STL named in the input), voxelize (placement; rank 0
 * writes <out_dir>/object_mesh.stl; z-ray voxelisation), pass1, exact_band, pass2, write
 * (this rank's <out_dir>/distance_NNNN.dat). A stage before its prerequisite: ERR_STATE. */
PPOHDEM_API ppohdem_status ppohdem_util_read_mesh(ppohdem_util* util);
PPOHDEM_API ppohdem_status ppohdem_util_voxelize(ppohdem_util* util, const char* out_dir);
PPOHDEM_API ppohdem_status ppohdem_util_pass1(ppohdem_util* util);
PPOHDEM_API ppohdem_status ppohdem_util_exact_band(ppohdem_util* util);
PPOHDEM_API ppohdem_status ppohdem_util_pass2(ppohdem_util* util);
PPOHDEM_API ppohdem_status ppohdem_util_write(const ppohdem_util* util, const char* out_dir);
/* Facet count of the mesh read. */
PPOHDEM_API ppohdem_status ppohdem_util_facet_count(const ppohdem_util* util, size_t* count);
/* The current field (after pass1, exact_band or pass2) [m], GridSpec order, all ranks' planes;
 * inside[count] (may be NULL): 1 where the voxelisation said inside. */
PPOHDEM_API ppohdem_status ppohdem_util_field(const ppohdem_util* util, double* distance, int32_t* inside, size_t count);

/* DEM: the original's sample program (600 spheres, a moving object from distance_NNNN.dat). */
typedef struct ppohdem_legacy_dem ppohdem_legacy_dem;
typedef struct ppohdem_legacy_parameters {
  double tstep, tfin;             /* Tstep [s], Time_finish [s] */
  int32_t dstep, pnum;            /* steps per output frame, particle count */
  double length[3];               /* box L [m] */
  int32_t cells[3];               /* Cn */
  double pi, radius, mass, im, kn, kt, en, et, fric_const, gravity, obj_kn, obj_en;
  int32_t size_contact_list, size_contact_list_wall;
  int32_t obj_n[3], winstart[3];
  double obj_velocity[3], obj_omega[4], centroid[3];
} ppohdem_legacy_parameters;
/* Reads input_params_update.dat and fills the original's hard-coded parameters. */
PPOHDEM_API ppohdem_status ppohdem_legacy_read_parameters(const char* params_file, ppohdem_legacy_parameters* parameters);
/* ppohDEM_pre: physics "ppohdem-1.0" (NULL: same; the original's arithmetic, bit for bit) or
 * "corrected" (ppohdem's reference engine on the same sample, docs/compat.md). Reads
 * distance_NNNN.dat and object_mesh.stl from work_dir (corrected: distance_NNNN.dat from the
 * params file's folder), takes count particles at
 * positions[3*count] [m] with radius[count] [m] (at rest, ids 1..count in this order) and writes
 * work_dir/objects_distance.csv. */
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_create(const char* params_file, const char* work_dir, const char* physics,
                                         size_t count, const double* positions, const double* radius,
                                         ppohdem_legacy_dem** dem);
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_destroy(ppohdem_legacy_dem* dem);
/* The stages of the original's time loop. update_index: sort by cell (once before the loop);
 * check_update: re-sort if due; integrate: forces, object, symplectic Euler; dataout: the step
 * counter and, every dstep steps, work_dir/data/outNNN.dat; check_objects: every dstep steps
 * the object field for the current frame, distance/objects_distanceNNN.csv and obj/objNNN.pov.
 * *done receives 1 when the stage acted (a re-sort, a frame) and may be NULL. */
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_update_index(ppohdem_legacy_dem* dem);
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_check_update(ppohdem_legacy_dem* dem, int32_t* done);
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_integrate(ppohdem_legacy_dem* dem);
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_dataout(ppohdem_legacy_dem* dem, int32_t* done);
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_check_objects(ppohdem_legacy_dem* dem, int32_t* done);
/* type(ppohDEM_counter): steps done, time [s], frames written, accumulated max speed. */
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_counter(const ppohdem_legacy_dem* dem, int64_t* itime, double* rtime,
                                          int32_t* file_index, double* pos_accum);
/* MaxRadius [m] of the particles. */
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_max_radius(const ppohdem_legacy_dem* dem, double* max_radius);
/* Positions [m], velocities, angular velocities, radius into caller arrays of count particles,
 * in the engine's current order (any pointer may be NULL). */
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_particles(const ppohdem_legacy_dem* dem, double* positions, double* velocities,
                                            double* angular_velocities, double* radius, size_t count);
/* The full-precision state dump (ids in order), as the patched original's
 * fullprec/state_stepNNNNNN.dat (ppohdem-1.0 physics only). */
PPOHDEM_API ppohdem_status ppohdem_legacy_dem_write_state(const ppohdem_legacy_dem* dem, const char* path);

#ifdef __cplusplus
}
#endif
#endif /* PPOHDEM_PPOHDEM_H */
