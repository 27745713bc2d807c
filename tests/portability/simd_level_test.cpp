// The SIMD level (ppohdem/simd_level.hpp, docs/portability.md "SIMD levels"):
// - PPOHDEM_SIMD's values are parsed as documented and a bad one is refused with a clear error;
// - the CPU's level agrees with the kernel's view of the CPU (/proc/cpuinfo flags, an oracle
//   independent of __builtin_cpu_supports);
// - a forced level reaches every dispatch site (ctest runs ForcedLevel once per level with
//   PPOHDEM_SIMD set, tests/portability/CMakeLists.txt);
// - the fast SDF field of a fixture mesh and a fast DEM bed run are the same bytes at every level
//   this CPU runs (through the command line, PPOHDEM_SIMD set per run). Tolerance zero: every
//   lane does the scalar code's operations in its order, without FMA.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/cli_runner.hpp"
#include "../dem_fast/bed_scene.hpp"
#include "../../core/src/dem/fast/hertz_mindlin_x4.hpp"  // internal: x4_contacts_available
#include "ppohdem/error.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"
#include "ppohdem/simd_level.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {
namespace fs = std::filesystem;
using test::CommandResult;
using test::run_shell;

constexpr SimdLevel kAll[] = {SimdLevel::sse2, SimdLevel::avx, SimdLevel::avx512};

TEST(SimdLevel, ParsesTheDocumentedValues) {
  EXPECT_EQ(parse_simd_level("sse2"), SimdLevel::sse2);
  EXPECT_EQ(parse_simd_level("avx"), SimdLevel::avx);
  EXPECT_EQ(parse_simd_level("avx512"), SimdLevel::avx512);
  EXPECT_EQ(parse_simd_level("auto"), std::nullopt);
  EXPECT_EQ(parse_simd_level(""), std::nullopt);
  for (const SimdLevel level : kAll) EXPECT_EQ(parse_simd_level(simd_level_name(level)), level);
}

TEST(SimdLevel, RefusesOtherValuesNamingTheVariableAndTheChoices) {
  for (const char* bad : {"avx2", "AVX", "sse", " avx", "avx512f", "none", "0"}) {
    try {
      (void)parse_simd_level(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("PPOHDEM_SIMD"), std::string::npos) << what;
      EXPECT_NE(what.find("expected sse2, avx, avx512 or auto"), std::string::npos) << what;
      EXPECT_NE(what.find(std::string("'") + bad + "'"), std::string::npos) << what;
    }
  }
}

/// The flags line of /proc/cpuinfo's first processor, or nullopt (not Linux, not x86).
std::optional<std::string> cpuinfo_flags() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("flags", 0) == 0) return line + " ";
  }
  return std::nullopt;
}

TEST(SimdLevel, CpuLevelIsTheWidestTheKernelReports) {
#if !defined(__x86_64__)
  EXPECT_EQ(cpu_simd_level(), SimdLevel::sse2) << "no wide lanes outside x86-64";
#else
  const auto flags = cpuinfo_flags();
  if (!flags) GTEST_SKIP() << "no /proc/cpuinfo flags line";
  const bool avx512 = flags->find(" avx512f ") != std::string::npos;
  const bool avx = flags->find(" avx ") != std::string::npos;
  const SimdLevel expected = avx512 ? SimdLevel::avx512 : avx ? SimdLevel::avx : SimdLevel::sse2;
  EXPECT_EQ(cpu_simd_level(), expected) << *flags;
  RecordProperty("cpu_simd_level", simd_level_name(cpu_simd_level()));
#endif
}

/// The vendor_id line of /proc/cpuinfo's first processor, or nullopt.
std::optional<std::string> cpuinfo_vendor() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("vendor_id", 0) == 0) return line;
  }
  return std::nullopt;
}

TEST(SimdLevel, CpuVendorIsTheOneTheKernelReports) {
#if !defined(__x86_64__)
  EXPECT_FALSE(cpu_is_intel());
#else
  const auto vendor = cpuinfo_vendor();
  if (!vendor) GTEST_SKIP() << "no /proc/cpuinfo vendor_id line";
  EXPECT_EQ(cpu_is_intel(), vendor->find("GenuineIntel") != std::string::npos) << *vendor;
#endif
}

// The DEM lanes' rule (docs/portability.md "DEM lane width"): four lanes instead of eight on an
// Intel CPU unless PPOHDEM_SIMD asks for eight; every other case keeps the level.
TEST(SimdLevel, DemLanesAreFourOnIntelUnlessEightAreAskedFor) {
  EXPECT_EQ(dem_simd_level(SimdLevel::avx512, false, true), SimdLevel::avx);
  EXPECT_EQ(dem_simd_level(SimdLevel::avx512, true, true), SimdLevel::avx512);
  EXPECT_EQ(dem_simd_level(SimdLevel::avx512, false, false), SimdLevel::avx512);
  EXPECT_EQ(dem_simd_level(SimdLevel::avx512, true, false), SimdLevel::avx512);
  for (const bool forced : {false, true}) {
    for (const bool intel : {false, true}) {
      EXPECT_EQ(dem_simd_level(SimdLevel::avx, forced, intel), SimdLevel::avx);
      EXPECT_EQ(dem_simd_level(SimdLevel::sse2, forced, intel), SimdLevel::sse2);
    }
  }
}

// AVX-512VL's encoding for the four lanes exactly where the rule above made them four (and the
// CPU has VL): never when PPOHDEM_SIMD names a level, nor on another vendor's or level's CPU.
TEST(SimdLevel, DemFourLanesTakeAvx512VlOnlyWhereTheRuleMadeThemFour) {
  EXPECT_TRUE(dem_four_lanes_avx512vl(SimdLevel::avx512, false, true, true));
  EXPECT_FALSE(dem_four_lanes_avx512vl(SimdLevel::avx512, false, true, false));
  EXPECT_FALSE(dem_four_lanes_avx512vl(SimdLevel::avx512, true, true, true));
  EXPECT_FALSE(dem_four_lanes_avx512vl(SimdLevel::avx512, false, false, true));
  for (const bool forced : {false, true}) {
    for (const bool intel : {false, true}) {
      for (const SimdLevel level : {SimdLevel::sse2, SimdLevel::avx}) {
        EXPECT_FALSE(dem_four_lanes_avx512vl(level, forced, intel, true));
        EXPECT_FALSE(dem_four_lanes_avx512vl(level, forced, intel, false));
      }
    }
  }
}

// Run by ctest once per value of PPOHDEM_SIMD (and unset): the level simd_level() gives, and the
// paths the dispatch sites take at it.
TEST(SimdLevel, ForcedLevelReachesEveryDispatch) {
  const char* env = std::getenv("PPOHDEM_SIMD");
  const std::optional<SimdLevel> forced = parse_simd_level(env != nullptr ? env : "");
  const SimdLevel cpu = cpu_simd_level();
  if (forced && *forced > cpu) {
    EXPECT_THROW((void)simd_level(), InputError) << "a level this CPU does not run must be refused";
    return;
  }
  const SimdLevel expected = forced.value_or(cpu);
  ASSERT_EQ(simd_level(), expected);
  using Simd = sdf::fast::TriangleTree::PacketSimd;
  const Simd packet = sdf::fast::TriangleTree::packet_simd_available();
  EXPECT_EQ(packet, expected == SimdLevel::avx512 ? Simd::avx512 : expected == SimdLevel::avx ? Simd::avx : Simd::sse2);
  // The DEM lanes: four on an Intel CPU with AVX-512 unless PPOHDEM_SIMD names a level.
  const auto vendor = cpuinfo_vendor();
  const bool intel = vendor && vendor->find("GenuineIntel") != std::string::npos;
  const SimdLevel dem = !forced && intel && expected == SimdLevel::avx512 ? SimdLevel::avx : expected;
  EXPECT_EQ(dem_simd_level(), dem);
  EXPECT_EQ(dem::fast::x4_contacts_available(), dem >= SimdLevel::avx);
  EXPECT_EQ(dem::fast::x8_contacts_available(), dem >= SimdLevel::avx512);
  const auto flags = cpuinfo_flags();
  const bool vl = flags && flags->find(" avx512vl ") != std::string::npos;
  EXPECT_EQ(dem::fast::x4_contacts_in_avx512vl(), dem == SimdLevel::avx && expected == SimdLevel::avx512 && vl);
  RecordProperty("simd_level", simd_level_name(expected));
  RecordProperty("dem_simd_level", simd_level_name(dem));
}

/// A legacy VTK file's bytes without its title line (line 2: program, host and date).
std::string vtk_without_title(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  EXPECT_TRUE(in.good()) << file;
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::size_t first = bytes.find('\n');
  const std::size_t second = first == std::string::npos ? first : bytes.find('\n', first + 1);
  EXPECT_NE(second, std::string::npos) << file;
  return second == std::string::npos ? bytes : bytes.substr(0, first + 1) + bytes.substr(second + 1);
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

/// `level`: a value of PPOHDEM_SIMD.
CommandResult ppohdem_at(const std::string& level, const std::string& arguments, const fs::path& cwd) {
  return run_shell("cd " + quoted(cwd) + " && PPOHDEM_SIMD=" + level + " '" + PPOHDEM_EXE + "' " + arguments + " 2>&1");
}
CommandResult ppohdem_at(SimdLevel level, const std::string& arguments, const fs::path& cwd) {
  return ppohdem_at(std::string(simd_level_name(level)), arguments, cwd);
}

/// The levels this CPU runs, narrowest first (at least sse2).
std::vector<SimdLevel> runnable_levels() {
  std::vector<SimdLevel> levels;
  for (const SimdLevel level : kAll) {
    if (level <= cpu_simd_level()) levels.push_back(level);
  }
  return levels;
}

// The fast builder's exact field (no band) of a CAD part with sharp edges, 41 x 29 x 41 nodes,
// 2 threads: sse2 takes the 2-lane packets, avx the 4-lane and avx512 the 8-lane traversal.
TEST(SimdLevels, FastSdfFieldIsTheSameBytesAtEveryLevel) {
  const fs::path dir = test::scratch_dir();
  std::string first;
  for (const SimdLevel level : runnable_levels()) {
    const fs::path out = dir / (std::string("fandisk_") + simd_level_name(level) + ".vtk");
    const CommandResult r = ppohdem_at(level,
                                       "voxelize --quiet --mesh " + quoted(test::fixture("meshes/fandisk.stl")) +
                                           " --cells 41 29 41 --box -0.6 -0.4 -0.6 0.6 0.4 0.6 --method fast "
                                           "--threads 2 --out " + quoted(out),
                                       dir);
    ASSERT_EQ(r.exit_code, 0) << simd_level_name(level) << ": " << r.output;
    const std::string bytes = vtk_without_title(out);
    ASSERT_GT(bytes.size(), 41u * 29u * 41u * 8u);
    if (first.empty()) {
      first = bytes;
    } else {
      EXPECT_TRUE(bytes == first) << out << " differs from the sse2 field";
    }
  }
  RecordProperty("levels", static_cast<int>(runnable_levels().size()));
}

// The fast engine on a colliding frictional bed (1152 spheres, 200 steps, ctest's threads): avx
// takes the four-lane contacts, avx512 the eight-lane ones (both the four-lane neighbour test),
// sse2 the one-at-a-time code, auto the CPU's own choice.
TEST(SimdLevels, FastDemTrajectoryIsTheSameBytesAtEveryLevel) {
  const fs::path root = test::scratch_dir();
  std::vector<std::string> first;
  const std::vector<std::string> files = {"frame_000100.csv", "frame_000200.csv", "final.csv", "energy.csv"};
  // auto too: on an Intel CPU with AVX-512 its four lanes take AVX-512VL's encoding, which no
  // named level does (dem_four_lanes_avx512vl).
  std::vector<std::string> levels;
  for (const SimdLevel level : runnable_levels()) levels.emplace_back(simd_level_name(level));
  levels.emplace_back("auto");
  for (const std::string& level : levels) {
    const fs::path dir = root / level;
    fs::create_directories(dir);
    const fs::path scene = test::write_bed(dir, 12, 12, 8, 200, 100);
    const CommandResult r =
        ppohdem_at(level, "simulate --quiet --engine fast " + quoted(scene), dir);  // OMP_NUM_THREADS from ctest
    ASSERT_EQ(r.exit_code, 0) << level << ": " << r.output;
    std::vector<std::string> bodies;
    for (const std::string& f : files) bodies.push_back(test::body(dir / "out" / f));
    ASSERT_GT(bodies[2].size(), 1152u * 10u) << "final.csv holds every particle";
    if (first.empty()) {
      first = bodies;
      continue;
    }
    for (std::size_t k = 0; k < files.size(); ++k) {
      EXPECT_TRUE(bodies[k] == first[k]) << level << ": " << files[k] << " differs from sse2's";
    }
  }
}

TEST(SimdLevels, BadValueStopsTheProgramWithAClearMessage) {
  const fs::path dir = test::scratch_dir();
  const CommandResult r = run_shell("cd " + quoted(dir) + " && PPOHDEM_SIMD=avx2 '" + PPOHDEM_EXE +
                                    "' voxelize --quiet --mesh " + quoted(test::fixture("meshes/box.stl")) +
                                    " --cells 5 5 5 --box -2 -2 -2 2 2 2 --out b.vtk 2>&1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("PPOHDEM_SIMD: expected sse2, avx, avx512 or auto, found 'avx2'"), std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace ppohdem
