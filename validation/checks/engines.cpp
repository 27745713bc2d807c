// Engine table of the oracle suite (mirror of apps/cmd_simulate.cpp's table).
#include "engines.hpp"

#include <map>
#include <stdexcept>

#include "ppohdem/dem/fast/fast_engine.hpp"
#include "ppohdem/dem/reference/reference_engine.hpp"

namespace ppohdem::validation {
namespace {
const std::map<std::string, dem::EngineFactory>& table() {
  static const std::map<std::string, dem::EngineFactory> engines{
      {"reference", &dem::reference::ReferenceEngine::make},
      {"fast", &dem::fast::FastEngine::make},  // the optimized engine (core/dem/fast)
      // add further engines here (same names as `ppohdem simulate --engine`)
  };
  return engines;
}
}  // namespace

std::vector<std::string> engine_names() {
  std::vector<std::string> names{"reference"};
  for (const auto& [name, factory] : table())
    if (name != "reference") names.push_back(name);
  return names;
}

bool has_engine(const std::string& name) { return table().count(name) != 0; }

std::unique_ptr<dem::DemEngine> make_engine(const std::string& name,
                                            const dem::SimulationSetup& setup) {
  const auto it = table().find(name);
  if (it == table().end()) throw std::invalid_argument("unknown DEM engine '" + name + "'");
  return it->second(setup);
}

}  // namespace ppohdem::validation
