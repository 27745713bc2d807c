#pragma once
// The structs behind the C API's opaque handles (ppohdem.h), shared by the c_api_*.cpp files.
#include <cmath>
#include <memory>
#include <string>

#include "c_api_guard.hpp"
#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/scene.hpp"
#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/grid/scalar_field.hpp"

struct ppohdem_field {
  ppohdem::ScalarField field;
};

struct ppohdem_scene {
  ppohdem::dem::Scene scene;
};

struct ppohdem_engine {
  std::unique_ptr<ppohdem::dem::DemEngine> engine;
  std::string scene_source;
};

namespace ppohdem::c_api {

/// GridSpec of a ppohdem_grid; ArgumentError if a spacing is not > 0 or a count < 1.
inline GridSpec grid_spec_of(const ppohdem_grid& g) {
  GridSpec spec;
  for (int a = 0; a < 3; ++a) {
    if (!(g.spacing[a] > 0.0) || !std::isfinite(g.spacing[a])) {
      throw ArgumentError("grid spacing[" + std::to_string(a) + "] must be finite and > 0");
    }
    if (g.nodes[a] < 1) throw ArgumentError("grid nodes[" + std::to_string(a) + "] must be >= 1");
    if (!std::isfinite(g.origin[a])) throw ArgumentError("grid origin must be finite");
    spec.origin[a] = g.origin[a];
    spec.spacing[a] = g.spacing[a];
    spec.nodes[a] = g.nodes[a];
  }
  return spec;
}

}  // namespace ppohdem::c_api
