#pragma once
// The DEM engines the oracle suite can exercise, by name (the same names as
// `ppohdem simulate --engine`). Add an engine in engines.cpp when it is built.
#include <memory>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"

namespace ppohdem::validation {

std::vector<std::string> engine_names();  ///< every engine built, "reference" first
bool has_engine(const std::string& name);
/// Throws std::invalid_argument for an unknown name.
std::unique_ptr<dem::DemEngine> make_engine(const std::string& name, const dem::SimulationSetup& setup);

}  // namespace ppohdem::validation
