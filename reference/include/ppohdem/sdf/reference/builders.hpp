#pragma once
/// \file builders.hpp
/// The reference SDF builders by method name: "exact" (ExactSdfBuilder) and "seed"
/// (SeedPipelineSdfBuilder with the original's band of 2 sqrt(3) h).
#include <memory>
#include <string_view>

#include "ppohdem/sdf/signed_distance.hpp"

namespace ppohdem::sdf::reference {

/// Throws InputError naming the valid methods for any other name.
std::unique_ptr<SdfBuilder> make_reference_sdf_builder(std::string_view method);

}  // namespace ppohdem::sdf::reference
