/// \file builders.cpp
/// Method name -> reference builder.
#include "ppohdem/sdf/reference/builders.hpp"

#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/sdf/reference/exact_sdf_builder.hpp"
#include "ppohdem/sdf/reference/seed_pipeline_sdf_builder.hpp"

namespace ppohdem::sdf::reference {

std::unique_ptr<SdfBuilder> make_reference_sdf_builder(std::string_view method) {
  if (method == "exact") return std::make_unique<ExactSdfBuilder>();
  if (method == "seed") return std::make_unique<SeedPipelineSdfBuilder>();
  throw InputError("unknown SDF method '" + std::string(method) + "': expected one of exact, seed");
}

}  // namespace ppohdem::sdf::reference
