// ppohdem: command-line entry point. Sub-commands live in cmd_*.cpp, one per command.
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "ppohdem/build_info.hpp"
#include "ppohdem/error.hpp"

int main(int argc, char** argv) {
  // MPI_Init/MPI_Finalize (a one-rank SerialComm without MPI); before CLI parsing, which must not
  // see mpirun's arguments.
  const ppohdem::CommEnvironment comm_environment(&argc, &argv);
  CLI::App app{"ppohdem: verified DEM and signed-distance-field tools (ppOpen-APPL/DEM re-creation)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("ppohdem ") + ppohdem::build_info::kVersion +
                                        " (git " + ppohdem::build_info::kGitHash + ")");
  ppohdem::app::register_mesh_info(app);
  ppohdem::app::register_voxelize(app, comm_environment.world());
  ppohdem::app::register_simulate(app);
  ppohdem::app::register_validate(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ppohdem::app::ExitStatus& e) {
    return e.code;
  } catch (const ppohdem::InputError& e) {
    std::fprintf(stderr, "ppohdem: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
