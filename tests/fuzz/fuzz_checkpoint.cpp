// libFuzzer target: checkpoint files (dem::decode_checkpoint). The input is the PAYLOAD, framed
// by checkpoint_frame.hpp. An accepted payload must be canonical: encoding the decoded
// checkpoint again gives back exactly the same file.
#include <vector>

#include "checkpoint_frame.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  const std::vector<std::uint8_t> file = fuzz::framed_payload(dem::kCheckpointMagic, data, size);
  fuzz::run_reader([&] {
    const dem::Checkpoint c = dem::decode_checkpoint(file, "fuzz.bin");
    PPOHDEM_FUZZ_CHECK(dem::encode_checkpoint(c) == file);
  });
  return 0;
}
