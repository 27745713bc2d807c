#pragma once
// Table and Markdown report of `ppohdem validate` (provenance first, then one table per group).
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "ppohdem/validation/check_registry.hpp"

namespace ppohdem::validation {

struct GroupResult {
  const CheckGroup* group = nullptr;
  std::vector<CheckRow> rows;
  double seconds = 0.0;  ///< wall time of the group [s]
};

struct ReportInfo {
  std::string mode;  ///< "quick" or "full"
  bool live = false;
  std::vector<std::string> engines;
  double total_seconds = 0.0;
  std::string command;
};

/// Provenance lines: version, git hash, compiler and flags, ranks, threads, CPU, date, load.
std::vector<std::pair<std::string, std::string>> provenance_fields();

/// Plain-text table on a terminal.
void print_table(std::ostream& os, const std::vector<GroupResult>& results);

/// The Markdown report; plot links are relative to `report_dir`.
void write_markdown_report(std::ostream& os, const ReportInfo& info,
                           const std::vector<GroupResult>& results,
                           const std::filesystem::path& report_dir);

}  // namespace ppohdem::validation
