// libFuzzer target: the per-rank parts of a checkpoint (dem::decode_checkpoint_part). As for
// fuzz_checkpoint, the input is the PAYLOAD: the target wraps it in a valid header and trailer
// (magic "PPOHDEMP", version, this build, length, both CRCs) and decodes that. An accepted
// part must be canonical: encoding it again gives back exactly the same file.
#include <vector>

#include "fuzz_support.hpp"
#include "ppohdem/dem/checkpoint.hpp"

namespace {

void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  std::vector<std::uint8_t> file(dem::kCheckpointPartMagic, dem::kCheckpointPartMagic + 8);
  put_u32(file, dem::kCheckpointFormatVersion);
  const std::string build = dem::checkpoint_build_name();
  put_u32(file, static_cast<std::uint32_t>(build.size()));
  file.insert(file.end(), build.begin(), build.end());
  for (int k = 0; k < 8; ++k) file.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(size) >> (8 * k)));
  put_u32(file, dem::crc32_of(file.data(), file.size()));
  file.insert(file.end(), data, data + size);
  put_u32(file, dem::crc32_of(data, size));
  fuzz::run_reader([&] {
    const dem::CheckpointPart part = dem::decode_checkpoint_part(file, "fuzz.bin");
    PPOHDEM_FUZZ_CHECK(dem::encode_checkpoint_part(part) == file);
  });
  return 0;
}
