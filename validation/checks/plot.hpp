#pragma once
// Plotting for check groups: a group writes its data as CSV in CheckContext::work_dir and calls
// run_plot, which runs validation/checks/plot_validation.py with /usr/bin/python3 (matplotlib;
// override with the environment variable PPOHDEM_PYTHON). A missing Python or matplotlib only
// prints a warning: plots illustrate the report, the checks are the rows.
#include <string>
#include <vector>

#include "ppohdem/validation/check_registry.hpp"

namespace ppohdem::validation {

/// Writes rows of numbers with a header line to `path` (comma-separated, %.10g).
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& rows);

/// `s` as one POSIX shell word: in single quotes, each ' written as '\'' .
std::string shell_quote(const std::string& s);

/// Runs `plot_validation.py KIND CSV PNG [extra...]`; PNG is a file name in ctx.img_dir.
/// Returns false (and warns on stderr) if the plot could not be made.
bool run_plot(const CheckContext& ctx, const std::string& kind, const std::string& csv,
              const std::string& png, const std::vector<std::string>& extra = {});

}  // namespace ppohdem::validation
