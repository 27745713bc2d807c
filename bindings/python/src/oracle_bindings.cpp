// Oracles callable from Python (docs/python.md "Oracles"): the analytic Hertz pair
// (validation/checks/hertz_theory.hpp), the CGAL distance where the build has CGAL, and the
// Lipschitz check of a field (field_metrics.hpp).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>

#include "common.hpp"
#include "hertz_theory.hpp"
#include "ppohdem/dem/hertz_damping.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/sdf/field_metrics.hpp"
#include "py_field.hpp"
#ifdef PPOHDEM_PYTHON_WITH_CGAL
#include "ppohdem/validation/cgal_signed_distance.hpp"
#include "ppohdem/validation/exact_distance.hpp"
#endif

namespace ppohdem::python {

void bind_oracles(py::module_& o) {
  o.def("hertz_force", py::vectorize(&validation::hertz_elastic_force), py::arg("overlap"), py::arg("r_eff"),
        py::arg("e_star"), "Hertz normal force (4/3) E* sqrt(R*) overlap^1.5 [N] (0 without overlap)");
  o.def(
      "hertz_impact",
      [](double m_eff, double r_eff, double e_star, double v) {
        const validation::HertzImpactTheory h = validation::hertz_impact(m_eff, r_eff, e_star, v);
        py::dict d;
        d["max_overlap"] = h.max_overlap;
        d["max_force"] = h.max_force;
        d["duration"] = h.duration;
        return d;
      },
      py::arg("m_eff"), py::arg("r_eff"), py::arg("e_star"), py::arg("v"),
      "Elastic Hertz impact in closed form (Johnson 1985): max_overlap [m], max_force [N], duration [s]");
  o.def(
      "oblique_impact",
      [](double mass, double radius, double e_star, double g_star, double v_n, double v_t, double mu,
         double restitution, std::optional<double> mass_b, std::optional<double> radius_b, double spin_a,
         double spin_b) {
        validation::ObliqueProblem p;
        p.a = {mass, 0.4 * mass * radius * radius, radius};  // solid sphere I = (2/5) m R^2
        p.plane = !mass_b.has_value();
        if (mass_b) {
          if (!radius_b) throw InputError("oblique_impact: mass_b needs radius_b");
          p.b = {*mass_b, 0.4 * *mass_b * *radius_b * *radius_b, *radius_b};
        }
        p.e_star = e_star;
        p.g_star = g_star;
        p.mu = mu;
        p.alpha = restitution < 1.0 ? dem::hertz_damping_ratio_for_restitution(restitution) : 0.0;
        p.v_n = v_n;
        p.v_t = v_t;
        p.spin_a = spin_a;
        p.spin_b = spin_b;
        py::gil_scoped_release release;
        const validation::ObliqueReference r = validation::oblique_reference(p);
        py::gil_scoped_acquire acquire;
        py::dict d;
        d["normal_velocity_after"] = r.normal_velocity_after;
        d["tangential_velocity_after"] = r.tangential_velocity_after;
        d["spin_a_after"] = r.spin_a_after;
        d["spin_b_after"] = r.spin_b_after;
        d["slip_velocity_after"] = r.slip_velocity_after;
        d["normal_impulse"] = r.normal_impulse;
        d["tangential_impulse"] = r.tangential_impulse;
        d["duration"] = r.duration;
        d["restitution"] = r.normal_velocity_after / v_n;
        return d;
      },
      py::arg("mass"), py::arg("radius"), py::arg("e_star"), py::arg("g_star"), py::arg("v_n"), py::arg("v_t") = 0.0,
      py::arg("mu") = 0.0, py::arg("restitution") = 1.0, py::arg("mass_b") = py::none(),
      py::arg("radius_b") = py::none(), py::arg("spin_a") = 0.0, py::arg("spin_b") = 0.0,
      "Hertz-Mindlin impact of sphere A on a plane (or on sphere B) integrated by RK4 with 100,000 steps per "
      "contact (Chung & Ooi 2011 benchmarks); damping from `restitution` by Tsuji's alpha(e)");
  o.def("damping_ratio", &dem::hertz_damping_ratio_for_restitution, py::arg("restitution"),
        "Tsuji's alpha(e) of the damped Hertz law (hertz_damping.hpp)");
  o.def(
      "lipschitz_ratio", [](const PyField& f) { return lipschitz_ratio(*f.field); }, py::arg("field"),
      "max |phi_a - phi_b| / |x_a - x_b| over 26-neighbour node pairs (<= 1 for a true distance)");
#ifdef PPOHDEM_PYTHON_WITH_CGAL
  o.attr("has_cgal") = true;
  o.def(
      "signed_distance",
      [](const py::object& mesh, const py::object& points, int threads) {
        const TriangleMesh m = mesh_from(mesh);
        const std::vector<Vec3> p = points_from(points);
        std::vector<double> phi;
        {
          py::gil_scoped_release release;
          phi = validation::cgal_signed_distance_at(m, p, threads);
        }
        return py::array_t<double>(static_cast<py::ssize_t>(phi.size()), phi.data());
      },
      py::arg("mesh"), py::arg("points"), py::arg("threads") = 1,
      "CGAL signed distance at (M, 3) points (negative inside; unsigned if the mesh is not closed)");
  o.def(
      "signed_distance_field",
      [](const py::object& mesh, const std::array<int, 3>& cells, const std::array<double, 6>& box, int threads) {
        const TriangleMesh m = mesh_from(mesh);
        const GridSpec grid = grid_from_cells_box(cells, box);
        PyField f;
        f.method = "cgal";
        f.threads = threads;
        validation::OracleReport report;
        {
          py::gil_scoped_release release;
          f.field = std::make_shared<ScalarField>(validation::cgal_signed_distance(m, grid, threads, &report));
        }
        f.report.warnings = report.warnings;
        f.report.inside_fraction = static_cast<double>(report.inside_nodes) / static_cast<double>(grid.node_count());
        return f;
      },
      py::arg("mesh"), py::arg("cells"), py::arg("box"), py::arg("threads") = 1,
      "The CGAL oracle on the grid of sdf.build (same cells and box)");
  o.def(
      "exact_distance",
      [](const py::object& mesh, const py::object& points) {
        const TriangleMesh m = mesh_from(mesh);
        const std::vector<Vec3> p = points_from(points);
        std::vector<double> d(p.size());
        for (std::size_t k = 0; k < p.size(); ++k) d[k] = validation::exact_unsigned_distance(m, p[k]);
        return py::array_t<double>(static_cast<py::ssize_t>(d.size()), d.data());
      },
      py::arg("mesh"), py::arg("points"), "Unsigned distance with exact CGAL constructions (slow: a few points)");
#else
  o.attr("has_cgal") = false;
#endif
}

}  // namespace ppohdem::python
