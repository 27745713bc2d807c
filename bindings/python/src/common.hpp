#pragma once
// Shared helpers of the Python module (docs/python.md): read-only NumPy views over memory that a
// C++ object owns, and grids from the `cells`/`box` arguments of `ppohdem voxelize`.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstddef>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::python {
namespace py = pybind11;

/// A view of `data` (no copy) that keeps `owner` alive and cannot be written through.
template <class T>
py::array readonly_view(const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
                        py::handle owner) {
  static const T empty{};  // a size-0 view still needs a non-null pointer (else NumPy allocates)
  py::array a(py::dtype::of<T>(), std::move(shape), std::move(strides), data ? data : &empty, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// Node counts and box as `ppohdem voxelize --cells NX NY NZ --box XMIN ... ZMAX` take them
/// (node (i,j,k) at min + (i,j,k) (max - min) / (N - 1)); the same checks and messages.
GridSpec grid_from_cells_box(const std::array<int, 3>& cells, const std::array<double, 6>& box);

/// A mesh argument: an STL path (str or os.PathLike) or a ppohdem.sdf.Mesh.
TriangleMesh mesh_from(const py::object& mesh);

/// (M, 3) float64 points from any array-like.
std::vector<Vec3> points_from(const py::object& points);

void bind_dem(py::module_& m);
void bind_sdf(py::module_& sdf);
void bind_oracles(py::module_& oracles);

}  // namespace ppohdem::python
