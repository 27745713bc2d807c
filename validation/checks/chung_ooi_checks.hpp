#pragma once
#include <vector>

#include "ppohdem/validation/check_registry.hpp"

namespace ppohdem::validation {
std::vector<CheckGroup> make_chung_ooi_checks();
}  // namespace ppohdem::validation
