// Signed distance fields (docs/python.md "Signed distance fields"): the builders of
// `ppohdem voxelize`, the field with a NumPy view of its nodes, and the stages of the
// reference pipeline for teaching (ray parity, winding number, fast sweeping).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#ifdef PPOHDEM_WITH_OPENMP
#include <omp.h>
#endif

#include "common.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/grid/trilinear.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/provenance.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "ppohdem/sdf/reference/builders.hpp"
#include "ppohdem/sdf/reference/fast_sweeping.hpp"
#include "ppohdem/sdf/reference/ray_parity.hpp"
#include "ppohdem/sdf/reference/winding_number.hpp"
#include "ppohdem/sdf/signed_distance.hpp"
#include "py_field.hpp"

namespace ppohdem::python {
namespace {

namespace fs = std::filesystem;

struct PyMesh {
  std::shared_ptr<const TriangleMesh> mesh;
};

PyField build_field(const py::object& mesh_arg, const std::array<int, 3>& cells, const std::array<double, 6>& box,
                    const std::string& method, double band, int threads) {
  const GridSpec grid = grid_from_cells_box(cells, box);
  const TriangleMesh mesh = mesh_from(mesh_arg);
  if (mesh.empty()) throw InputError("sdf.build: the mesh has no triangles");
  PyField f;
  f.threads = threads;
  f.method = method;
  py::gil_scoped_release release;
  if (method == "fast") {
    if (threads < 0) throw InputError("sdf.build: threads must be >= 0 (0: all cores)");
    if (!(band >= 0.0)) throw InputError("sdf.build: band must be >= 0 cells (0: exact everywhere)");
    sdf::fast::FastSdfOptions options;
    options.threads = threads;
    options.band_cells = band;
    f.field = std::make_shared<ScalarField>(sdf::fast::FastSdfBuilder(options).build(mesh, grid, &f.report));
  } else {
    if (band != 0.0) throw InputError("sdf.build: band applies to method=\"fast\" only");
    auto builder = sdf::reference::make_reference_sdf_builder(method);
    f.field = std::make_shared<ScalarField>(builder->build(mesh, grid, &f.report));
  }
  return f;
}

py::array bool_grid(const std::vector<bool>& inside, const GridSpec& grid) {
  // (nx, ny, nz) in Fortran order so that a[i, j, k] is node (i, j, k), as Field.values.
  py::array_t<bool, py::array::f_style> out({grid.nodes[0], grid.nodes[1], grid.nodes[2]});
  bool* w = out.mutable_data();
  for (std::size_t n = 0; n < inside.size(); ++n) w[n] = inside[n];
  return out;
}

}  // namespace

void bind_sdf(py::module_& sdf) {
  py::class_<PyMesh>(sdf, "Mesh", "A triangle mesh (STL), vertices counter-clockwise seen from outside")
      .def_static(
          "load", [](const fs::path& path) { return PyMesh{std::make_shared<TriangleMesh>(read_stl(path))}; },
          py::arg("path"), "Read an STL file (ASCII or binary)")
      .def_static(
          "from_triangles",
          [](py::array_t<double, py::array::c_style | py::array::forcecast> t) {
            if (t.ndim() != 3 || t.shape(1) != 3 || t.shape(2) != 3) {
              throw InputError("Mesh.from_triangles: expected an array of shape (T, 3, 3)");
            }
            auto mesh = std::make_shared<TriangleMesh>();
            auto r = t.unchecked<3>();
            for (py::ssize_t k = 0; k < t.shape(0); ++k) {
              Triangle tri;
              for (int v = 0; v < 3; ++v) tri.v[v] = Vec3(r(k, v, 0), r(k, v, 1), r(k, v, 2));
              mesh->triangles.push_back(tri);
            }
            return PyMesh{mesh};
          },
          py::arg("triangles"))
      .def_property_readonly("triangles",
                             [](const PyMesh& m) {
                               py::array_t<double> out({static_cast<py::ssize_t>(m.mesh->size()), py::ssize_t{3}, py::ssize_t{3}});
                               auto w = out.mutable_unchecked<3>();
                               for (std::size_t k = 0; k < m.mesh->size(); ++k) {
                                 for (int v = 0; v < 3; ++v) {
                                   for (int c = 0; c < 3; ++c) w(static_cast<py::ssize_t>(k), v, c) = m.mesh->triangles[k].v[v][c];
                                 }
                               }
                               return out;
                             },
                             "(T, 3, 3) float64 copy of the vertices")
      .def("save_stl", [](const PyMesh& m, const fs::path& path) { write_stl(path, *m.mesh, StlEncoding::kBinary); }, py::arg("path"))
      .def("__len__", [](const PyMesh& m) { return m.mesh->size(); });

  py::class_<PyField>(sdf, "Field", "A scalar field on a regular grid of nodes (phi < 0 inside)")
      .def_property_readonly("values",
                             [](py::object self) {
                               const PyField& f = self.cast<const PyField&>();
                               const Index3 n = f.field->grid.nodes;
                               const auto s = static_cast<py::ssize_t>(sizeof(double));
                               return readonly_view<double>(f.field->values.data(), {n[0], n[1], n[2]},
                                                            {s, s * n[0], s * n[0] * n[1]}, self);
                             },
                             "(nx, ny, nz) view of the node values: values[i, j, k] at origin + (i, j, k) * spacing")
      .def_property_readonly("origin", [](const PyField& f) { const Vec3 o = f.field->grid.origin; return py::make_tuple(o.x(), o.y(), o.z()); })
      .def_property_readonly("spacing", [](const PyField& f) { const Vec3 h = f.field->grid.spacing; return py::make_tuple(h.x(), h.y(), h.z()); })
      .def_property_readonly("shape", [](const PyField& f) { const Index3 n = f.field->grid.nodes; return py::make_tuple(n[0], n[1], n[2]); })
      .def_property_readonly("method", [](const PyField& f) { return f.method; })
      .def_property_readonly("warnings", [](const PyField& f) { return f.report.warnings; })
      .def_property_readonly("inside_fraction", [](const PyField& f) { return f.report.inside_fraction; })
      .def(
          "query",
          [](const PyField& f, const py::object& points) {
            const std::vector<Vec3> p = points_from(points);
            const auto m = static_cast<py::ssize_t>(p.size());
            py::array_t<double> phi(m);
            py::array_t<double> grad({m, py::ssize_t{3}});
            auto wp = phi.mutable_unchecked<1>();
            auto wg = grad.mutable_unchecked<2>();
            const double nan = std::numeric_limits<double>::quiet_NaN();
            for (py::ssize_t k = 0; k < m; ++k) {
              const std::optional<FieldSample> s = sample_trilinear(*f.field, p[static_cast<std::size_t>(k)]);
              wp(k) = s ? s->value : nan;
              for (int c = 0; c < 3; ++c) wg(k, c) = s ? s->gradient[c] : nan;
            }
            return py::make_tuple(phi, grad);
          },
          py::arg("points"),
          "phi (M,) and grad phi (M, 3) at (M, 3) points by the engines' trilinear interpolation; NaN outside the grid")
      .def(
          "save_vtk",
          [](const PyField& f, const fs::path& path, std::optional<std::string> header) {
            // The title `ppohdem voxelize --out` writes: the run header (provenance.hpp).
            write_vtk_structured_points(path, *f.field, "distance", header ? *header : provenance_line(1, f.threads));
          },
          py::arg("path"), py::arg("header") = py::none(),
          "Write legacy VTK STRUCTURED_POINTS, as `ppohdem voxelize --out`; header replaces the title line")
      .def_static(
          "from_array",
          [](py::array_t<double, py::array::f_style | py::array::forcecast> values, const std::array<double, 3>& origin,
             const std::array<double, 3>& spacing) {
            if (values.ndim() != 3) throw InputError("Field.from_array: values must be (nx, ny, nz)");
            PyField f;
            f.method = "array";
            GridSpec g;
            g.origin = Vec3(origin[0], origin[1], origin[2]);
            g.spacing = Vec3(spacing[0], spacing[1], spacing[2]);
            g.nodes = {static_cast<int>(values.shape(0)), static_cast<int>(values.shape(1)), static_cast<int>(values.shape(2))};
            g.validate("Field.from_array");
            f.field = std::make_shared<ScalarField>(g);
            std::copy(values.data(), values.data() + values.size(), f.field->values.begin());
            return f;
          },
          py::arg("values"), py::arg("origin"), py::arg("spacing"), "A field holding a copy of `values`")
      .def("__repr__", [](const PyField& f) {
        const Index3 n = f.field->grid.nodes;
        return "<ppohdem.sdf.Field " + f.method + " " + std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " +
               std::to_string(n[2]) + " nodes>";
      });

  sdf.def("build", &build_field, py::arg("mesh"), py::arg("cells"), py::arg("box"), py::arg("method") = "fast",
          py::arg("band") = 0.0, py::arg("threads") = 0,
          "Signed distance of a mesh at the nodes of a grid, as `ppohdem voxelize --mesh --cells --box --method`");
  sdf.def(
      "load_vtk",
      [](const fs::path& path) {
        PyField f;
        f.method = "vtk";
        f.field = std::make_shared<ScalarField>(read_vtk_structured_points(path));
        return f;
      },
      py::arg("path"));
  sdf.def(
      "compare",
      [](const PyField& candidate, const PyField& oracle, double band) {
        const FieldComparison c = compare_fields(*candidate.field, *oracle.field, band);
        py::dict d;  // field_metrics.hpp; errors in units of h = the smallest spacing
        d["h"] = c.h;
        d["max_error_h"] = c.all.max_error_h;
        d["rms_error_h"] = c.all.rms_error_h;
        d["band_max_error_h"] = c.band.max_error_h;
        d["band_rms_error_h"] = c.band.rms_error_h;
        d["band_nodes"] = c.band.nodes;
        d["sign_checked_nodes"] = c.sign_checked_nodes;
        d["sign_mismatches"] = c.sign_mismatches;
        d["non_finite"] = c.non_finite_candidate;
        d["max_relative_error"] = c.max_relative_error;
        return d;
      },
      py::arg("candidate"), py::arg("oracle"), py::arg("band") = 2.0,
      "Errors of a field against an oracle field on the same grid (field_metrics.hpp)");

  // The stages of the reference pipeline, for teaching (docs/sdf.md).
  sdf.def(
      "column_crossings",
      [](const py::object& mesh_arg, const std::array<int, 3>& cells, const std::array<double, 6>& box, int i, int j) {
        const GridSpec grid = grid_from_cells_box(cells, box);
        if (i < 0 || j < 0 || i >= grid.nodes[0] || j >= grid.nodes[1]) throw InputError("column_crossings: (i, j) outside the grid");
        const sdf::reference::CrossList list = sdf::reference::make_cross_list(mesh_from(mesh_arg), grid);
        std::vector<double> z;
        for (const auto& c : list.column(i, j)) z.push_back(c.z);
        return z;
      },
      py::arg("mesh"), py::arg("cells"), py::arg("box"), py::arg("i"), py::arg("j"),
      "Heights z of the crossings of node column (i, j) with the mesh, sorted (ray parity stage 1)");
  sdf.def(
      "inside_by_ray_parity",
      [](const py::object& mesh_arg, const std::array<int, 3>& cells, const std::array<double, 6>& box) {
        const GridSpec grid = grid_from_cells_box(cells, box);
        return bool_grid(sdf::reference::inside_by_column_parity(mesh_from(mesh_arg), grid), grid);
      },
      py::arg("mesh"), py::arg("cells"), py::arg("box"), "(nx, ny, nz) bool: odd number of crossings above the node");
  sdf.def(
      "inside_by_winding_number",
      [](const py::object& mesh_arg, const std::array<int, 3>& cells, const std::array<double, 6>& box) {
        const GridSpec grid = grid_from_cells_box(cells, box);
        return bool_grid(sdf::reference::inside_by_winding_number(mesh_from(mesh_arg), grid), grid);
      },
      py::arg("mesh"), py::arg("cells"), py::arg("box"), "(nx, ny, nz) bool: generalized winding number > 1/2");
  sdf.def(
      "winding_number",
      [](const py::object& mesh_arg, const py::object& points) {
        const TriangleMesh mesh = mesh_from(mesh_arg);
        const std::vector<Vec3> p = points_from(points);
        std::vector<double> w(p.size());
        for (std::size_t k = 0; k < p.size(); ++k) w[k] = sdf::reference::winding_number(mesh, p[k]);
        return py::array_t<double>(static_cast<py::ssize_t>(w.size()), w.data());
      },
      py::arg("mesh"), py::arg("points"), "Generalized winding number w (1 inside a closed mesh, 0 outside)");
  sdf.def(
      "fast_sweep",
      [](const PyField& distance, py::array_t<bool, py::array::f_style | py::array::forcecast> frozen) {
        const GridSpec& g = distance.field->grid;
        if (static_cast<std::size_t>(frozen.size()) != g.node_count()) throw InputError("fast_sweep: frozen must have the field's shape");
        std::vector<bool> fixed(frozen.data(), frozen.data() + frozen.size());
        PyField out;
        out.method = "fast sweeping";
        out.field = std::make_shared<ScalarField>(*distance.field);
        const int sweeps = sdf::reference::fast_sweep(*out.field, fixed);
        return py::make_tuple(out, sweeps);
      },
      py::arg("distance"), py::arg("frozen"),
      "Unsigned distance propagated from the frozen nodes (+inf elsewhere) by Godunov sweeps; (field, sweeps)");
}

GridSpec grid_from_cells_box(const std::array<int, 3>& cells, const std::array<double, 6>& box) {
  for (int a = 0; a < 3; ++a) {  // the checks and messages of `ppohdem voxelize` (cmd_voxelize.cpp)
    if (cells[a] < 2) throw InputError("cells: every count must be >= 2 (nodes per axis), got " + std::to_string(cells[a]));
    if (!(box[a + 3] > box[a])) throw InputError("box: max must exceed min on every axis (axis " + std::to_string(a) + ")");
  }
  return GridSpec::spanning(Vec3(box[0], box[1], box[2]), Vec3(box[3], box[4], box[5]), {cells[0], cells[1], cells[2]});
}

TriangleMesh mesh_from(const py::object& mesh) {
  if (py::isinstance<PyMesh>(mesh)) return *mesh.cast<const PyMesh&>().mesh;
  const TriangleMesh m = read_stl(py::module_::import("os").attr("fspath")(mesh).cast<std::string>());
  if (m.empty()) throw InputError(py::str(mesh).cast<std::string>(), 0, "the mesh has no triangles");
  return m;
}

std::vector<Vec3> points_from(const py::object& points) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  if (!a || !((a.ndim() == 2 && a.shape(1) == 3) || (a.ndim() == 1 && a.shape(0) == 3))) {
    throw InputError("points: expected an array of shape (M, 3)");
  }
  const std::size_t m = a.ndim() == 1 ? 1 : static_cast<std::size_t>(a.shape(0));
  std::vector<Vec3> p(m);
  for (std::size_t k = 0; k < m; ++k) p[k] = Vec3(a.data()[3 * k], a.data()[3 * k + 1], a.data()[3 * k + 2]);
  return p;
}

}  // namespace ppohdem::python
