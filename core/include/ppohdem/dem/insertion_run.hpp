#pragma once
/// \file insertion_run.hpp
/// The scene's [[insert]] tables during a run (run.hpp; insertion.hpp): at every step the
/// events due, the particles appended to the engine, <dir>/insertions.csv
///   step,time,insert,requested,inserted,failed,total_inserted,total_failed
/// (one row per event; `insert` is the table's index), a warning on stderr when particles
/// could not be inserted, and the checkpoint record (InsertionRecord).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/insertion.hpp"

namespace ppohdem::dem {

class InsertionRun {
 public:
  /// `writer`: this rank writes the file and the warnings.
  InsertionRun(const SimulationSetup& setup, const std::vector<InsertSpec>& specs, std::filesystem::path file,
               std::string header, bool writer);
  bool active() const { return !specs_.empty(); }
  /// Inserts the particles due at the engine's step (collective with several ranks: every rank
  /// calls it). Events after step 0 add their particles' energy to input().
  void at_step(DemEngine& engine);
  /// The wall time of this rank's at_step calls so far [s].
  double seconds() const { return seconds_; }
  /// The kinetic, rotational and gravitational energy brought in after step 0 [J].
  Energies input() const;
  std::int64_t inserted() const;
  std::int64_t failed() const;
  void flush() const;
  const InsertionRecord& record() const { return record_; }
  /// Continue from a checkpoint's record (InputError naming `source` if it does not fit).
  void restore(const InsertionRecord& record, const std::string& source);

 private:
  void insert_due(DemEngine& engine);  ///< at_step's work

  const SimulationSetup& setup_;
  std::vector<InsertSpec> specs_;
  std::filesystem::path file_;
  std::string header_;
  bool writer_;
  InsertionRecord record_;
  double seconds_ = 0.0;
};

}  // namespace ppohdem::dem
