// `ppohdem voxelize`: the seed's DEM-Util distance_calculate.
//
//   ppohdem voxelize input_constants_voxelizer.dat [--method exact|seed] [--ranks N] [--vtk F.vtk]
//       The seed's form: mesh on line 1, output directory on line 2, grid of n nodes per axis at
//       x = (L/n)(i-1); writes distance_NNNN.dat (the original layout) and object_mesh.stl.
//   ppohdem voxelize --mesh M.stl --cells NX NY NZ --box XMIN YMIN ZMIN XMAX YMAX ZMAX
//                    [--method exact|seed] --out F.vtk [--placement SX,SY,SZ,PX,PY,PZ]
//       Node (i,j,k) at min + (i,j,k) (max - min)/(N - 1); writes legacy VTK STRUCTURED_POINTS.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/mesh/placement.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/compat/ppohdem10_voxelizer.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"

namespace ppohdem::app {
namespace fs = std::filesystem;

namespace {

struct VoxelizeOptions {
  std::string legacy_input;  // positional: input_constants_voxelizer.dat
  std::string mesh;
  std::vector<int> cells;
  std::vector<double> box;
  std::vector<double> placement;
  std::string placement_mode = "fit";
  std::string method = "fast";
  int threads = 0;                  // 0: OpenMP default
  double band = 0.0;                // fast method: 0 = exact everywhere, W > 0 = exact within W h
  std::string precision = "double"; // fast method: double or float storage
  std::string out_vtk;
  int ranks = 1;
  std::string compat;  // "" (correct default) or "ppohdem-1.0" (the original, number for number)
  bool quiet = false;
};

PlacementMode parse_placement_mode(const std::string& name) {
  if (name == "fit") return PlacementMode::kUniformFit;
  if (name == "stretch") return PlacementMode::kPerAxis;
  if (name == "original") return PlacementMode::kPpohdem10;
  throw InputError("--placement-mode: expected fit, stretch or original, got '" + name + "'");
}

// Fail before a long computation if the output cannot be written: create and remove a probe.
void check_writable_directory(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw InputError(dir.string(), 0, "output directory does not exist");
  }
  AtomicFileWriter probe(dir / ".ppohdem-write-probe");
  // Destroyed without commit(): the probe file is removed again.
}

std::string human_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f s", s);
  return buf;
}

// Progress on stderr for grids over a million nodes (at most ~every 5 %).
SdfProgress make_progress(std::size_t nodes, bool quiet) {
  if (quiet || nodes <= 1000000) return {};
  auto last = std::make_shared<int>(-1);
  return [last](std::size_t done, std::size_t total) {
    const int percent = total == 0 ? 100 : static_cast<int>(100.0 * static_cast<double>(done) / static_cast<double>(total));
    if (percent / 5 != *last / 5 || percent == 100) {
      *last = percent;
      std::fprintf(stderr, "\rvoxelize: %3d %%", percent);
      if (percent == 100) std::fputc('\n', stderr);
      std::fflush(stderr);
    }
  };
}

struct BuildResult {
  ScalarField field;
  SdfReport report;
  double seconds = 0.0;
  std::size_t field_bytes = 0;  // the field as the builder stored it (float: half)
  std::size_t peak_bytes = 0;   // peak resident memory, max over ranks
};

// "fast" runs on every rank of `comm` (z-slabs, gathered on rank 0); the reference methods run
// on rank 0 only. Only rank 0's result holds the field.
BuildResult build_field(const TriangleMesh& mesh, const GridSpec& grid, const VoxelizeOptions& o, const Comm& comm) {
  BuildResult r;
  const auto t0 = std::chrono::steady_clock::now();
  if (o.method == "fast") {
    if (o.precision != "double" && o.precision != "float") {
      throw InputError("--precision: expected double or float, got '" + o.precision + "'");
    }
    if (o.threads < 0) throw InputError("--threads must be >= 0 (0: all cores)");
    sdf::fast::FastSdfOptions options;
    options.threads = o.threads;
    if (!(o.band >= 0.0)) throw InputError("--band must be >= 0 cells (0: exact everywhere)");
    options.band_cells = o.band;
    sdf::fast::FastSdfBuilder builder(options);
    if (comm.rank() == 0) builder.set_progress(make_progress(grid.node_count(), o.quiet));
    if (o.precision == "float") {
      const std::vector<float> values = sdf::fast::build_sdf_distributed_float(builder, comm, mesh, grid, &r.report);
      r.field_bytes = values.size() * sizeof(float);
      r.field.grid = grid;
      r.field.values.assign(values.begin(), values.end());  // the writers take doubles
    } else {
      r.field = sdf::fast::build_sdf_distributed(builder, comm, mesh, grid, &r.report);
      r.field_bytes = r.field.values.size() * sizeof(double);
    }
  } else {
    if (o.band != 0.0) throw InputError("--band applies to --method fast only");
    if (comm.size() > 1) throw InputError("--method " + o.method + " is serial: run it without mpirun, or use --method fast");
    auto builder = sdf::reference::make_reference_sdf_builder(o.method);
    builder->set_progress(make_progress(grid.node_count(), o.quiet));
    r.field = builder->build(mesh, grid, &r.report);
    r.field_bytes = r.field.values.size() * sizeof(double);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.peak_bytes = static_cast<std::size_t>(comm.max_over_ranks(static_cast<double>(peak_resident_bytes())));
  return r;
}

// "fast", or "fast (exact within W h, transfer beyond)" in band mode.
std::string method_label(const VoxelizeOptions& o) {
  if (o.method != "fast" || o.band == 0.0) return o.method;
  std::ostringstream label;
  label << o.method << " (band " << o.band << " h: exact within, closest-triangle transfer beyond)";
  return label.str();
}

// What the warnings below need from the mesh. Not compute_mesh_stats(): its vertex welding and
// edge sort would be a second serial pass over the topology, which the fast builder's sign
// already makes (docs/performance.md "The whole voxelize process").
struct GeometryFacts {
  BoundingBox box;
  std::size_t degenerate_triangles = 0;  // exactly zero area, as MeshStats counts them
};

GeometryFacts geometry_facts(const TriangleMesh& mesh) {
  GeometryFacts facts;
  facts.box = bounding_box(mesh);
  for (const Triangle& t : mesh.triangles) facts.degenerate_triangles += t.area_vector() == Vec3::Zero() ? 1 : 0;
  return facts;
}

// Warnings that do not depend on the builder: degenerate triangles, a mesh sticking out of the grid.
void add_geometry_warnings(const GridSpec& grid, const GeometryFacts& stats, SdfReport& report) {
  BoundingBox grid_box;
  grid_box.expand(grid.origin);
  grid_box.expand(grid.upper_corner());
  if (!grid_box.contains(stats.box)) {
    report.warnings.push_back("the grid box does not contain the whole mesh (distances are still exact)");
  }
  if (stats.degenerate_triangles > 0) {
    report.warnings.push_back(std::to_string(stats.degenerate_triangles) + " zero-area triangles");
  }
}

void print_summary(const GridSpec& grid, const TriangleMesh& mesh, const BuildResult& r,
                   const std::string& method, const std::vector<std::string>& outputs) {
  std::vector<std::string> warnings = r.report.warnings;
  std::printf("voxelize: method %s, %zu nodes (%d x %d x %d), %zu triangles, %s, inside fraction %.4f",
              method.c_str(), grid.node_count(), grid.nodes[0], grid.nodes[1], grid.nodes[2],
              mesh.size(), human_seconds(r.seconds).c_str(), r.report.inside_fraction);
  for (const auto& w : warnings) std::printf("; warning: %s", w.c_str());
  std::printf("\n");
  std::printf("voxelize: memory: field %.1f MiB, peak resident %.1f MiB (max over ranks)\n",
              static_cast<double>(r.field_bytes) / 1048576.0, static_cast<double>(r.peak_bytes) / 1048576.0);
  for (const auto& o : outputs) std::printf("voxelize: wrote %s\n", o.c_str());
}

TriangleMesh read_mesh_checked(const fs::path& path) {
  StlReadReport read_report;
  TriangleMesh mesh = read_stl(path, &read_report);
  if (mesh.empty()) throw InputError(path.string(), 0, "the mesh has no triangles");
  return mesh;
}

// Relative paths in the legacy file are tried against the input file's directory first, then
// against the current directory (where the original program resolved them).
fs::path resolve_legacy_base(const fs::path& input_file, const std::string& mesh_entry) {
  const fs::path input_dir = input_file.has_parent_path() ? input_file.parent_path() : fs::path(".");
  if (fs::path(mesh_entry).is_absolute()) return input_dir;
  if (fs::exists(input_dir / mesh_entry)) return input_dir;
  if (fs::exists(fs::current_path() / mesh_entry)) return fs::current_path();
  throw InputError(input_file.string(), 1,
                   "mesh file '" + mesh_entry + "' not found (looked in '" + input_dir.string() +
                       "' and in the current directory)");
}

// `--compat ppohdem-1.0`: the original program's algorithm as it really is (reference/compat/,
// docs/compat.md), including its defects, with the original's placement; byte-identical
// distance_NNNN.dat files for the same --ranks.
void run_legacy_compat(const VoxelizeOptions& o, const VoxelizerInput& in, const fs::path& mesh_path,
                       const fs::path& out_dir) {
  const TriangleMesh raw = read_mesh_checked(mesh_path);
  Placement placement;
  placement.size = in.object_size;
  placement.position = in.object_position;
  placement.mode = PlacementMode::kPpohdem10;
  const TriangleMesh mesh = place_mesh(raw, placement);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<double> values = compat::ppohdem10_distance(mesh, in, o.ranks);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_distance_dat(out_dir, values, in.voxels, o.ranks);
  write_stl(out_dir / "object_mesh.stl", mesh, StlEncoding::kAscii, /*use_file_normals=*/true);
  std::printf("voxelize: compat ppohdem-1.0, %d x %d x %d nodes, %zu triangles, %s, %d rank file(s)\n",
              in.voxels[0], in.voxels[1], in.voxels[2], mesh.size(), human_seconds(seconds).c_str(), o.ranks);
  for (int rank = 0; rank < o.ranks; ++rank) {
    std::printf("voxelize: wrote %s\n", distance_dat_path(out_dir, rank).string().c_str());
  }
  std::printf("voxelize: wrote %s\n", (out_dir / "object_mesh.stl").string().c_str());
}

void run_legacy(const VoxelizeOptions& o, const Comm& comm) {
  const fs::path input_file(o.legacy_input);
  const VoxelizerInput in = read_voxelizer_input(input_file);
  const fs::path base = resolve_legacy_base(input_file, in.mesh_file);
  const fs::path mesh_path = base / in.mesh_file;
  const fs::path out_dir = base / in.output_dir;
  check_writable_directory(out_dir);
  if (o.ranks < 1) throw InputError("--ranks must be >= 1");
  if (!o.compat.empty()) {
    if (o.compat != "ppohdem-1.0") throw InputError("--compat: the only mode is ppohdem-1.0, got '" + o.compat + "'");
    if (comm.rank() == 0) run_legacy_compat(o, in, mesh_path, out_dir);
    return;
  }

  const TriangleMesh raw = read_mesh_checked(mesh_path);
  Placement placement;
  placement.size = in.object_size;
  placement.position = in.object_position;
  placement.mode = parse_placement_mode(o.placement_mode);
  const TriangleMesh mesh = place_mesh(raw, placement);
  const GeometryFacts stats = geometry_facts(mesh);
  const GridSpec grid = GridSpec::ppohdem_legacy(in.length, in.voxels);
  grid.validate(input_file.string());

  BuildResult r = build_field(mesh, grid, o, comm);
  if (comm.rank() != 0) return;  // rank 0 holds the field and writes the files
  add_geometry_warnings(grid, stats, r.report);

  if (o.ranks > grid.nodes[0]) {
    throw InputError("--ranks " + std::to_string(o.ranks) + " exceeds the " + std::to_string(grid.nodes[0]) +
                     " x-planes to split");
  }
  write_distance_dat(out_dir, r.field.values, grid.nodes, o.ranks);
  std::vector<std::string> outputs;
  for (int rank = 0; rank < o.ranks; ++rank) outputs.push_back(distance_dat_path(out_dir, rank).string());
  write_stl(out_dir / "object_mesh.stl", mesh, StlEncoding::kAscii, /*use_file_normals=*/true);
  outputs.push_back((out_dir / "object_mesh.stl").string());
  if (!o.out_vtk.empty()) {
    write_vtk_structured_points(o.out_vtk, r.field, "distance", provenance_line(comm.size(), o.threads));
    outputs.push_back(o.out_vtk);
  }
  print_summary(grid, mesh, r, method_label(o), outputs);
}

void run_modern(const VoxelizeOptions& o, const Comm& comm) {
  if (o.mesh.empty() || o.cells.size() != 3 || o.box.size() != 6 || o.out_vtk.empty()) {
    throw InputError(
        "voxelize: give either an input_constants_voxelizer.dat file, or all of --mesh, --cells NX NY NZ, "
        "--box XMIN YMIN ZMIN XMAX YMAX ZMAX and --out F.vtk");
  }
  for (int a = 0; a < 3; ++a) {
    if (o.cells[a] < 2) {
      throw InputError("--cells: every count must be >= 2 (nodes per axis), got " + std::to_string(o.cells[a]));
    }
    if (!(o.box[a + 3] > o.box[a])) {
      throw InputError("--box: max must exceed min on every axis (axis " + std::to_string(a) + ")");
    }
  }
  const fs::path out(o.out_vtk);
  check_writable_directory(out.has_parent_path() ? out.parent_path() : fs::path("."));

  TriangleMesh mesh = read_mesh_checked(o.mesh);
  if (!o.placement.empty()) {
    if (o.placement.size() != 6) throw InputError("--placement: expected SX,SY,SZ,PX,PY,PZ (6 numbers)");
    Placement p;
    p.size = Vec3(o.placement[0], o.placement[1], o.placement[2]);
    p.position = Vec3(o.placement[3], o.placement[4], o.placement[5]);
    p.mode = parse_placement_mode(o.placement_mode);
    mesh = place_mesh(mesh, p);
  }
  const GeometryFacts stats = geometry_facts(mesh);
  const GridSpec grid = GridSpec::spanning(Vec3(o.box[0], o.box[1], o.box[2]),
                                           Vec3(o.box[3], o.box[4], o.box[5]),
                                           {o.cells[0], o.cells[1], o.cells[2]});
  BuildResult r = build_field(mesh, grid, o, comm);
  if (comm.rank() != 0) return;  // rank 0 holds the field and writes the files
  add_geometry_warnings(grid, stats, r.report);
  write_vtk_structured_points(out, r.field, "distance", provenance_line(comm.size(), o.threads));
  print_summary(grid, mesh, r, method_label(o), {out.string()});
}

}  // namespace

void register_voxelize(CLI::App& app, const Comm& comm) {
  auto o = std::make_shared<VoxelizeOptions>();
  auto* cmd = app.add_subcommand("voxelize", "Signed distance of an STL mesh on a grid (DEM-Util distance_calculate)");
  cmd->add_option("input", o->legacy_input, "input_constants_voxelizer.dat (the seed's form)");
  cmd->add_option("--mesh", o->mesh, "STL mesh (ASCII or binary)");
  cmd->add_option("--cells", o->cells, "node counts NX NY NZ")->expected(3);
  cmd->add_option("--box", o->box, "grid box XMIN YMIN ZMIN XMAX YMAX ZMAX")->expected(6);
  cmd->add_option("--placement", o->placement, "scale/centre the mesh first: SX,SY,SZ,PX,PY,PZ")
      ->expected(6)
      ->delimiter(',');
  cmd->add_option("--placement-mode", o->placement_mode, "fit (uniform, default), stretch (per axis) or original");
  cmd->add_option("--method", o->method, "fast (default; OpenMP + MPI), exact or seed (reference, serial)");
  cmd->add_option("--threads", o->threads, "fast: OpenMP threads per rank (0 = all cores)");
  cmd->add_option("--band", o->band,
                  "fast: exact within W cells of the surface, closest-triangle transfer beyond (0 = exact everywhere)");
  cmd->add_option("--precision", o->precision, "fast: field storage, double (default) or float (half the memory)");
  cmd->add_option("--out", o->out_vtk, "output legacy VTK file (modern form)");
  cmd->add_option("--vtk", o->out_vtk, "also write a VTK file (legacy form)");
  cmd->add_option("--ranks", o->ranks, "legacy form: split distance_NNNN.dat as N MPI ranks would");
  cmd->add_option("--compat", o->compat,
                  "ppohdem-1.0: reproduce the original program's output number for number (legacy form)");
  cmd->add_flag("--quiet", o->quiet, "no progress output");
  cmd->callback([o, &comm] {
    if (!o->legacy_input.empty()) {
      if (!o->mesh.empty() || !o->cells.empty() || !o->box.empty()) {
        throw InputError("voxelize: give either a legacy input file or --mesh/--cells/--box, not both");
      }
      run_legacy(*o, comm);
    } else {
      if (!o->compat.empty()) throw InputError("--compat applies to the legacy form (input_constants_voxelizer.dat)");
      run_modern(*o, comm);
    }
  });
}

}  // namespace ppohdem::app
