// ppohdem: command-line entry point. Sub-commands live in cmd_*.cpp, one per command.
#include <cstdio>
#include <exception>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "commands.hpp"
#include "ppohdem/build_info.hpp"
#include "ppohdem/error.hpp"

/// Keeps freed heap memory in the process for reuse instead of returning it to the kernel.
/// The DEM engines free and reallocate MB-sized buffers at every neighbour-list build; with
/// glibc's defaults (mmap above a dynamic threshold, trim of the heap top) each build page
/// faults that memory in again, and page faults are dear on a virtual machine
/// (docs/performance.md "No page faults at list builds"). Peak RSS grows by the largest
/// transient buffers. Results are unaffected.
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // blocks below 32 MiB (glibc's largest allowed) from the heap
  mallopt(M_TRIM_THRESHOLD, -1);        // never trim the heap (-1 converts to the largest size)
#endif
}

int main(int argc, char** argv) {
  keep_freed_memory();
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
  ppohdem::app::register_project(app);
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
