#pragma once
/// \file load_log.hpp
/// loads.csv: the loads on every boundary (walls and objects) at their own interval, `[output]
/// loads_every = N` steps, optionally averaged over the interval (`loads_average = true`);
/// docs/objects.md "Loads output". One row per boundary per interval:
///
///   step,time,boundary,force_x,force_y,force_z,moment_x,moment_y,moment_z,samples
///   [-, s, - (index in the scene's boundaries: walls in file order, then objects), N x3,
///    N m x3 about the origin, number of steps averaged (1: the load at that step)]
///
/// F = -sum f_i is the force the particles exert on the boundary and M_0 = sum p_i x (-f_i)
/// its moment about the origin (BoundaryLoad, engine.hpp). Averaged: the mean over the steps
/// (step - N, step] of the load after each step, F_mean = (1/N) sum_k F_k; a row at the run's
/// last step, or after a restart inside an interval, averages the steps it has (`samples`).
/// The file is rewritten atomically on flush(), as energy.csv.
#include <filesystem>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"

namespace ppohdem::dem {

class LoadLog {
 public:
  /// `names`: a description of each boundary, written as comment lines under the run header.
  LoadLog(std::filesystem::path file, std::string header, std::vector<std::string> names);
  /// Add the loads after one step to the running sums (averaging).
  void accumulate(const std::vector<BoundaryLoad>& loads);
  /// One row per boundary: the mean of the accumulated loads (and reset the sums), or, with
  /// nothing accumulated, `loads` itself (samples = 1).
  void add(long step, double time, const std::vector<BoundaryLoad>& loads);
  void flush() const;
  /// After a restart at `step`: keep the rows of the file on disk up to that step (the
  /// checkpoint does not carry loads.csv); no file, no rows.
  void continue_from_disk(long step);

 private:
  std::filesystem::path file_;
  std::string header_;
  std::vector<std::string> names_;
  std::vector<std::string> rows_;
  std::vector<BoundaryLoad> sums_;
  long samples_ = 0;
};

}  // namespace ppohdem::dem
