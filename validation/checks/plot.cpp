#include "plot.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace ppohdem::validation {

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& rows) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  for (std::size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  char buf[64];
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.10g", row[i]);
      out << (i ? "," : "") << buf;
    }
    out << "\n";
  }
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q.append("'\\''");
    else q.push_back(c);
  }
  q.push_back('\'');
  return q;
}

bool run_plot(const CheckContext& ctx, const std::string& kind, const std::string& csv,
              const std::string& png, const std::vector<std::string>& extra) {
  const char* env = std::getenv("PPOHDEM_PYTHON");
  const std::string python = env != nullptr ? env : "/usr/bin/python3";
  const std::string script =
      (std::filesystem::path(ctx.source_dir) / "validation" / "checks" / "plot_validation.py").string();
  std::string cmd = shell_quote(python);
  cmd.append(" ").append(shell_quote(script)).append(" ").append(shell_quote(kind)).append(" ");
  cmd.append(shell_quote(csv)).append(" ");
  cmd.append(shell_quote((std::filesystem::path(ctx.img_dir) / png).string()));
  for (const auto& e : extra) cmd.append(" ").append(shell_quote(e));
  cmd.append(" 1>&2");
  const int rc = std::system(cmd.c_str());
  if (rc != 0) {
    std::fprintf(stderr, "[validate] warning: plot %s not made (%s exited %d)\n", png.c_str(),
                 python.c_str(), rc);
    return false;
  }
  return true;
}

}  // namespace ppohdem::validation
