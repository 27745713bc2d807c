#pragma once
/// \file builder_list.hpp
/// The builders every contract body runs on, and readable test names ("SdfContract/fast_band.*").
#include <gtest/gtest.h>

#include <string>

#include "sdf_builder_traits.hpp"

namespace ppohdem::test::sdf_contract {

using AllBuilders = ::testing::Types<ReferenceExact, ReferenceSeed, FastExact, FastSharedCandidates, FastBand,
                                     FastFloat, FastDistributedOneRank, FastThreeSlabs>;

struct BuilderName {
  template <typename B>
  static std::string GetName(int) {
    return B::name;
  }
};

}  // namespace ppohdem::test::sdf_contract
