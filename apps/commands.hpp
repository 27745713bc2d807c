#pragma once
// Sub-command registration for the `ppohdem` tool. Each register_* adds a CLI11 subcommand
// whose callback runs the command; errors propagate as exceptions to main().
#include <CLI/CLI.hpp>

#include "ppohdem/comm/comm.hpp"

namespace ppohdem::app {
void register_mesh_info(CLI::App& app);
void register_voxelize(CLI::App& app, const ppohdem::Comm& comm);
void register_simulate(CLI::App& app, const ppohdem::Comm& comm);
void register_validate(CLI::App& app);
void register_project(CLI::App& app);

/// Thrown by a command that ends with a given exit status (not an error message).
struct ExitStatus {
  int code;
};
}  // namespace ppohdem::app
