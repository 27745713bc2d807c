#pragma once
// Runs the `ppohdem` program as a child process (the port check runs whole simulations, so a
// build, rank count or launcher under test is exercised exactly as a user runs it).
#include <string>
#include <vector>

namespace ppohdem::port {

/// Runs argv[0] with the arguments, stdout and stderr to `log_file` (appended; "" = inherited);
/// `launcher` words (e.g. "mpirun -n 2") go first. Returns the exit status (128 + signal if killed).
int run_program(const std::vector<std::string>& argv, const std::string& log_file,
                const std::vector<std::string>& launcher = {});

/// Runs several commands at once, at most `jobs` at a time; returns each one's exit status.
std::vector<int> run_programs(const std::vector<std::vector<std::string>>& commands,
                              const std::vector<std::string>& log_files, int jobs,
                              const std::vector<std::string>& launcher = {});

/// `ppohdem` next to this executable (both are built into apps/).
std::string find_ppohdem_program();

}  // namespace ppohdem::port
