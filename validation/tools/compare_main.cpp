// ppohdem-compare: how far a candidate distance field is from an oracle field.
//
//   ppohdem-compare CANDIDATE.vtk ORACLE.vtk [--band 2] [--sign-tolerance 1e-9] [--json]
//
// Prints compare_fields() (errors in units of h, sign mismatches) and the candidate's
// Lipschitz ratio (core/include/ppohdem/sdf/field_metrics.hpp). It reports; it does not judge:
// the exit status is non-zero only when an input cannot be read or the grids differ.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"
#include "ppohdem/sdf/field_metrics.hpp"

namespace {

// JSON has no Infinity/NaN: those become null.
std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::string json_stats(const ppohdem::ErrorStats& s) {
  return "{\"nodes\": " + std::to_string(s.nodes) +
         ", \"max_error_h\": " + json_number(s.max_error_h) +
         ", \"rms_error_h\": " + json_number(s.rms_error_h) + ", \"worst_node\": [" +
         std::to_string(s.worst_node[0]) + ", " + std::to_string(s.worst_node[1]) + ", " +
         std::to_string(s.worst_node[2]) + "]}";
}

std::string to_json(const ppohdem::FieldComparison& c, double lipschitz) {
  return "{\"h\": " + json_number(c.h) + ", \"band_in_h\": " + json_number(c.band_in_h) +
         ", \"sign_tolerance_in_h\": " + json_number(c.sign_tolerance_in_h) +
         ", \"band\": " + json_stats(c.band) + ", \"all\": " + json_stats(c.all) +
         ", \"max_relative_error\": " + json_number(c.max_relative_error) +
         ", \"sign_checked_nodes\": " + std::to_string(c.sign_checked_nodes) +
         ", \"sign_mismatches\": " + std::to_string(c.sign_mismatches) +
         ", \"non_finite_candidate\": " + std::to_string(c.non_finite_candidate) +
         ", \"candidate_lipschitz_ratio\": " + json_number(lipschitz) + "}";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ppohdem-compare: compare a candidate distance field with an oracle field"};
  std::string candidate_path;
  std::string oracle_path;
  double band_in_h = 2.0;
  double sign_tolerance_in_h = 1e-9;
  bool json = false;
  app.add_option("candidate", candidate_path, "candidate field (legacy VTK STRUCTURED_POINTS)")
      ->required();
  app.add_option("oracle", oracle_path, "oracle field on the same grid")->required();
  app.add_option("--band", band_in_h, "narrow band |oracle| < band * h, in h")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--sign-tolerance", sign_tolerance_in_h,
                 "compare signs only where |oracle| > this * h")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--json", json, "print one JSON object instead of a table");
  CLI11_PARSE(app, argc, argv);

  try {
    using namespace ppohdem;
    const ScalarField candidate = read_vtk_structured_points(candidate_path);
    const ScalarField oracle = read_vtk_structured_points(oracle_path);
    const FieldComparison comparison =
        compare_fields(candidate, oracle, band_in_h, sign_tolerance_in_h);
    const double lipschitz = lipschitz_ratio(candidate);
    if (json) {
      std::printf("%s\n", to_json(comparison, lipschitz).c_str());
    } else {
      std::printf("candidate %s\noracle    %s\n%s%-34s%.6g\n", candidate_path.c_str(),
                  oracle_path.c_str(), format_comparison(comparison).c_str(),
                  "candidate Lipschitz ratio", lipschitz);
    }
  } catch (const ppohdem::InputError& e) {
    std::fprintf(stderr, "ppohdem-compare: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem-compare: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
