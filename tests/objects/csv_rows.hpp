#pragma once
// The data rows of a ppohdem CSV output (energy.csv, objects.csv, final.csv) as doubles:
// provenance comment lines ('#') and the header (it starts with a letter: "step", "id") are
// skipped.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ppohdem::test {

inline std::vector<std::vector<double>> numeric_csv_rows(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || std::isalpha(static_cast<unsigned char>(line[0]))) continue;
    std::vector<double> row;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace ppohdem::test
