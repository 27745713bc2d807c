// `--compat ppohdem-1.0` DEM (reference/compat/include/ppohdem/compat/ppohdem10_dem.hpp) against the original program's
// own outputs (fixtures/ppohdem-1.0/dem-sample/, the patched original's full-precision dumps and
// its data/outNNN.dat, objects_distanceNNN.csv, objNNN.pov files). The oracle is the original
// Fortran program as it ran: nothing here was produced by ppohdem.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "ppohdem10_dem_format.hpp"  // reference/compat/src (private header)
#include "ppohdem/error.hpp"
#include "ppohdem10_dem_sample.hpp"

namespace ppohdem::compat {
namespace {

using namespace test_support;
using C = Ppohdem10DemConstants;

// ---------------------------------------------------------------------------------------------
// Constants and formats

TEST(Ppohdem10DemConstants, AreTheFloatRoundedDoublesTheOriginalUses) {
  // Oracle: the original's README (§2 "Hard-coded parameters"), values printed by the original.
  EXPECT_EQ(C::kTimeStep, 0.0020000000949949026);
  EXPECT_EQ(C::kPi, 3.1415927410125732);
  EXPECT_EQ(C::kRadius, 0.10000000149011612);
  EXPECT_EQ(C::kTangentialDamping, 0.10000000149011612);
  EXPECT_EQ(C::kInertia, 0.10000000149011612);
  EXPECT_EQ(C::kFriction, 0.5774000287055969);
  EXPECT_EQ(C::kGravity, 0.009999999776482582);
}

TEST(Ppohdem10DemFormats, WriteWhatGfortranWrote) {
  // Oracle: text from the original's files (out001.dat E16.6, objects_distance001.csv
  // list-directed, obj001.pov F12.8, the dumps ES25.17), with the doubles they print.
  EXPECT_EQ(fortran::e_format(0.249656369681834023, 16, 6), "    0.249656E+00");
  EXPECT_EQ(fortran::e_format(5.5, 16, 6), "    0.550000E+01");
  EXPECT_EQ(fortran::e_format(-0.0123456789, 16, 6), "   -0.123457E-01");
  EXPECT_EQ(fortran::list_directed_real(4.9831618753839084), "4.9831618753839084");
  EXPECT_EQ(fortran::list_directed_real(0.67367042725224469), "0.67367042725224469");
  EXPECT_EQ(fortran::list_directed_real(-0.10976668043080949), "-0.10976668043080949");
  EXPECT_EQ(fortran::list_directed_real(9.9534405509978899E-002), "9.9534405509978899E-002");
  EXPECT_EQ(fortran::list_directed_real(-9.9204610091712261E-002), "-9.9204610091712261E-002");
  EXPECT_EQ(fortran::list_directed_real(441.73683999999997), "441.73683999999997");
  EXPECT_EQ(fortran::f_format(-2.62868421, 12, 8), " -2.62868421");
  EXPECT_EQ(fortran::es_format(2.49656369681834023E-01, 25, 17), "  2.49656369681834023E-01");
  EXPECT_EQ(fortran::es_format(-2.00000005029141691E-05, 25, 17), " -2.00000005029141691E-05");
  EXPECT_EQ(fortran::es_format(0.0, 25, 17), "  0.00000000000000000E+00");
}

TEST(Ppohdem10DemFormats, StateDumpRoundTripsByteForByte) {
  // The patched original wrote these dumps ((I6,16ES25.17,2I4)); parse + format must give its
  // bytes back, so our ES25.17 is gfortran's on 600 x 16 values of every magnitude.
  for (const char* name : {"state_step000001.dat", "state_step050000.dat", "state_final.dat"}) {
    const std::string text = ppohdem::test::read_xz_file(dem_fixture(std::string("fullprec/") + name + ".xz"));
    EXPECT_TRUE(format_ppohdem10_state(parse_ppohdem10_state(text, name)) == text) << name;
  }
}

TEST(Ppohdem10DemFormats, StateReaderNamesFileAndLine) {
  try {
    (void)parse_ppohdem10_state("# step 0 rtime 0.0 n 1\n 1 2 3\n", "bad.dat");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.dat:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("19 columns"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// The re-sort

TEST(Ppohdem10Sort, EqualKeysArePermutedAsHoarePartitionDoes) {
  // Hand-traced ppohDEM_iqsort2 on 4 equal keys: swap(1,4), swap(2,3), then (1,2) and (3,4)
  // are swapped again: values 1 2 3 4 end as 3 4 1 2. A stable sort would leave 1 2 3 4.
  std::vector<int> keys = {5, 5, 5, 5};
  std::vector<int> values = {1, 2, 3, 4};
  ppohdem10_iqsort2(keys, values, 1, 4);
  EXPECT_EQ(values, (std::vector<int>{3, 4, 1, 2}));
}

RC_GTEST_PROP(Ppohdem10Sort, SortsKeysAndCarriesTheirValues, (std::vector<int> raw)) {
  RC_PRE(!raw.empty());
  std::vector<int> keys = raw;
  for (int& k : keys) k = 1 + std::abs(k % 50);  // cell numbers, many equal
  std::vector<int> values(keys.size());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<int>(i + 1);
  const std::vector<int> original = keys;
  ppohdem10_iqsort2(keys, values, 1, static_cast<int>(keys.size()));
  RC_ASSERT(std::is_sorted(keys.begin(), keys.end()));
  std::vector<int> seen = values;
  std::sort(seen.begin(), seen.end());
  for (std::size_t i = 0; i < seen.size(); ++i) RC_ASSERT(seen[i] == static_cast<int>(i + 1));  // a permutation
  for (std::size_t i = 0; i < keys.size(); ++i) RC_ASSERT(keys[i] == original[static_cast<std::size_t>(values[i] - 1)]);
}

// ---------------------------------------------------------------------------------------------
// The run from the original's initial state

// The sample from the original's state_step000000.dat, run to `last_step`; the frames written
// on the way are kept if asked. (150,000 steps: ci/compat_dem_full.sh.)
struct SampleRun {
  Ppohdem10State state;
  std::map<int, std::string> frames;  // data/outNNN.dat text
  long outside_box = 0;
};

SampleRun run_sample_to(long last_step, bool keep_frames) {
  const fs::path dir = ppohdem::test::scratch_dir();
  lay_out_sample(dir);
  Ppohdem10Dem dem(read_ppohdem10_dem_input(dir / "input_params_update.dat", dir, dir / "state_step000000.dat"));
  SampleRun r;
  while (dem.counter().itime < last_step) {
    const Ppohdem10StepEvents e = dem.step();
    if (e.frame && keep_frames) r.frames[dem.counter().file_index] = dem.frame_text();
  }
  r.state = dem.state();
  r.outside_box = dem.particles().outside_box_count;
  return r;
}

std::string original_frame(int frame) {
  // The 300 frames are stored back to back; each has 600 lines of 4 x 16 characters + '\n'.
  static const std::string all = ppohdem::test::read_xz_file(dem_fixture("data/out001_to_out300.dat.xz"));
  constexpr std::size_t kBytes = 600 * 65;
  return all.substr(static_cast<std::size_t>(frame - 1) * kBytes, kBytes);
}

std::string dump_name(long step) {
  char name[64];
  std::snprintf(name, sizeof name, "state_step%06ld.dat", step);
  return name;
}

void expect_bitwise(const Ppohdem10State& ours, const Ppohdem10State& original) {
  EXPECT_EQ(ours.step, original.step);
  EXPECT_EQ(bits(ours.rtime), bits(original.rtime)) << "rtime, accumulated in steps of the float-rounded dt";
  const StateDiff d = compare_states(ours, original);
  ASSERT_TRUE(d.same_ids);
  // The issue asks for 1e-12 relative; the mirrored operation order gives every one of the
  // 9,600 doubles (x, v, omega, r, F, t of 600 particles) bit for bit, so that is required.
  EXPECT_LE(d.max_relative, 1e-12);
  EXPECT_EQ(d.bitwise_equal, d.values) << "max relative difference " << d.max_relative;
  EXPECT_EQ(d.count_mismatches, 0u) << "particles whose contact counts differ";
}

class Ppohdem10DemDump : public ::testing::TestWithParam<long> {};

TEST_P(Ppohdem10DemDump, StateIsTheOriginalsBitForBit) {
  // Before step 5000 nothing touches anything (original README §2): these check the free
  // flight, the float-rounded constants, the object force of the corner field and rtime.
  const long step = GetParam();
  expect_bitwise(run_sample_to(step, false).state, original_state(dump_name(step)));
}

INSTANTIATE_TEST_SUITE_P(Steps, Ppohdem10DemDump, ::testing::Values(1L, 2L, 10L, 100L, 500L, 1000L, 5000L));

TEST(Ppohdem10Dem, Step50000AndItsFramesAreTheOriginalsBitForBit) {
  // 50,000 steps: particles have hit the turning cube, the walls and each other.
  const SampleRun run = run_sample_to(50000, true);
  expect_bitwise(run.state, original_state(dump_name(50000)));
  // Guard that this exercises the contact code: the original's dump holds 72 particle-contact
  // entries and 136 wall contacts here.
  int pairs = 0;
  int walls = 0;
  for (const Ppohdem10ParticleRecord& r : run.state.particles) {
    pairs += r.ncontact;
    walls += r.ncontact_wall;
  }
  EXPECT_EQ(pairs, 72);
  EXPECT_EQ(walls, 136);
  // A fast particle (id 500, 1.67 m/s towards y = 0) passes its centre through the wall near
  // step 40300 in the original too (its out081.dat row has y = 0.0119601 on the way back).
  EXPECT_GT(run.outside_box, 0);

  // data/outNNN.dat of frames 1..100: first at printed precision with rows matched as sets
  // (the original re-sorts its rows by cell), then byte for byte, row order included (the
  // unstable quicksort and its stale cell indices are mirrored too).
  ASSERT_EQ(run.frames.size(), 100u);
  auto rows = [](const std::string& text) {
    std::vector<std::string> r;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) r.push_back(line);
    std::sort(r.begin(), r.end());
    return r;
  };
  for (const auto& [frame, ours] : run.frames) {
    const std::string original = original_frame(frame);
    EXPECT_EQ(rows(ours), rows(original)) << "frame " << frame << ": the printed rows differ as sets";
    EXPECT_TRUE(ours == original) << "frame " << frame << " is not byte-identical";
  }
}

// The whole run, 150,000 steps (three times the test above): too long for every CI run, so
// disabled here; run it with ci/compat_dem_full.sh (--gtest_also_run_disabled_tests).
TEST(Ppohdem10DemFull, DISABLED_FinalStateAndAll300FramesAreTheOriginalsBitForBit) {
  const SampleRun run = run_sample_to(150000, true);
  expect_bitwise(run.state, original_state("state_final.dat"));
  ASSERT_EQ(run.frames.size(), 300u);
  int identical = 0;
  for (const auto& [frame, ours] : run.frames) {
    if (ours == original_frame(frame)) ++identical;
    EXPECT_TRUE(ours == original_frame(frame)) << "frame " << frame << " is not byte-identical";
  }
  std::printf("%d of 300 frames byte-identical; %ld re-sorts with a centre outside the box\n", identical,
              run.outside_box);
}

TEST(Ppohdem10Dem, RestartFromAStateWithoutContactsIsBitwise) {
  // At step 500 no particle touches anything (the original's dump: all contact counts 0), so
  // neither the unknown contact history nor the unknown particle order matters: a start from
  // state_step000500.dat must reach the original's step 1000 bit for bit.
  const fs::path dir = ppohdem::test::scratch_dir();
  lay_out_sample(dir);
  write_bytes(dir / "state_step000500.dat", ppohdem::test::read_xz_file(dem_fixture("fullprec/state_step000500.dat.xz")));
  Ppohdem10Dem dem(read_ppohdem10_dem_input(dir / "input_params_update.dat", dir, dir / "state_step000500.dat"));
  while (dem.counter().itime < 1000) dem.step();
  const StateDiff d = compare_states(dem.state(), original_state("state_step001000.dat"));
  EXPECT_EQ(d.bitwise_equal, d.values);
}

// ---------------------------------------------------------------------------------------------
// The object: field and picture per frame (they do not depend on the particles)

TEST(Ppohdem10DemObject, FieldAndPovAreTheOriginalsByteForByte) {
  const fs::path dir = ppohdem::test::scratch_dir();
  lay_out_sample(dir);
  const Ppohdem10DemInput input =
      read_ppohdem10_dem_input(dir / "input_params_update.dat", dir, dir / "state_step000000.dat");
  const Ppohdem10Dem dem(input);
  EXPECT_TRUE(dem.object_field_csv() ==
              ppohdem::test::read_xz_file(dem_fixture("objects_distance/objects_distance_init.csv.xz")))
      << "the initial field (the data grid's corner)";
  for (const int frame : {1, 2, 10, 100, 150, 300}) {
    // A run at that frame: the state at step 500 f with the field of frame f.
    Ppohdem10DemInput at_frame = input;
    at_frame.initial.step = 500L * frame;
    const Ppohdem10Dem later(at_frame);
    char csv[64];
    char pov[64];
    std::snprintf(csv, sizeof csv, "objects_distance/objects_distance%03d.csv.xz", frame);
    std::snprintf(pov, sizeof pov, "obj/obj%03d.pov", frame);
    EXPECT_TRUE(later.object_field_csv() == ppohdem::test::read_xz_file(dem_fixture(csv))) << csv;
    EXPECT_TRUE(later.object_pov() == read_file_bytes(dem_fixture(pov))) << pov;
  }
}

}  // namespace
}  // namespace ppohdem::compat
