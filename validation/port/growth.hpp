#pragma once
// The growth diagnostic (docs/port-validation.md "Growth diagnostic"): the RMS distance between
// the port's run of seed 1001 and the reference machine's run of the same seed, frame by frame,
// drawn over the envelope of the RMS distance between pairs of reference members. A port that
// differs by round-off starts below the envelope (bitwise equal: 0) and joins it as the
// trajectories part; a physics difference starts above it.
#include <filesystem>
#include <string>
#include <vector>

namespace ppohdem::port {

struct GrowthRow {
  long step = 0;
  double port = 0.0;                              // RMS port vs reference [m]; NaN if not judged
  double low = 0.0, median = 0.0, high = 0.0;     // members' pairwise RMS: min, median, max [m]
};

/// The seed whose reference trajectory the baseline keeps (the port's first run).
constexpr long kGrowthSeed = 1001;

/// DIR/<scene>.growth.csv from `pairs` (run folders, taken two by two) and the reference run of
/// kGrowthSeed: every frame step of the runs, the positions of every 10th particle (by id).
void save_growth(const std::filesystem::path& dir, const std::string& scene,
                 const std::vector<std::filesystem::path>& pairs, const std::filesystem::path& reference_run);

/// The rows of a port's run of kGrowthSeed against DIR/<scene>.growth.csv (empty if missing).
std::vector<GrowthRow> growth_rows(const std::filesystem::path& dir, const std::string& scene,
                                   const std::filesystem::path& port_run);

}  // namespace ppohdem::port
