// --compat ppohdem-1.0 against the original program's own outputs (fixtures/ppohdem-1.0/util-*):
// the distance files must be byte-identical, for 1 and 2 ranks, on the cube sample and on the
// two sphere samples (the centred one is the degenerate case where grid columns pass through
// mesh vertices and edges).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "ppohdem/io/distance_dat.hpp"
#include "ppohdem/io/legacy_inputs.hpp"
#include "ppohdem/mesh/placement.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/compat/ppohdem10_voxelizer.hpp"
#include "test_paths.hpp"
#include "xz_file.hpp"

namespace ppohdem::compat {
namespace {

namespace fs = std::filesystem;

enum class Sample { kCube, kOffsetSphere, kCentredSphere };

fs::path sample_dir(Sample s) {
  switch (s) {
    case Sample::kCube: return test::fixture("ppohdem-1.0/util-cube");
    case Sample::kOffsetSphere: return test::fixture("ppohdem-1.0/util-sphere/offset");
    case Sample::kCentredSphere: return test::fixture("ppohdem-1.0/util-sphere/centered");
  }
  return {};
}

TriangleMesh sample_mesh(Sample s) {
  if (s == Sample::kCube) return read_stl(test::fixture("ppohdem-1.0/test-cube.stl"));
  const std::string text = test::read_xz_file(test::fixture("ppohdem-1.0/util-sphere/sphere_uv64x32.stl.xz"));
  return read_stl_bytes(text, "sphere_uv64x32.stl");
}

// The original's file for `rank` of an `nprocs`-rank run, decompressed.
std::string original_file(Sample s, int nprocs, int rank) {
  const std::string name = "distance_000" + std::to_string(rank) + ".dat.xz";
  if (s == Sample::kCube) return test::read_xz_file(sample_dir(s) / ("np" + std::to_string(nprocs)) / name);
  return test::read_xz_file(sample_dir(s) / ("np" + std::to_string(nprocs) + "_" + name));
}

// Our run of the sample, cached: each run takes a few seconds and several tests read it.
const Ppohdem10Trace& run(Sample s, int nprocs) {
  static std::map<std::pair<Sample, int>, Ppohdem10Trace> cache;
  const auto key = std::make_pair(s, nprocs);
  auto it = cache.find(key);
  if (it == cache.end()) {
    const VoxelizerInput input = read_voxelizer_input(sample_dir(s) / "input_constants_voxelizer.dat");
    const TriangleMesh placed =
        place_mesh(sample_mesh(s), Placement{input.object_size, input.object_position, PlacementMode::kPpohdem10});
    it = cache.emplace(key, ppohdem10_distance_trace(placed, input, nprocs)).first;
  }
  return it->second;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Writes our files, compares each with the original byte for byte; on a mismatch reports how
// many records differ at the printed precision and the first few.
void expect_files_identical(Sample s, int nprocs) {
  const Ppohdem10Trace& trace = run(s, nprocs);
  // The run met none of the cases where the original's behaviour is undefined.
  EXPECT_EQ(trace.odd_crossing_columns, 0);
  EXPECT_EQ(trace.overflowing_columns, 0);
  EXPECT_EQ(trace.nonfinite_crossing_columns, 0);
  const fs::path dir = test::scratch_dir();
  write_distance_dat(dir, trace.distance, trace.nodes, nprocs);
  for (int rank = 0; rank < nprocs; ++rank) {
    const std::string ours = read_file_bytes(distance_dat_path(dir, rank));
    const std::string theirs = original_file(s, nprocs, rank);
    if (ours == theirs) continue;
    const auto a = lines_of(ours);
    const auto b = lines_of(theirs);
    int differing = 0;
    std::string first;
    for (std::size_t n = 0; n < std::min(a.size(), b.size()); ++n) {
      if (a[n] == b[n]) continue;
      if (++differing <= 5) first += "\n  ours:     " + a[n] + "\n  original: " + b[n];
    }
    ADD_FAILURE() << "rank " << rank << " of " << nprocs << ": " << differing << " of " << b.size()
                  << " lines differ (line counts " << a.size() << " vs " << b.size() << ")" << first;
  }
}

TEST(Ppohdem10Cube, OneRankFileIsByteIdenticalToTheOriginal) { expect_files_identical(Sample::kCube, 1); }
TEST(Ppohdem10Cube, TwoRankFilesAreByteIdenticalToTheOriginal) { expect_files_identical(Sample::kCube, 2); }
TEST(Ppohdem10OffsetSphere, OneRankFileIsByteIdenticalToTheOriginal) {
  expect_files_identical(Sample::kOffsetSphere, 1);
}
TEST(Ppohdem10OffsetSphere, TwoRankFilesAreByteIdenticalToTheOriginal) {
  expect_files_identical(Sample::kOffsetSphere, 2);
}
TEST(Ppohdem10CentredSphere, OneRankFileIsByteIdenticalToTheOriginal) {
  expect_files_identical(Sample::kCentredSphere, 1);
}
TEST(Ppohdem10CentredSphere, TwoRankFilesAreByteIdenticalToTheOriginal) {
  expect_files_identical(Sample::kCentredSphere, 2);
}

// The rank count changes only nodes on the faces j = 1 and j = gridY of rank 0's last plane
// (i = 38, 1-based), where the boundary extrapolation reads the ghost plane exchanged before the
// last sweep. The original's README counts 10 such nodes on the offset sphere, 11 on the centred
// one, and none on the cube.
void expect_rank_count_effect(Sample s, int expected_differences) {
  const Ppohdem10Trace& one = run(s, 1);
  const Ppohdem10Trace& two = run(s, 2);
  const Index3 n = one.nodes;
  int differences = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t at = static_cast<std::size_t>(i + n[0] * (j + n[1] * k));
        if (format_fortran_e20_8(one.distance[at]) == format_fortran_e20_8(two.distance[at])) continue;
        ++differences;
        EXPECT_EQ(i, 37) << "j " << j << " k " << k;
        EXPECT_TRUE(j == 0 || j == n[1] - 1) << "i " << i << " k " << k;
      }
  EXPECT_EQ(differences, expected_differences);
}

TEST(Ppohdem10Ranks, TwoRanksChangeNothingOnTheCube) { expect_rank_count_effect(Sample::kCube, 0); }
TEST(Ppohdem10Ranks, TwoRanksChangeTenRankBoundaryFaceNodesOnTheOffsetSphere) {
  expect_rank_count_effect(Sample::kOffsetSphere, 10);
}
TEST(Ppohdem10Ranks, TwoRanksChangeElevenRankBoundaryFaceNodesOnTheCentredSphere) {
  expect_rank_count_effect(Sample::kCentredSphere, 11);
}

TEST(Ppohdem10Cube, UnreachedSentinelNodesAreCountedAsTheOriginalReports) {
  // The original's README: 16,322 cube nodes keep the sentinel 10 Lx = 440 (or 440 + W, 2W, 3W
  // on the boundary), i.e. the value >= 440.
  const Ppohdem10Trace& trace = run(Sample::kCube, 1);
  int unreached = 0;
  for (const double d : trace.distance) unreached += d >= trace.sentinel ? 1 : 0;
  EXPECT_EQ(unreached, 16322);
}

// object_mesh.stl as the original writes it (output_object_mesh), against its own files.
std::string placed_object_mesh(Sample s) {
  const VoxelizerInput input = read_voxelizer_input(sample_dir(s) / "input_constants_voxelizer.dat");
  return ppohdem10_object_mesh_stl(
      place_mesh(sample_mesh(s), Placement{input.object_size, input.object_position, PlacementMode::kPpohdem10}));
}

TEST(Ppohdem10ObjectMesh, CubeIsByteIdenticalToTheOriginal) {
  EXPECT_TRUE(placed_object_mesh(Sample::kCube) == read_file_bytes(test::fixture("ppohdem-1.0/object_mesh_cube.stl")));
}
TEST(Ppohdem10ObjectMesh, SpheresAreByteIdenticalToTheOriginal) {
  for (const Sample s : {Sample::kOffsetSphere, Sample::kCentredSphere}) {
    EXPECT_TRUE(placed_object_mesh(s) == test::read_xz_file(sample_dir(s) / "object_mesh.stl.xz"));
  }
}

}  // namespace
}  // namespace ppohdem::compat
