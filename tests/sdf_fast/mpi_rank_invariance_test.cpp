// Run under mpirun at 1, 2 and 4 ranks: the field built distributed over the ranks (z-slabs,
// gathered on rank 0) must be bitwise identical to a serial build made in the same process on
// rank 0, for double and float storage, on a closed mesh and on an open one.
#include <cstdio>
#include <cstring>
#include <string>

#include "mpi_case.hpp"
#include "ppohdem/comm/comm.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"
#include "test_paths.hpp"

int main(int argc, char** argv) {
  using namespace ppohdem;
  test::MpiCase run(&argc, &argv);
  const Comm& comm = run.comm();
  for (const char* name : {"meshes/fandisk.stl", "meshes/bunny.stl"}) {
    const TriangleMesh mesh = read_stl(test::fixture(name));
    const BoundingBox box = bounding_box(mesh);
    // 21 z-planes: uneven slabs at 2 and 4 ranks, whose boundaries cut through 8^3 bricks.
    const GridSpec grid = GridSpec::spanning(box.min - 0.3 * box.extent(), box.max + 0.3 * box.extent(), {22, 19, 21});
    for (const double band : {0.0, 1.0}) {  // exact everywhere, and band mode (global bricks)
      sdf::fast::FastSdfOptions options;
      options.threads = 1;
      options.band_cells = band;
      const sdf::fast::FastSdfBuilder builder(options);
      const ScalarField distributed = sdf::fast::build_sdf_distributed(builder, comm, mesh, grid);
      const std::vector<float> distributed_float = sdf::fast::build_sdf_distributed_float(builder, comm, mesh, grid);
      if (comm.rank() == 0) {
        const ScalarField serial = builder.build(mesh, grid);
        const bool same = distributed.values.size() == serial.values.size() &&
                          std::memcmp(distributed.values.data(), serial.values.data(), serial.values.size() * sizeof(double)) == 0;
        bool same_float = distributed_float.size() == serial.values.size();
        for (std::size_t n = 0; same_float && n < serial.values.size(); ++n) {
          same_float = distributed_float[n] == static_cast<float>(serial.values[n]);
        }
        std::printf("%s band %g on %d ranks: double %s, float %s\n", name, band, comm.size(),
                    same ? "identical" : "DIFFERENT", same_float ? "identical" : "DIFFERENT");
        run.expect(same, std::string(name) + ": the double field differs");
        run.expect(same_float, std::string(name) + ": the float field differs");
      } else {
        run.expect(distributed.values.empty() && distributed_float.empty(),
                   "received field values; only rank 0 should");
      }
    }
  }
  return run.exit_code();
}
