// `ppohdem voxelize`: placeholder until the SDF issue lands.
#include "commands.hpp"

namespace ppohdem::app {
void register_voxelize(CLI::App&) {}
}  // namespace ppohdem::app
