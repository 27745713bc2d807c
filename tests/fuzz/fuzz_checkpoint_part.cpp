// libFuzzer target: the per-rank parts of a checkpoint (dem::decode_checkpoint_part). The
// input is the PAYLOAD, framed by checkpoint_frame.hpp (magic "PPOHDEMP"). An accepted part
// must be canonical: encoding it again gives back exactly the same file.
#include <vector>

#include "checkpoint_frame.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  const std::vector<std::uint8_t> file = fuzz::framed_payload(dem::kCheckpointPartMagic, data, size);
  fuzz::run_reader([&] {
    const dem::CheckpointPart part = dem::decode_checkpoint_part(file, "fuzz.bin");
    PPOHDEM_FUZZ_CHECK(dem::encode_checkpoint_part(part) == file);
  });
  return 0;
}
