#pragma once
/// \file check_registry.hpp
/// The oracle-check registry behind `ppohdem validate` (docs/validation.md).
///
/// A *check group* is a named set of oracle checks (e.g. "Chung & Ooi test 1", "YADE two-sphere
/// impact"). Running a group returns one CheckRow per compared number: what was measured, the
/// independent expected value, the tolerance, and where that tolerance comes from. The
/// `ppohdem-validate` driver (validation/checks/validate_main.cpp) runs every group in
/// all_check_groups(), prints one table, writes docs/validation-report.md and exits non-zero if
/// any row failed.
///
/// How to add a group (explicit list, no static initialisers: static-library registration by
/// static objects is silently dropped by the linker when nothing references the object file):
///   1. write `CheckGroup make_foo_checks();` in a header under validation/checks/ (or in your
///      own folder, e.g. validation/yade/yade_checks.hpp) and define it in a .cpp;
///   2. add that .cpp to the ppohdem_validation_checks library in validation/CMakeLists.txt;
///   3. add one line `register_check_group(make_foo_checks());` in all_check_groups()
///      (validation/checks/all_check_groups.cpp).
/// A group returns rows; it must not print to stdout (progress goes to stderr). Plots: write
/// PNGs into CheckContext::img_dir and list their file names (relative to img_dir) in
/// CheckGroup::plots so the report links them.
#include <functional>
#include <string>
#include <vector>

namespace ppohdem::validation {

/// One compared number. `measured`, `expected` and `tolerance` are preformatted text (with units)
/// so a row can also say "0 of 200 seeds failed" or "< 1e-12 relative".
struct CheckRow {
  std::string check, engine, measured, expected, tolerance, tolerance_source;
  bool passed = false;
};

/// What a group is asked to do.
struct CheckContext {
  bool quick = true;        ///< --quick (CI, a few minutes) vs --full (long studies, < 1 h)
  bool live = false;        ///< --live: rerun peer codes (YADE) instead of stored outputs
  std::string source_dir;   ///< checkout root (fixtures/, validation/ are found from here)
  std::string work_dir;     ///< scratch directory for intermediate files (exists)
  std::string img_dir;      ///< where plots go (docs/img by default; exists)
  std::vector<std::string> engines;  ///< DEM engine names to exercise ("reference", "fast", ...)
};

/// A named set of checks and the plots it produces.
struct CheckGroup {
  std::string name;
  bool in_quick;  ///< run by --quick (else only by --full)
  std::function<std::vector<CheckRow>(const CheckContext&)> run;
  std::vector<std::string> plots;  ///< PNG file names relative to CheckContext::img_dir
};

/// Appends a group to the registry (called from all_check_groups()).
void register_check_group(CheckGroup group);

/// The registered groups, in registration order (all_check_groups() fills them on first call).
const std::vector<CheckGroup>& check_groups();

/// Registers every group of the suite once (explicit list in all_check_groups.cpp) and returns
/// check_groups().
const std::vector<CheckGroup>& all_check_groups();

/// Helper for groups: a row comparing |measured - expected| <= tolerance (absolute), formatted
/// with `unit` and 6 significant digits.
CheckRow compare_abs(std::string check, std::string engine, double measured, double expected,
                     double tolerance, std::string unit, std::string tolerance_source);

/// Helper: |measured - expected| <= rel_tolerance * |expected|.
CheckRow compare_rel(std::string check, std::string engine, double measured, double expected,
                     double rel_tolerance, std::string unit, std::string tolerance_source);

/// Helper: measured <= bound (one-sided bound, e.g. a drift or an error norm).
CheckRow compare_le(std::string check, std::string engine, double measured, double bound,
                    std::string unit, std::string tolerance_source);

}  // namespace ppohdem::validation
