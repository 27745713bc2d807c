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
#include "ppohdem10_dem_format.hpp"

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

// output_object_mesh: the placed mesh with the file's facet normals, every line written
// list-directed (one leading blank; reals with 17 significant digits), e.g.
// "        vertex 24.999997000001500 24.999999700000149 13.000000000000000".
void write_original_object_mesh(const std::string& path, const TriangleMesh& placed) {
  using compat::fortran::list_directed_real;
  auto three = [](const Vec3& v) {
    return list_directed_real(v.x()) + ' ' + list_directed_real(v.y()) + ' ' + list_directed_real(v.z());
  };
  std::string text = " solid Object01 \n";
  for (const Triangle& t : placed.triangles) {
    text += "   facet normal " + three(t.file_normal) + "\n";
    text += "     outer loop \n";
    for (const Vec3& v : t.v) text += "        vertex " + three(v) + "\n";
    text += "     endloop \n";
    text += "   endfacet \n";
  }
  text += " endsolid Object01 \n";
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
      write_original_object_mesh(prefixed(out_prefix, "object_mesh.stl"), placed);
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
    const std::vector<double> values = u.stages->distance();
    const Index3& n = u.input.voxels;
    char name[32];
    std::snprintf(name, sizeof name, "distance_%04d.dat", u.rank);
    AtomicFileWriter writer(prefixed(out_prefix, name));
    std::string text;
    char line[64];
    // output_data: rank 0 writes the header (4i8), then every rank its own x-planes as
    // (3I8,1E20.8), k outer, j, i inner (docs/formats.md).
    if (u.rank == 0) {
      std::snprintf(line, sizeof line, "%8d%8d%8d%8d\n", n[0], n[1], n[2], u.nprocs);
      text += line;
    }
    const DistanceDatSlab slab = distance_dat_slab(n[0], u.nprocs, u.rank);
    for (int k = 0; k < n[2]; ++k) {
      for (int j = 0; j < n[1]; ++j) {
        for (int i = slab.first_plane; i < slab.first_plane + slab.plane_count; ++i) {
          std::snprintf(line, sizeof line, "%8d%8d%8d", i + 1, j + 1, k + 1);
          text += line;
          text += format_fortran_e20_8(values[static_cast<std::size_t>(i) +
                                              static_cast<std::size_t>(n[0]) *
                                                  (static_cast<std::size_t>(j) +
                                                   static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k))]);
          text += '\n';
        }
      }
    }
    writer.stream() << text;
    writer.commit();
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
