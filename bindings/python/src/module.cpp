// The Python module `ppohdem` (docs/python.md): a thin adapter over core/, reference/ and
// validation/; it computes nothing of its own (DESIGN.md "Interfaces for users").
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/provenance.hpp"

PYBIND11_MODULE(_ppohdem, m) {
  namespace py = pybind11;
  m.doc() = "ppohdem: DEM engines, signed distance fields and their oracles (docs/python.md)";
  // InputError carries ppohdem's message with file and line; it is a ValueError in Python.
  static py::exception<ppohdem::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ppohdem::InputError& e) {
      py::object error = py::reinterpret_borrow<py::object>(input_error.ptr())(e.what());
      error.attr("file") = e.file();    // "" if none
      error.attr("line") = e.line();    // 0 if unknown
      error.attr("detail") = e.message();  // the message without file and line
      PyErr_SetObject(input_error.ptr(), error.ptr());
    }
  });
  m.def("provenance", [](int threads) { return ppohdem::provenance_line(1, threads); }, py::arg("threads") = 0,
        "The run header line ppohdem writes at the top of its outputs");
  ppohdem::python::bind_dem(m);
  py::module_ sdf = m.def_submodule("sdf", "Signed distance fields: builders, fields, teaching stages");
  ppohdem::python::bind_sdf(sdf);
  py::module_ oracles = m.def_submodule("oracles", "Independent answers: Hertz pair, CGAL distance, Lipschitz");
  ppohdem::python::bind_oracles(oracles);
}
