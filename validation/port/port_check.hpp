#pragma once
// `ppohdem validate --port | --save-baseline DIR | --against DIR | --export-scenes DIR`
// (docs/port-validation.md): the chaotic tier's ensemble consistency test.
#include <map>
#include <string>
#include <vector>

#include "ensemble.hpp"

namespace ppohdem::port {

struct PortOptions {
  bool port = false;                  // --port: check this build against the baseline
  std::string save_baseline;          // --save-baseline DIR
  std::string against;                // --against DIR (default SOURCE/fixtures/port-baseline)
  std::string export_scenes;          // --export-scenes DIR
  std::vector<std::string> external;  // --external RUN1 RUN2 RUN3
  std::string out;                    // report file (default ./port-validation-report.md)
  std::string source_dir;             // checkout (fixtures/)
  std::string work_dir;               // scratch (default a temporary directory)
  std::vector<std::string> scenes;    // default: every scene of the baseline
  int members = 100;                  // fit members of a new baseline
  int held_out = 30;                  // held-out members (false-positive rate)
  int runs = 3;                       // a port's runs per scene
  long first_port_seed = 1001;        // seeds of the port's runs (not in the baseline)
  int jobs = 1;                       // simulations at once
  std::map<std::string, double> scale;  // known-bad change (--scale-parameter)
  std::string launcher;               // e.g. "mpirun -n 2" before each ppohdem simulate
  std::string engine = "fast";
  EnsembleRule rule;                  // for --save-baseline
  bool refit = false;                 // --save-baseline DIR --refit: new rule, the stored members
  bool growth_only = false;           // --save-baseline DIR --growth: only the growth diagnostic
  bool any() const {
    return port || !save_baseline.empty() || !against.empty() || !export_scenes.empty() || !external.empty();
  }
};

/// Runs the requested mode; returns the exit status (0 pass, 1 fail, 2 bad input).
int run_port_validation(const PortOptions& options, const std::string& command_line);

}  // namespace ppohdem::port
