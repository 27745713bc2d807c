#pragma once
// `ppohdem simulate` under mpirun, as the fast engine's MPI command-line tests run it
// (fast_mpi_cli_test.cpp, mesh_object_mpi_cli_test.cpp). Needs PPOHDEM_EXE and PPOHDEM_MPIEXEC.
#include <filesystem>
#include <string>

#include "../apps/cli_runner.hpp"

namespace ppohdem::test {

/// `ppohdem simulate <scene> <args>` under mpirun with P ranks and T threads per rank.
inline CommandResult run_mpi(int ranks, int threads, const std::filesystem::path& scene, const std::string& args) {
  const std::string command = "env OMP_NUM_THREADS=" + std::to_string(threads) +
                              " OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"
                              // Waiting ranks yield the core and are not pinned: on a shared
                              // 2-core machine spinning, pinned ranks and threads wait for each
                              // other's descheduled partner (docs/dem.md "Domain decomposition").
                              " OMPI_MCA_mpi_yield_when_idle=1 OMP_WAIT_POLICY=passive '" +
                              std::string(PPOHDEM_MPIEXEC) + "' -n " + std::to_string(ranks) + " --oversubscribe --bind-to none '" +
                              std::string(PPOHDEM_EXE) + "' simulate '" + scene.string() + "' " + args + " 2>&1";
  return run_shell(command);
}

}  // namespace ppohdem::test
