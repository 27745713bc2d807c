// libFuzzer target: legacy input_params_update.dat (parse_update_params_input).
#include <cmath>

#include "fuzz_support.hpp"
#include "ppohdem/io/legacy_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  fuzz::run_reader([&] {
    const UpdateParamsInput in = parse_update_params_input(fuzz::as_text(data, size), "input_params_update.dat");
    // Promises of legacy_inputs.hpp for an accepted file.
    PPOHDEM_FUZZ_CHECK(in.domain_length.allFinite() && in.domain_length.minCoeff() > 0.0);
    PPOHDEM_FUZZ_CHECK(std::isfinite(in.time_finish) && in.time_finish > 0.0);
    for (int a = 0; a < 3; ++a) PPOHDEM_FUZZ_CHECK(in.window_nodes[a] >= 1 && in.window_start[a] >= 1);
    PPOHDEM_FUZZ_CHECK(in.velocity.allFinite() && in.rotation_axis.allFinite() && in.centroid.allFinite());
    PPOHDEM_FUZZ_CHECK(std::isfinite(in.omega_pi_rad_per_w));
  });
  return 0;
}
