/* Calls every function of ppohdem.h, compiled as C99 (not C++), including the error paths.
 * Usage: c_api_test FIXTURES_DIR (the repository's fixtures/). docs/fortran.md "The C API".
 * Expected values are independent of the library: exact geometry (the distance from a cube's
 * centre to its faces), trilinear interpolation of a linear field (exact by construction),
 * closed-form free fall, and bitwise equality of a restarted run with the uninterrupted one. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "ppohdem/ppohdem.h"

static int failures = 0;

#define CHECK(cond)                                                      \
  do {                                                                   \
    if (!(cond)) {                                                       \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                        \
    }                                                                    \
  } while (0)

/* The call must succeed. */
#define OK(call)                                                                                   \
  do {                                                                                             \
    ppohdem_status s_ = (call);                                                                    \
    if (s_ != PPOHDEM_OK) {                                                                        \
      fprintf(stderr, "%s:%d: %s returned %d: %s\n", __FILE__, __LINE__, #call, (int)s_, ppohdem_last_error()); \
      ++failures;                                                                                  \
    }                                                                                              \
  } while (0)

/* The call must fail with `status` and a message containing `word`. */
#define FAILS(call, status, word)                                                                        \
  do {                                                                                                   \
    ppohdem_status s_ = (call);                                                                          \
    if (s_ != (status) || strstr(ppohdem_last_error(), (word)) == NULL) {                                \
      fprintf(stderr, "%s:%d: %s: expected status %d with \"%s\", got %d: \"%s\"\n", __FILE__, __LINE__, \
              #call, (int)(status), (word), (int)s_, ppohdem_last_error());                              \
      ++failures;                                                                                        \
    }                                                                                                    \
  } while (0)

/* Cube [-1,1]^3: 8 vertices, 12 outward-wound triangles. */
static const double kCubeVertices[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                         -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const int32_t kCubeTriangles[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                           2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 3, 0, 4, 3, 4, 7};

static void test_version(void) {
  char small[4];
  size_t needed = 0;
  char* line;
  CHECK(strcmp(ppohdem_version(), "0.1.0") == 0);
  OK(ppohdem_provenance(NULL, 0, &needed));
  CHECK(needed > 8);
  FAILS(ppohdem_provenance(small, sizeof small, &needed), PPOHDEM_ERR_BUFFER, "needed");
  line = malloc(needed);
  OK(ppohdem_provenance(line, needed, NULL));
  CHECK(strstr(line, "ppohdem") != NULL);
  free(line);
  CHECK(strcmp(ppohdem_last_error(), "") == 0); /* a success clears the message */
}

static void test_sdf(const char* fixtures) {
  /* 5^3 nodes, h = 0.5, from -1: node (2,2,2) is the centre, at distance 1 from every face. */
  ppohdem_grid grid = {{-1, -1, -1}, {0.5, 0.5, 0.5}, {5, 5, 5}};
  double phi[125];
  const char* methods[2] = {"exact", "fast"};
  int32_t bad[36];
  char path[1024];
  ppohdem_grid bad_grid = grid;
  int m;
  for (m = 0; m < 2; ++m) {
    OK(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &grid, methods[m], phi, 125));
    CHECK(fabs(phi[2 + 5 * (2 + 5 * 2)] + 1.0) < 1e-12); /* centre: -1 */
    CHECK(fabs(phi[0]) < 1e-12);                           /* corner node on the surface: 0 */
  }
  OK(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &grid, NULL, phi, 125));
  FAILS(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &grid, "magic", phi, 125),
        PPOHDEM_ERR_ARGUMENT, "magic");
  FAILS(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, NULL, NULL, phi, 125),
        PPOHDEM_ERR_ARGUMENT, "grid");
  FAILS(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &grid, NULL, phi, 124),
        PPOHDEM_ERR_BUFFER, "125");
  memcpy(bad, kCubeTriangles, sizeof bad);
  bad[7] = 8;
  FAILS(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, bad, 12, &grid, NULL, phi, 125), PPOHDEM_ERR_ARGUMENT,
        "triangles[7]");
  bad_grid.spacing[1] = 0.0;
  FAILS(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &bad_grid, NULL, phi, 125),
        PPOHDEM_ERR_ARGUMENT, "spacing[1]");
  /* test-cube.stl is the same cube (some vertices written 9.999999e-01). */
  snprintf(path, sizeof path, "%s/ppohdem-1.0/test-cube.stl", fixtures);
  OK(ppohdem_sdf_build_from_file(path, &grid, "exact", phi, 125));
  CHECK(fabs(phi[2 + 5 * (2 + 5 * 2)] + 1.0) < 1e-6); /* 1e-6: the file's 9.999999e-01 vertices */
  FAILS(ppohdem_sdf_build_from_file("/nonexistent/mesh.stl", &grid, NULL, phi, 125), PPOHDEM_ERR_INPUT,
        "/nonexistent/mesh.stl");
}

static void test_field(void) {
  /* f = x + 2y + 3z on 3 x 4 x 5 nodes: trilinear interpolation reproduces it exactly. */
  ppohdem_grid grid = {{1, 2, 3}, {0.5, 0.25, 1.0}, {3, 4, 5}};
  double values[60];
  double points[6] = {1.3, 2.6, 4.7, 10, 0, 0};
  double phi[2], gradient[6];
  size_t outside = 0;
  ppohdem_field* field = NULL;
  int i, j, k;
  for (k = 0; k < 5; ++k)
    for (j = 0; j < 4; ++j)
      for (i = 0; i < 3; ++i) values[i + 3 * (j + 4 * k)] = (1 + 0.5 * i) + 2 * (2 + 0.25 * j) + 3 * (3 + 1.0 * k);
  FAILS(ppohdem_field_create(&grid, values, 59, &field), PPOHDEM_ERR_ARGUMENT, "60");
  CHECK(field == NULL);
  OK(ppohdem_field_create(&grid, values, 60, &field));
  OK(ppohdem_field_query(field, points, 2, phi, gradient, &outside));
  CHECK(fabs(phi[0] - (1.3 + 2 * 2.6 + 3 * 4.7)) < 1e-12);
  CHECK(fabs(gradient[0] - 1) < 1e-12 && fabs(gradient[1] - 2) < 1e-12 && fabs(gradient[2] - 3) < 1e-12);
  CHECK(isnan(phi[1]) && isnan(gradient[3]) && outside == 1);
  OK(ppohdem_field_query(field, points, 1, phi, NULL, NULL));
  FAILS(ppohdem_field_query(NULL, points, 1, phi, NULL, NULL), PPOHDEM_ERR_ARGUMENT, "field");
  OK(ppohdem_field_destroy(field));
  OK(ppohdem_field_destroy(NULL));
}

/* One sphere falling freely from z0 = 1 for 1000 steps. */
static ppohdem_scene* falling_scene(void) {
  const double gravity[3] = {0, 0, -9.81};
  const double position[3] = {0, 0, 1};
  const double radius = 0.01;
  ppohdem_scene* scene = NULL;
  OK(ppohdem_scene_create(1e-5, gravity, 2500, 1e7, 0.3, 0.5, 0.5, &scene));
  OK(ppohdem_scene_add_particles(scene, 1, NULL, position, NULL, &radius, NULL));
  return scene;
}

static void test_dem(const char* fixtures, const char* work) {
  const double gravity[3] = {0, 0, -9.81};
  ppohdem_scene* scene = falling_scene();
  ppohdem_scene* toml = NULL;
  ppohdem_engine* engine = NULL;
  ppohdem_engine* again = NULL;
  ppohdem_energies e0, e1;
  double x[3], v[3], w[3], f[3], t[3], x2[3], time = 0;
  double point[3] = {0, 0, 0}, normal[3] = {0, 0, 1};
  int64_t id = 0;
  long steps = -1;
  size_t count = 0;
  int32_t material = -1, bad_material = 7;
  char path[1024];
  ppohdem_field* field = NULL;
  ppohdem_grid grid = {{-1, -1, -1}, {0.5, 0.5, 0.5}, {5, 5, 5}};
  double phi[125];
  double pos2[3] = {0.5, 0.5, 1.0}, radius2 = 0.01;
  const double t_end = 1000 * 1e-5;

  FAILS(ppohdem_scene_create(0.0, gravity, 2500, 1e7, 0.3, 0.5, 0.5, &toml), PPOHDEM_ERR_ARGUMENT, "dt");
  FAILS(ppohdem_scene_create(1e-5, gravity, -1, 1e7, 0.3, 0.5, 0.5, &toml), PPOHDEM_ERR_INPUT, "density");
  OK(ppohdem_scene_particle_count(scene, &count));
  CHECK(count == 1);
  OK(ppohdem_scene_steps(scene, &steps));
  CHECK(steps == 0);
  FAILS(ppohdem_engine_create(scene, "warp", &engine), PPOHDEM_ERR_ARGUMENT, "warp");
  OK(ppohdem_engine_create(scene, NULL, &engine));
  OK(ppohdem_engine_energies(engine, &e0));
  OK(ppohdem_engine_step(engine));
  OK(ppohdem_engine_advance(engine, 999));
  FAILS(ppohdem_engine_advance(engine, -1), PPOHDEM_ERR_ARGUMENT, "steps");
  OK(ppohdem_engine_step_count(engine, &steps));
  CHECK(steps == 1000);
  OK(ppohdem_engine_time(engine, &time));
  CHECK(fabs(time - t_end) < 1e-15);
  OK(ppohdem_engine_particle_count(engine, &count));
  CHECK(count == 1);
  OK(ppohdem_engine_read(engine, PPOHDEM_POSITION, x, 1));
  OK(ppohdem_engine_read(engine, PPOHDEM_VELOCITY, v, 1));
  OK(ppohdem_engine_read(engine, PPOHDEM_ANGULAR_VELOCITY, w, 1));
  OK(ppohdem_engine_read(engine, PPOHDEM_FORCE, f, 1));
  OK(ppohdem_engine_read(engine, PPOHDEM_TORQUE, t, 1));
  FAILS(ppohdem_engine_read(engine, PPOHDEM_POSITION, x, 0), PPOHDEM_ERR_BUFFER, "needed");
  FAILS(ppohdem_engine_read(engine, (ppohdem_quantity)9, x, 1), PPOHDEM_ERR_ARGUMENT, "quantity");
  /* Free fall: z = 1 - g t^2 / 2, v = -g t; 1e-9: round-off of 1000 steps, any second-order
   * integrator is exact for a constant acceleration. */
  CHECK(fabs(x[2] - (1 - 0.5 * 9.81 * t_end * t_end)) < 1e-9);
  CHECK(fabs(v[2] + 9.81 * t_end) < 1e-9);
  CHECK(w[0] == 0 && f[2] == 0 && t[0] == 0);
  OK(ppohdem_engine_read_ids(engine, &id, 1));
  CHECK(id == 1);
  FAILS(ppohdem_engine_read_ids(engine, &id, 0), PPOHDEM_ERR_BUFFER, "ids");
  OK(ppohdem_engine_energies(engine, &e1));
  CHECK(e1.kinetic > 0 && e1.rotational == 0 && e1.elastic == 0);
  CHECK(fabs(e1.total - e0.total) < 1e-9 * fabs(e0.gravitational)); /* energy conserved */

  /* Checkpoint at step 1000, restart a second engine, advance both: bitwise equal. */
  snprintf(path, sizeof path, "%s/fall.ckpt", work);
  OK(ppohdem_engine_checkpoint(engine, path));
  OK(ppohdem_engine_create(scene, "reference", &again));
  OK(ppohdem_engine_restart(again, path));
  OK(ppohdem_engine_advance(engine, 100));
  OK(ppohdem_engine_advance(again, 100));
  OK(ppohdem_engine_read(engine, PPOHDEM_POSITION, x, 1));
  OK(ppohdem_engine_read(again, PPOHDEM_POSITION, x2, 1));
  CHECK(x[0] == x2[0] && x[1] == x2[1] && x[2] == x2[2]);
  FAILS(ppohdem_engine_restart(again, "/nonexistent/fall.ckpt"), PPOHDEM_ERR_INPUT, "/nonexistent/fall.ckpt");
  FAILS(ppohdem_engine_checkpoint(engine, "/nonexistent/dir/x.ckpt"), PPOHDEM_ERR_INPUT, "/nonexistent/dir");
  OK(ppohdem_engine_destroy(again));
  OK(ppohdem_engine_destroy(engine));
  engine = NULL;

  /* Arrays: a second material, a wall, an object (the cube's field), the fast engine. */
  OK(ppohdem_scene_add_material(scene, 2000, 1e7, 0.25, 0.6, 0.3, &material));
  CHECK(material == 1);
  FAILS(ppohdem_scene_add_particles(scene, 1, NULL, pos2, NULL, &radius2, &bad_material), PPOHDEM_ERR_ARGUMENT,
        "material[0]");
  OK(ppohdem_scene_add_particles(scene, 1, NULL, pos2, NULL, &radius2, &material));
  OK(ppohdem_scene_add_wall(scene, point, normal, NULL));
  FAILS(ppohdem_scene_add_wall(scene, NULL, normal, NULL), PPOHDEM_ERR_ARGUMENT, "point");
  OK(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &grid, "exact", phi, 125));
  OK(ppohdem_field_create(&grid, phi, 125, &field));
  OK(ppohdem_scene_add_object(scene, field, "cube", NULL, NULL, NULL));
  FAILS(ppohdem_scene_add_object(scene, NULL, "cube", NULL, NULL, NULL), PPOHDEM_ERR_ARGUMENT, "field");
  OK(ppohdem_field_destroy(field)); /* the scene holds a copy */
  OK(ppohdem_engine_create(scene, "fast", &engine));
  OK(ppohdem_engine_advance(engine, 10));
  OK(ppohdem_engine_particle_count(engine, &count));
  CHECK(count == 2);
  OK(ppohdem_engine_destroy(engine));
  OK(ppohdem_scene_destroy(scene));
  OK(ppohdem_scene_destroy(NULL));

  /* A TOML scene. */
  snprintf(path, sizeof path, "%s/scenes/two_spheres.toml", fixtures);
  OK(ppohdem_scene_read_toml(path, &toml));
  OK(ppohdem_scene_steps(toml, &steps));
  CHECK(steps == 40000);
  OK(ppohdem_scene_particle_count(toml, &count));
  CHECK(count == 2);
  OK(ppohdem_scene_destroy(toml));
  FAILS(ppohdem_scene_read_toml("/nonexistent/scene.toml", &toml), PPOHDEM_ERR_INPUT, "/nonexistent/scene.toml");
  FAILS(ppohdem_engine_step(NULL), PPOHDEM_ERR_ARGUMENT, "engine");
  OK(ppohdem_engine_destroy(NULL));
}

/* A motion program through the C API. The cube [-1,1]^3 (its exact field on 17^3 nodes over
 * [-2,2]^3: linear above the top face's middle, so the trilinear contact is a plane's) rests
 * for 0.01 s, then rises at v = 0.1 m/s and hits a sphere floating (no gravity) 0.01 m above
 * it, then stops at 0.3 s. An elastic (e = 1) impact with a face moving at v leaves the sphere
 * at 2 v. Tolerance 1e-6 relative: the Hertz contact lasts ~0.028 s = 280 steps of 1e-4 s, and
 * the integrator's error in the rebound speed is second order in dt / t_c (3e-8 here). */
static void test_motion_program(void) {
  const double gravity[3] = {0, 0, 0};
  ppohdem_grid grid = {{-2, -2, -2}, {0.25, 0.25, 0.25}, {17, 17, 17}};
  static double phi[17 * 17 * 17];
  ppohdem_field* field = NULL;
  ppohdem_scene* scene = NULL;
  ppohdem_engine* engine = NULL;
  const double pos[3] = {0.0, 0.0, 1.11}, radius = 0.1;
  double x[3], v[3];
  ppohdem_motion_segment program[3];
  memset(program, 0, sizeof program);
  program[0].type = PPOHDEM_MOTION_REST;
  program[0].start = 0.0;
  program[1].type = PPOHDEM_MOTION_TRANSLATE;
  program[1].start = 0.01;
  program[1].velocity[2] = 0.1;
  program[2].type = PPOHDEM_MOTION_REST;
  program[2].start = 0.3;

  OK(ppohdem_sdf_build_from_arrays(kCubeVertices, 8, kCubeTriangles, 12, &grid, "exact", phi, 17 * 17 * 17));
  OK(ppohdem_field_create(&grid, phi, 17 * 17 * 17, &field));
  OK(ppohdem_scene_create(1e-4, gravity, 2500, 1e7, 0.3, 1.0, 0.0, &scene));
  OK(ppohdem_scene_add_particles(scene, 1, NULL, pos, NULL, &radius, NULL));
  OK(ppohdem_scene_add_object_program(scene, field, "cube", NULL, program, 3));
  OK(ppohdem_engine_create(scene, "fast", &engine));
  OK(ppohdem_engine_advance(engine, 99)); /* t = 0.0099 s: the cube has not moved */
  OK(ppohdem_engine_read(engine, PPOHDEM_VELOCITY, v, 1));
  CHECK(v[0] == 0 && v[1] == 0 && v[2] == 0);
  OK(ppohdem_engine_advance(engine, 3901)); /* t = 0.4 s: the contact ended near 0.14 s */
  OK(ppohdem_engine_read(engine, PPOHDEM_VELOCITY, v, 1));
  OK(ppohdem_engine_read(engine, PPOHDEM_POSITION, x, 1));
  CHECK(fabs(v[2] - 0.2) < 1e-6 * 0.2);
  CHECK(v[0] == 0 && v[1] == 0 && x[0] == 0 && x[1] == 0);
  OK(ppohdem_engine_destroy(engine));

  /* Errors name the segment and the field. */
  program[1].start = 0.0;
  FAILS(ppohdem_scene_add_object_program(scene, field, "cube", NULL, program, 3), PPOHDEM_ERR_ARGUMENT, "segments[1].start");
  program[1].start = 0.01;
  program[1].type = PPOHDEM_MOTION_ROTATE; /* axis left zero */
  FAILS(ppohdem_scene_add_object_program(scene, field, "cube", NULL, program, 3), PPOHDEM_ERR_ARGUMENT, "segments[1].axis");
  program[1].type = PPOHDEM_MOTION_VIBRATE_TRANSLATE; /* frequency left zero */
  FAILS(ppohdem_scene_add_object_program(scene, field, "cube", NULL, program, 3), PPOHDEM_ERR_ARGUMENT, "segments[1].frequency");
  program[1].type = 9;
  FAILS(ppohdem_scene_add_object_program(scene, field, "cube", NULL, program, 3), PPOHDEM_ERR_ARGUMENT, "segments[1].type");
  FAILS(ppohdem_scene_add_object_program(scene, field, "cube", NULL, program, 0), PPOHDEM_ERR_ARGUMENT, "segment_count");
  FAILS(ppohdem_scene_add_object_program(scene, field, "cube", NULL, NULL, 3), PPOHDEM_ERR_ARGUMENT, "segments");
  OK(ppohdem_field_destroy(field));
  OK(ppohdem_scene_destroy(scene));
}

static void write_file(const char* path, const char* text) {
  FILE* f = fopen(path, "w");
  CHECK(f != NULL);
  if (f) {
    fputs(text, f);
    fclose(f);
  }
}

/* The ppohDEM-1.0 stages on a small grid (20^3 nodes over 44 m), in order and out of order. */
static void test_legacy(const char* fixtures, const char* work) {
  char path[1024], text[2048], prefix[1024], params[1024];
  ppohdem_util* util = NULL;
  ppohdem_legacy_dem* dem = NULL;
  ppohdem_legacy_parameters p;
  int32_t nodes[3];
  double length[3], size[3], position[3];
  size_t facets = 0;
  double* field = malloc(sizeof(double) * 76 * 76 * 76);
  int32_t* inside = malloc(sizeof(int32_t) * 76 * 76 * 76);
  int64_t itime = 0;
  double rtime = 0, pos_accum = 0, max_radius = 0;
  int32_t file_index = -1, done = -1;
  double positions[6] = {22 * 11.0 / 44, 5.5, 9.0, 4.0, 5.5, 9.0}, radius[2] = {0.1, 0.11};
  double got[6];
  int n, negative = 0, inside_count = 0;

  snprintf(path, sizeof path, "%s/input_constants_voxelizer.dat", work);
  snprintf(text, sizeof text, "%s/ppohdem-1.0/test-cube.stl\n%s/\n76 76 76\nLx_Ly_Lz: 44 44 44\n"
           "sizeX_sizeY_sizeZ: 6 6 6\nposX_posY_posZ: 22 22 16\n", fixtures, work);
  write_file(path, text);
  snprintf(prefix, sizeof prefix, "%s/", work);
  FAILS(ppohdem_util_create("/nonexistent/input.dat", 1, 0, &util), PPOHDEM_ERR_INPUT, "/nonexistent/input.dat");
  FAILS(ppohdem_util_create(path, 2, 2, &util), PPOHDEM_ERR_ARGUMENT, "rank");
  OK(ppohdem_util_create(path, 1, 0, &util));
  OK(ppohdem_util_input(util, nodes, length, size, position));
  CHECK(nodes[0] == 76 && length[1] == 44 && size[2] == 6 && position[2] == 16);
  FAILS(ppohdem_util_voxelize(util, prefix), PPOHDEM_ERR_STATE, "ppohDEM_v_pre");
  FAILS(ppohdem_util_facet_count(util, &facets), PPOHDEM_ERR_STATE, "ppohDEM_v_pre");
  FAILS(ppohdem_util_pass1(util), PPOHDEM_ERR_STATE, "ppohDEM_v_makevoxel");
  FAILS(ppohdem_util_field(util, field, NULL, 76 * 76 * 76), PPOHDEM_ERR_STATE, "makevoxel");
  OK(ppohdem_util_read_mesh(util));
  OK(ppohdem_util_facet_count(util, &facets));
  CHECK(facets == 12);
  OK(ppohdem_util_voxelize(util, prefix));
  FAILS(ppohdem_util_exact_band(util), PPOHDEM_ERR_STATE, "pass 1");
  FAILS(ppohdem_util_write(util, prefix), PPOHDEM_ERR_STATE, "MPI2");
  OK(ppohdem_util_pass1(util));
  OK(ppohdem_util_exact_band(util));
  OK(ppohdem_util_pass2(util));
  FAILS(ppohdem_util_field(util, field, inside, 10), PPOHDEM_ERR_BUFFER, "distance");
  OK(ppohdem_util_field(util, field, inside, 76 * 76 * 76));
  for (n = 0; n < 76 * 76 * 76; ++n) {
    negative += field[n] < 0;
    inside_count += inside[n] != 0;
  }
  /* The placed cube is [19,25]^2 x [13,19]; nodes at 44/76 (i-1): 10 x 10 x 11 strictly inside
   * or on faces in x, y and z (README of the original: 1,210 inside nodes). */
  CHECK(negative == 1210);
  CHECK(inside_count > 0 && inside_count <= negative);
  OK(ppohdem_util_write(util, prefix));
  OK(ppohdem_util_destroy(util));
  OK(ppohdem_util_destroy(NULL));

  /* The DEM stages, with 2 particles above the cube. */
  snprintf(params, sizeof params, "%s/ppohdem-1.0/dem-sample/input_params_update.dat", fixtures);
  OK(ppohdem_legacy_read_parameters(params, &p));
  CHECK(p.tfin == 300 && p.pnum == 600 && p.dstep == 500 && p.tstep == (double)2.0e-3f && p.obj_omega[3] == 1200);
  FAILS(ppohdem_legacy_read_parameters("/nonexistent/params.dat", &p), PPOHDEM_ERR_INPUT, "/nonexistent/params.dat");
  FAILS(ppohdem_legacy_dem_create(params, work, "newton", 2, positions, radius, &dem), PPOHDEM_ERR_ARGUMENT, "newton");
  FAILS(ppohdem_legacy_dem_create(params, "/nonexistent", NULL, 2, positions, radius, &dem), PPOHDEM_ERR_INPUT,
        "/nonexistent");
  OK(ppohdem_legacy_dem_create(params, work, NULL, 2, positions, radius, &dem));
  FAILS(ppohdem_legacy_dem_integrate(dem), PPOHDEM_ERR_STATE, "ppohDEM_update_index");
  FAILS(ppohdem_legacy_dem_check_update(dem, &done), PPOHDEM_ERR_STATE, "ppohDEM_update_index");
  FAILS(ppohdem_legacy_dem_dataout(dem, &done), PPOHDEM_ERR_STATE, "ppohDEM_update_index");
  FAILS(ppohdem_legacy_dem_check_objects(dem, &done), PPOHDEM_ERR_STATE, "ppohDEM_update_index");
  OK(ppohdem_legacy_dem_update_index(dem));
  snprintf(path, sizeof path, "%s/data", work);
  mkdir(path, 0755);
  snprintf(path, sizeof path, "%s/obj", work);
  mkdir(path, 0755);
  /* distance/ is missing: check_objects must say so at step 500. */
  for (n = 0; n < 500; ++n) {
    OK(ppohdem_legacy_dem_check_update(dem, NULL));
    OK(ppohdem_legacy_dem_integrate(dem));
    OK(ppohdem_legacy_dem_dataout(dem, &done));
  }
  CHECK(done == 1);
  FAILS(ppohdem_legacy_dem_check_objects(dem, &done), PPOHDEM_ERR_INPUT, "distance");
  snprintf(path, sizeof path, "%s/distance", work);
  mkdir(path, 0755);
  OK(ppohdem_legacy_dem_check_objects(dem, &done));
  CHECK(done == 1);
  OK(ppohdem_legacy_dem_counter(dem, &itime, &rtime, &file_index, &pos_accum));
  CHECK(itime == 500 && file_index == 1 && fabs(rtime - 500 * (double)2.0e-3f) < 1e-12);
  OK(ppohdem_legacy_dem_max_radius(dem, &max_radius));
  CHECK(max_radius == 0.11);
  FAILS(ppohdem_legacy_dem_particles(dem, got, NULL, NULL, NULL, 1), PPOHDEM_ERR_BUFFER, "count");
  OK(ppohdem_legacy_dem_particles(dem, got, NULL, NULL, NULL, 2));
  /* No contact in 1 s of fall: z = 9 - g t (t + dt) / 2 for symplectic Euler, g = 0.01 (float). */
  CHECK(fabs(got[2] - 9.0) < 0.01 && got[2] < 9.0);
  snprintf(path, sizeof path, "%s/data/out001.dat", work);
  CHECK(access(path, R_OK) == 0);
  snprintf(path, sizeof path, "%s/state.dat", work);
  OK(ppohdem_legacy_dem_write_state(dem, path));
  OK(ppohdem_legacy_dem_destroy(dem));
  /* corrected reads the distance data next to the params file (dem::read_legacy_scene). */
  snprintf(path, sizeof path, "%s/input_params_update.dat", work);
  write_file(path, "Lx_Ly_Lz: 11 11 11\nTime_finish: 300\nObj_n_x_y_z: 20 20 20\nObj_winstart_x_y_z: 28 28 28\n"
             "Obj_velocity_x_y_z: 0 0 0.005\nObj_omega_x_y_z: 0 0 1\nObj_omega_Pi_rad_per_w: 1200\n"
             "Obj_centroid_x_y_z: 22 22 11\n");
  OK(ppohdem_legacy_dem_create(path, work, "corrected", 2, positions, radius, &dem));
  snprintf(path, sizeof path, "%s/state.dat", work);
  OK(ppohdem_legacy_dem_update_index(dem));
  OK(ppohdem_legacy_dem_integrate(dem));
  OK(ppohdem_legacy_dem_dataout(dem, &done));
  CHECK(done == 0);
  FAILS(ppohdem_legacy_dem_write_state(dem, path), PPOHDEM_ERR_STATE, "ppohdem-1.0");
  OK(ppohdem_legacy_dem_destroy(dem));
  OK(ppohdem_legacy_dem_destroy(NULL));
  free(field);
  free(inside);
}

int main(int argc, char** argv) {
  char work[] = "/tmp/ppohdem_c_api_XXXXXX";
  if (argc != 2) {
    fprintf(stderr, "usage: c_api_test FIXTURES_DIR\n");
    return 2;
  }
  if (mkdtemp(work) == NULL) {
    perror("mkdtemp");
    return 2;
  }
  test_version();
  test_sdf(argv[1]);
  test_field();
  test_dem(argv[1], work);
  test_motion_program();
  test_legacy(argv[1], work);
  if (failures == 0) {
    char command[128];
    printf("c_api_test: all checks passed\n");
    snprintf(command, sizeof command, "rm -rf %s", work); /* kept for inspection on failure */
    if (system(command) != 0) fprintf(stderr, "could not remove %s\n", work);
  } else {
    fprintf(stderr, "c_api_test: %d checks failed; files in %s\n", failures, work);
  }
  return failures == 0 ? 0 : 1;
}
