#pragma once
#include "ppohdem/validation/check_registry.hpp"

namespace ppohdem::validation {
/// Runs the property-test binaries (label `property`) and reports each property as a row.
CheckGroup make_invariant_checks();
}  // namespace ppohdem::validation
