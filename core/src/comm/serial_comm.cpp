/// \file serial_comm.cpp
/// The communicator environment when the build has no MPI: one rank, SerialComm.
#include "ppohdem/comm/comm.hpp"

namespace ppohdem {

bool mpi_available() { return false; }

CommEnvironment::CommEnvironment(int* /*argc*/, char*** /*argv*/) : world_(std::make_unique<SerialComm>()) {}

CommEnvironment::~CommEnvironment() = default;

}  // namespace ppohdem
