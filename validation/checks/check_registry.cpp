// The check registry (see check_registry.hpp) and the row-formatting helpers.
#include "ppohdem/validation/check_registry.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace ppohdem::validation {
namespace {
std::vector<CheckGroup>& registry() {
  static std::vector<CheckGroup> groups;
  return groups;
}

std::string fmt(double value, const std::string& unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", value);
  std::string text(buf);
  if (!unit.empty()) {
    text.append(" ");
    text.append(unit);
  }
  return text;
}
}  // namespace

void register_check_group(CheckGroup group) { registry().push_back(std::move(group)); }

const std::vector<CheckGroup>& check_groups() { return registry(); }

CheckRow compare_abs(std::string check, std::string engine, double measured, double expected,
                     double tolerance, std::string unit, std::string tolerance_source) {
  CheckRow row;
  row.check = std::move(check);
  row.engine = std::move(engine);
  row.measured = fmt(measured, unit);
  row.expected = fmt(expected, unit);
  row.tolerance = "±" + fmt(tolerance, unit);
  row.tolerance_source = std::move(tolerance_source);
  row.passed = std::isfinite(measured) && std::abs(measured - expected) <= tolerance;
  return row;
}

CheckRow compare_rel(std::string check, std::string engine, double measured, double expected,
                     double rel_tolerance, std::string unit, std::string tolerance_source) {
  CheckRow row;
  row.check = std::move(check);
  row.engine = std::move(engine);
  row.measured = fmt(measured, unit);
  row.expected = fmt(expected, unit);
  char buf[64];
  std::snprintf(buf, sizeof buf, "±%.3g %%", 100.0 * rel_tolerance);
  row.tolerance = buf;
  row.tolerance_source = std::move(tolerance_source);
  row.passed = std::isfinite(measured) &&
               std::abs(measured - expected) <= rel_tolerance * std::abs(expected);
  return row;
}

CheckRow compare_le(std::string check, std::string engine, double measured, double bound,
                    std::string unit, std::string tolerance_source) {
  CheckRow row;
  row.check = std::move(check);
  row.engine = std::move(engine);
  row.measured = fmt(measured, unit);
  row.expected = "<= " + fmt(bound, unit);
  row.tolerance = "(bound)";
  row.tolerance_source = std::move(tolerance_source);
  row.passed = std::isfinite(measured) && measured <= bound;
  return row;
}

}  // namespace ppohdem::validation
