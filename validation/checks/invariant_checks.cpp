// The property tests (rapidcheck, ctest label `property`) as rows of the validation report:
// runs each test binary with --gtest_output=xml and lists every test with its outcome. A
// failing property prints its seed in the binary's output (kept in the work directory) and
// can be replayed with RC_PARAMS="reproduce=..." (see docs/validation.md).
#include "invariant_checks.hpp"
#include "plot.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ppohdem::validation {
namespace {

namespace fs = std::filesystem;

struct PropertyBinary {
  const char* path;      ///< relative to the build directory
  const char* target;    ///< CMake target that builds it
  const char* filter;    ///< gtest filter
  const char* what;      ///< what the binary checks
};

/// The property binaries (explicit list; add yours here).
constexpr PropertyBinary kBinaries[] = {
    {"tests/dem/dem_invariants_test", "dem_invariants_test", "*",
     "DEM invariants: momentum, Newton 3, energy, permutation, rigid motion, cell list"},
    {"tests/validation/sdf_property_test", "sdf_property_test", "*",
     "SDF properties vs CGAL: random convex hulls, unions of boxes, Lipschitz, exact boxes"},
};

std::string attribute(const std::string& element, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto at = element.find(key);
  if (at == std::string::npos) return {};
  const auto start = at + key.size();
  return element.substr(start, element.find('"', start) - start);
}


std::vector<CheckRow> run_binaries(const CheckContext& ctx) {
  std::vector<CheckRow> rows;
  const fs::path build_dir = PPOHDEM_BINARY_DIR;
  // rapidcheck cases per property: 100 in --quick (rapidcheck's default), 1000 in --full.
  const std::string rc_params = ctx.quick ? "max_success=100" : "max_success=1000";
  for (const PropertyBinary& b : kBinaries) {
    const fs::path exe = build_dir / b.path;
    if (!fs::exists(exe)) {
      CheckRow row;
      row.check = std::string("property binary ") + b.path;
      row.engine = "-";
      row.measured = "not built";
      row.expected = "built and passing";
      row.tolerance = "-";
      row.tolerance_source = std::string("build the target ") + b.target + " (PPOHDEM_ENABLE_TESTING=ON)";
      rows.push_back(row);
      continue;
    }
    const fs::path xml = fs::path(ctx.work_dir) / (std::string(b.target) + ".xml");
    const fs::path log = fs::path(ctx.work_dir) / (std::string(b.target) + ".log");
    const std::string cmd = "RC_PARAMS=" + rc_params + " " + shell_quote(exe.string()) + " --gtest_filter=" +
                            shell_quote(b.filter) + " --gtest_output=xml:" + shell_quote(xml.string()) + " > " +
                            shell_quote(log.string()) + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream in(xml);
    std::stringstream text;
    text << in.rdbuf();
    const std::string s = text.str();
    std::size_t pos = 0, count = 0;
    while ((pos = s.find("<testcase ", pos)) != std::string::npos) {
      const auto end_tag = s.find('>', pos);
      const std::string element = s.substr(pos, end_tag - pos);
      const auto next = s.find("<testcase ", end_tag);
      const std::string body = s.substr(end_tag, (next == std::string::npos ? s.size() : next) - end_tag);
      CheckRow row;
      row.check = attribute(element, "classname") + "." + attribute(element, "name");
      row.engine = "reference";
      const bool failed = body.find("<failure") != std::string::npos;
      const bool skipped = attribute(element, "result") == "skipped";
      row.measured = failed ? "FAILED (seed and counterexample in " + log.string() + ")"
                            : (skipped ? "skipped" : "held for all generated cases");
      row.expected = "holds";
      row.tolerance = "in the test";
      row.tolerance_source = std::string(b.what) + " (" + b.path + ".cpp comments; RC " + rc_params + ")";
      row.passed = !failed && !skipped;
      rows.push_back(row);
      ++count;
      pos = end_tag;
    }
    if (count == 0 || (rc != 0 && rows.back().passed)) {
      CheckRow row;
      row.check = std::string("property binary ") + b.path + " ran";
      row.engine = "-";
      row.measured = "exit status " + std::to_string(rc) + ", " + std::to_string(count) + " tests (log " +
                     log.string() + ")";
      row.expected = "exit 0";
      row.tolerance = "-";
      row.tolerance_source = "a crashed test binary is a failure";
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace

CheckGroup make_invariant_checks() {
  CheckGroup g;
  g.name = "Property-based invariants (rapidcheck test binaries)";
  g.in_quick = true;
  g.run = run_binaries;
  return g;
}

}  // namespace ppohdem::validation
