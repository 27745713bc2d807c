// Regression tests for the fuzzing findings (docs/reliability.md, "Fuzzing"): headers whose
// counts promise far more data than the file holds must be refused with an InputError before
// anything is allocated. Before the fixes these inputs made the readers ask for 10^16 bytes
// (std::bad_alloc, or an AddressSanitizer abort) or accept a grid whose node count had wrapped
// around in size_t. The inputs are the reproducer files the fuzz targets replay on every run
// (tests/fuzz/regressions/<target>/).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <string_view>

#include "ppohdem/error.hpp"
#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"

namespace ppohdem {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string reproducer(const std::string& target, const std::string& name) {
  return read_file_bytes(std::string(PPOHDEM_SOURCE_DIR) + "/tests/fuzz/regressions/" + target + "/" + name);
}

/// The message of the InputError `read` throws; fails the test if it throws nothing or
/// anything else (std::bad_alloc was the symptom of these findings).
template <class Read>
std::string input_error_of(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected InputError, the input was accepted";
  return {};
}

std::string vtk_error(const std::string& name) {
  const std::string bytes = reproducer("vtk", name);
  return input_error_of([&] { read_vtk_structured_points_bytes(bytes, name); });
}

std::string distance_error(const std::string& name) {
  const std::string bytes = reproducer("distance_dat", name);
  const std::array<std::string_view, 1> ranks = {bytes};
  return input_error_of([&] { read_distance_dat_bytes(ranks, "dir"); });
}

TEST(VtkReader, RejectsHugeBinaryDimensionsBeforeAllocating) {
  // DIMENSIONS 1e6 1e6 1e3 = 1e15 doubles (8 PB) announced, no data bytes after the header.
  EXPECT_THAT(vtk_error("huge_dimensions_binary.vtk"),
              AllOf(HasSubstr("huge_dimensions_binary.vtk:8:"), HasSubstr("expected 1000000000000000 binary double"),
                    HasSubstr("found only 0 bytes")));
}

TEST(VtkReader, RejectsHugeAsciiDimensionsBeforeAllocating) {
  // 1e12 values announced, 6 bytes of ASCII data present ("1 2 3\n").
  EXPECT_THAT(vtk_error("huge_dimensions_ascii.vtk"),
              AllOf(HasSubstr("expected 1000000000000 ASCII values"), HasSubstr("found only 6 bytes")));
}

TEST(VtkReader, RejectsDimensionsWhoseProductWrapsAround) {
  // 2^22 * 2^22 * 2^20 = 2^64 wraps to 0 in a 64-bit size_t, which matched "POINT_DATA 0".
  EXPECT_THAT(vtk_error("dimensions_product_wraps.vtk"),
              AllOf(HasSubstr("dimensions_product_wraps.vtk:6:"), HasSubstr("more nodes than this machine can address")));
}

TEST(DistanceDatReader, RejectsHugeHeaderBeforeAllocating) {
  // 99999999 x 99999999 x 1 nodes (8e16 bytes of values) announced in a 30-byte file.
  EXPECT_THAT(distance_error("huge_header_one_rank"),
              AllOf(HasSubstr("distance_0000.dat:1:"), HasSubstr("announces 99999999 99999999 1 nodes"),
                    HasSubstr("at least 7 bytes per record")));
}

TEST(DistanceDatReader, RejectsHeaderWhoseProductWrapsAround) {
  // (2^31 - 1)^3 does not fit in size_t.
  EXPECT_THAT(distance_error("header_product_wraps"),
              AllOf(HasSubstr("distance_0000.dat:1:"), HasSubstr("announces 2147483647 2147483647 2147483647 nodes")));
}

TEST(DistanceDatReader, ReportsMissingRankBeforeAllocating) {
  // nprocs = gridX = 2^31 - 1: 16 GB of values would be allocated before rank 1 was looked for.
  EXPECT_THAT(distance_error("huge_nprocs_missing_ranks"),
              AllOf(HasSubstr("distance_0001.dat"), HasSubstr("nprocs = 2147483647"), HasSubstr("no such file")));
}

TEST(DistanceDatReader, AcceptsTheShortestRecordsTheSizeGuardAllows) {
  // The guard assumes at least 7 bytes per record: a valid file made of the shortest possible
  // records (the last one without its newline) must still be read.
  const std::string rank0 = "2 1 1 1\n1 1 1 0\n2 1 1 5";
  const std::array<std::string_view, 1> ranks = {rank0};
  const DistanceDat dat = read_distance_dat_bytes(ranks, "dir");
  EXPECT_EQ(dat.values, (std::vector<double>{0.0, 5.0}));
}

TEST(GridSpec, CheckedNodeCountDetectsOverflow) {
  EXPECT_EQ(checked_node_count({2, 3, 4}), std::optional<std::size_t>(24));
  EXPECT_EQ(checked_node_count({1 << 22, 1 << 22, 1 << 20}), std::nullopt);  // exactly 2^64
  EXPECT_EQ(checked_node_count({(1 << 22) - 1, 1 << 22, 1 << 20}).value(),
            ((std::size_t{1} << 22) - 1) << 42);  // 2^64 - 2^42: just fits
  EXPECT_EQ(checked_node_count({0, 5, 5}), std::nullopt);
}

}  // namespace
}  // namespace ppohdem
