// libFuzzer target: legacy input_constants_voxelizer.dat (parse_voxelizer_input).
#include <cmath>

#include "fuzz_support.hpp"
#include "ppohdem/io/legacy_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  fuzz::run_reader([&] {
    const VoxelizerInput in = parse_voxelizer_input(fuzz::as_text(data, size), "input_constants_voxelizer.dat");
    // Promises of legacy_inputs.hpp for an accepted file.
    PPOHDEM_FUZZ_CHECK(!in.mesh_file.empty() && !in.output_dir.empty());
    PPOHDEM_FUZZ_CHECK(in.voxels[0] >= 1 && in.voxels[1] >= 1 && in.voxels[2] >= 1);
    PPOHDEM_FUZZ_CHECK(in.length.allFinite() && in.length.minCoeff() > 0.0);
    PPOHDEM_FUZZ_CHECK(in.object_size.allFinite() && in.object_size.minCoeff() > 0.0);
    PPOHDEM_FUZZ_CHECK(in.object_position.allFinite());
  });
  return 0;
}
