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
  ppohdem::app::register_simulate(app, comm_environment.world());
  ppohdem::app::register_validate(app);
  // Under mpirun an error may reach some ranks only (e.g. rank 0 cannot write a file): end all
  // ranks then (MPI_Abort), rather than leave the others waiting in a collective.
  const ppohdem::Comm& world = comm_environment.world();
  auto failed = [&](int code) {
    if (world.size() > 1) {
      std::fflush(stderr);
      world.abort(code);
    }
    return code;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ppohdem::app::ExitStatus& e) {
    return e.code;
  } catch (const ppohdem::InputError& e) {
    std::fprintf(stderr, "ppohdem: error: %s\n", e.what());
    return failed(2);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem: error: %s\n", e.what());
    return failed(1);
  }
  return 0;
}
