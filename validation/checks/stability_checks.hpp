#pragma once
#include <vector>

#include "ppohdem/validation/check_registry.hpp"

namespace ppohdem::validation {
std::vector<CheckGroup> make_stability_checks();
}  // namespace ppohdem::validation
