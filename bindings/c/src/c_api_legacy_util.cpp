// The C API's ppohDEM-1.0 DEM-Util stages (ppohdem.h "ppohDEM-1.0 library stages"): the
// original's pipeline from reference/compat, one call per library subroutine, so that the
// Fortran module ppohDEM_util (DEM-Util) can keep the original's call sequence.
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "c_api_guard.hpp"
#include "ppohdem/compat/ppohdem10_voxelizer.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/mesh/placement.hpp"
#include "ppohdem/mesh/stl_io.hpp"

using namespace ppohdem;
using namespace ppohdem::c_api;

struct ppohdem_util {
  VoxelizerInput input;
  std::string input_file;
  int nprocs = 1;
  int rank = 0;
  std::optional<TriangleMesh> raw_mesh;
  std::unique_ptr<compat::Ppohdem10VoxelizerStages> stages;
};

namespace {

ppohdem_util& util_of(ppohdem_util* u) { return require(u, "util"); }

// A stage out of order is a StateError naming what is missing.
template <class Stage>
void run_stage(ppohdem_util& u, const char* needs, Stage&& stage) {
  if (!u.stages) throw StateError(std::string("needs ") + needs + " first");
  try {
    stage(*u.stages);
  } catch (const std::logic_error& e) {
    throw StateError(e.what());
  }
}

// The original writes file_info%output_filename // "distance_NNNN.dat": line 2 is a prefix.
std::string prefixed(const char* prefix, const std::string& name) {
  return std::string(prefix == nullptr ? "" : prefix) + name;
}

void write_text(const std::string& path, const std::string& text) {
  AtomicFileWriter out(path);
  out.stream() << text;
  out.commit();
}

}  // namespace

extern "C" {

ppohdem_status ppohdem_util_create(const char* input_file, int32_t nprocs, int32_t rank, ppohdem_util** util) {
  return guarded(__func__, [&] {
    require(util, "util") = nullptr;
    if (nprocs < 1 || rank < 0 || rank >= nprocs) {
      throw ArgumentError("expected 0 <= rank < nprocs, got rank " + std::to_string(rank) + " of " +
                          std::to_string(nprocs));
    }
    auto handle = std::make_unique<ppohdem_util>();
    handle->input_file = require_text(input_file, "input_file");
    handle->input = read_voxelizer_input(handle->input_file);
    handle->nprocs = nprocs;
    handle->rank = rank;
    *util = handle.release();
  });
}

ppohdem_status ppohdem_util_destroy(ppohdem_util* util) {
  delete util;
  return PPOHDEM_OK;
}

ppohdem_status ppohdem_util_input(const ppohdem_util* util, int32_t nodes[3], double length[3], double size[3],
                                  double position[3]) {
  return guarded(__func__, [&] {
    const ppohdem_util& u = require(util, "util");
    for (int a = 0; a < 3; ++a) {
      if (nodes != nullptr) nodes[a] = u.input.voxels[static_cast<std::size_t>(a)];
      if (length != nullptr) length[a] = u.input.length[a];
      if (size != nullptr) size[a] = u.input.object_size[a];
      if (position != nullptr) position[a] = u.input.object_position[a];
    }
  });
}

ppohdem_status ppohdem_util_read_mesh(ppohdem_util* util) {
  return guarded(__func__, [&] {
    ppohdem_util& u = util_of(util);
    // The original opens line 1 as written, relative to the working directory.
    u.raw_mesh = read_stl(u.input.mesh_file);
  });
}

ppohdem_status ppohdem_util_facet_count(const ppohdem_util* util, size_t* count) {
  return guarded(__func__, [&] {
    const ppohdem_util& u = require(util, "util");
    if (!u.raw_mesh) throw StateError("needs the mesh (ppohDEM_v_pre) first");
    require(count, "count") = u.raw_mesh->size();
  });
}

ppohdem_status ppohdem_util_voxelize(ppohdem_util* util, const char* out_prefix) {
  return guarded(__func__, [&] {
    ppohdem_util& u = util_of(util);
    if (!u.raw_mesh) throw StateError("needs the mesh (ppohDEM_v_pre) first");
    if (u.stages) throw StateError("the voxelisation has already run");
    Placement placement;
    placement.size = u.input.object_size;
    placement.position = u.input.object_position;
    placement.mode = PlacementMode::kPpohdem10;
    const TriangleMesh placed = place_mesh(*u.raw_mesh, placement);
    if (u.rank == 0) {
      write_text(prefixed(out_prefix, "object_mesh.stl"), compat::ppohdem10_object_mesh_stl(placed));
    }
    u.stages = std::make_unique<compat::Ppohdem10VoxelizerStages>(placed, u.input, u.nprocs);
    u.stages->voxelize();
  });
}

ppohdem_status ppohdem_util_pass1(ppohdem_util* util) {
  return guarded(__func__, [&] {
    run_stage(util_of(util), "the voxelisation (ppohDEM_v_makevoxel)", [](auto& s) { s.pass1(); });
  });
}

ppohdem_status ppohdem_util_exact_band(ppohdem_util* util) {
  return guarded(__func__, [&] {
    run_stage(util_of(util), "the voxelisation (ppohDEM_v_makevoxel)", [](auto& s) { s.exact_band(); });
  });
}

ppohdem_status ppohdem_util_pass2(ppohdem_util* util) {
  return guarded(__func__, [&] {
    run_stage(util_of(util), "the voxelisation (ppohDEM_v_makevoxel)", [](auto& s) { s.pass2(); });
  });
}

ppohdem_status ppohdem_util_write(const ppohdem_util* util, const char* out_prefix) {
  return guarded(__func__, [&] {
    const ppohdem_util& u = require(util, "util");
    if (!u.stages || u.stages->stages_done() < 4) {
      throw StateError("needs pass 2 (ppohDEM_v_distancecalculate_MPI2) first");
    }
    char name[32];
    std::snprintf(name, sizeof name, "distance_%04d.dat", u.rank);
    // output_data: file_info%output_filename // "distance_NNNN.dat", this rank's planes only.
    write_distance_dat_rank(prefixed(out_prefix, name), u.stages->distance(), u.input.voxels, u.nprocs, u.rank);
  });
}

ppohdem_status ppohdem_util_field(const ppohdem_util* util, double* distance, int32_t* inside, size_t count) {
  return guarded(__func__, [&] {
    const ppohdem_util& u = require(util, "util");
    if (!u.stages) throw StateError("needs the voxelisation (ppohDEM_v_makevoxel) first");
    const std::vector<double> values = u.stages->distance();
    require_capacity(count, values.size(), "distance (count)");
    if (distance != nullptr) std::memcpy(distance, values.data(), values.size() * sizeof(double));
    if (inside != nullptr) {
      const auto& flags = u.stages->trace().voxel_inside;
      for (std::size_t n = 0; n < flags.size(); ++n) inside[n] = flags[n];
    }
  });
}

}  // extern "C"
