#pragma once
// Run the `ppohdem` executable as a user would and capture exit code and output.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace ppohdem::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr, interleaved
};

/// Runs the shell command line `command` (add `2>&1` to capture stderr) and returns what it
/// printed on stdout and its exit code.
inline CommandResult run_shell(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) result.output += buffer.data();
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Runs `PPOHDEM_EXE <arguments>` (a shell command line; quote paths yourself) in `cwd`.
inline CommandResult run_ppohdem(const std::string& arguments, const std::string& cwd = ".") {
  return run_shell("cd '" + cwd + "' && '" + std::string(PPOHDEM_EXE) + "' " + arguments + " 2>&1");
}

}  // namespace ppohdem::test
