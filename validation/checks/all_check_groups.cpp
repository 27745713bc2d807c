// The explicit list of oracle check groups run by `ppohdem validate` (order = report order).
// To add a group: declare `CheckGroup make_foo_checks();` in a header, add its .cpp to
// ppohdem_validation_checks in validation/CMakeLists.txt, and add one register line below.
#include "ppohdem/validation/check_registry.hpp"

#include "chung_ooi_checks.hpp"
#include "invariant_checks.hpp"
#include "stability_checks.hpp"
#include "../yade/yade_checks.hpp"  // YADE comparison (validation/yade/yade_checks.{hpp,cpp})

namespace ppohdem::validation {

const std::vector<CheckGroup>& all_check_groups() {
  static const bool registered = [] {
    for (auto& group : make_chung_ooi_checks()) register_check_group(std::move(group));
    register_check_group(make_invariant_checks());
    for (auto& group : make_stability_checks()) register_check_group(std::move(group));
    register_check_group(make_yade_checks());  // YADE reference runs (stored + --live)
    return true;
  }();
  (void)registered;
  return check_groups();
}

}  // namespace ppohdem::validation
