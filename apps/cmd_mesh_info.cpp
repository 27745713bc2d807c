// `ppohdem mesh-info MESH.stl`: read an STL (ASCII or binary) and print its statistics.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/mesh/stl_io.hpp"

namespace ppohdem::app {

void register_mesh_info(CLI::App& app) {
  auto* cmd = app.add_subcommand("mesh-info", "Read an STL mesh and print its statistics");
  auto path = std::make_shared<std::string>();
  cmd->add_option("mesh", *path, "STL file (ASCII or binary)")->required();
  cmd->callback([path] {
    StlReadReport report;
    const TriangleMesh mesh = read_stl(*path, &report);
    const MeshStats stats = compute_mesh_stats(mesh);
    std::printf("%s: %s STL\n%s", path->c_str(),
                report.encoding == StlEncoding::kAscii ? "ASCII" : "binary",
                format_mesh_stats(stats).c_str());
  });
}

}  // namespace ppohdem::app
