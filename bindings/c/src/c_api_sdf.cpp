// The C API's signed distance fields (ppohdem.h "signed distance fields"): builders from the
// reference (exact, seed) and fast implementations, and trilinear queries of a field.
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "c_api_handles.hpp"
#include "ppohdem/grid/trilinear.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/sdf/reference/builders.hpp"

using namespace ppohdem;
using namespace ppohdem::c_api;

namespace {

std::unique_ptr<SdfBuilder> builder_named(const char* method) {
  const std::string name = method == nullptr ? "fast" : method;
  if (name == "fast") return sdf::fast::make_fast_sdf_builder();
  if (name == "exact" || name == "seed") return sdf::reference::make_reference_sdf_builder(name);
  throw ArgumentError("method: expected \"fast\", \"exact\" or \"seed\", got \"" + name + "\"");
}

void build_into(const TriangleMesh& mesh, const ppohdem_grid* grid, const char* method, double* out,
                std::size_t out_count) {
  const GridSpec spec = grid_spec_of(require(grid, "grid"));
  require(out, "out");
  require_capacity(out_count, spec.node_count(), "out");
  const ScalarField field = builder_named(method)->build(mesh, spec);
  std::memcpy(out, field.values.data(), field.values.size() * sizeof(double));
}

}  // namespace

extern "C" {

ppohdem_status ppohdem_sdf_build_from_file(const char* mesh_path, const ppohdem_grid* grid, const char* method,
                                           double* out, size_t out_count) {
  return guarded(__func__, [&] {
    const TriangleMesh mesh = read_stl(require_text(mesh_path, "mesh_path"));
    build_into(mesh, grid, method, out, out_count);
  });
}

ppohdem_status ppohdem_sdf_build_from_arrays(const double* vertices, size_t vertex_count, const int32_t* triangles,
                                             size_t triangle_count, const ppohdem_grid* grid, const char* method,
                                             double* out, size_t out_count) {
  return guarded(__func__, [&] {
    require(vertices, "vertices");
    require(triangles, "triangles");
    if (triangle_count == 0) throw ArgumentError("triangle_count is 0: a mesh needs triangles");
    TriangleMesh mesh;
    mesh.triangles.resize(triangle_count);
    for (std::size_t t = 0; t < triangle_count; ++t) {
      for (int c = 0; c < 3; ++c) {
        const int32_t v = triangles[3 * t + static_cast<std::size_t>(c)];
        if (v < 0 || static_cast<std::size_t>(v) >= vertex_count) {
          throw ArgumentError("triangles[" + std::to_string(3 * t + static_cast<std::size_t>(c)) + "] = " +
                              std::to_string(v) + ": expected a vertex index in [0, " +
                              std::to_string(vertex_count) + ")");
        }
        const double* p = vertices + 3 * static_cast<std::size_t>(v);
        mesh.triangles[t].v[static_cast<std::size_t>(c)] = Vec3(p[0], p[1], p[2]);
      }
    }
    build_into(mesh, grid, method, out, out_count);
  });
}

ppohdem_status ppohdem_field_create(const ppohdem_grid* grid, const double* values, size_t value_count,
                                    ppohdem_field** field) {
  return guarded(__func__, [&] {
    require(field, "field") = nullptr;
    const GridSpec spec = grid_spec_of(require(grid, "grid"));
    require(values, "values");
    if (value_count != spec.node_count()) {
      throw ArgumentError("value_count is " + std::to_string(value_count) + ", the grid has " +
                          std::to_string(spec.node_count()) + " nodes");
    }
    auto handle = std::make_unique<ppohdem_field>();
    handle->field = ScalarField(spec);
    std::memcpy(handle->field.values.data(), values, value_count * sizeof(double));
    *field = handle.release();
  });
}

ppohdem_status ppohdem_field_destroy(ppohdem_field* field) {
  delete field;
  return PPOHDEM_OK;
}

ppohdem_status ppohdem_field_query(const ppohdem_field* field, const double* points, size_t count, double* phi,
                                   double* gradient, size_t* outside) {
  return guarded(__func__, [&] {
    const ppohdem_field& f = require(field, "field");
    require(points, "points");
    require(phi, "phi");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::size_t missed = 0;
    for (std::size_t n = 0; n < count; ++n) {
      const auto sample = sample_trilinear(f.field, Vec3(points[3 * n], points[3 * n + 1], points[3 * n + 2]));
      if (!sample) ++missed;
      phi[n] = sample ? sample->value : nan;
      if (gradient != nullptr) {
        for (int a = 0; a < 3; ++a) gradient[3 * n + static_cast<std::size_t>(a)] = sample ? sample->gradient[a] : nan;
      }
    }
    if (outside != nullptr) *outside = missed;
  });
}

}  // extern "C"
