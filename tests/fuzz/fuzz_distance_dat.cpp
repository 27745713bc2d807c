// libFuzzer target: the original program's distance_NNNN.dat files (read_distance_dat_bytes).
// The input is split at NUL bytes into rank files 0, 1, 2, ... (the files are text, so a NUL
// never occurs in a real one); at most 16 ranks are formed.
#include <string_view>
#include <vector>

#include "fuzz_support.hpp"
#include "ppohdem/io/distance_dat.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  constexpr std::size_t kMaxRanks = 16;
  const std::string_view input = fuzz::as_text(data, size);
  std::vector<std::string_view> ranks;
  std::size_t start = 0;
  while (ranks.size() + 1 < kMaxRanks) {
    const std::size_t nul = input.find('\0', start);
    if (nul == std::string_view::npos) break;
    ranks.push_back(input.substr(start, nul - start));
    start = nul + 1;
  }
  ranks.push_back(input.substr(start));

  fuzz::run_reader([&] {
    const DistanceDat dat = read_distance_dat_bytes(ranks, "fuzz");
    PPOHDEM_FUZZ_CHECK(dat.nprocs >= 1 && static_cast<std::size_t>(dat.nprocs) <= ranks.size());
    const auto count = checked_node_count(dat.nodes);
    PPOHDEM_FUZZ_CHECK(count.has_value() && dat.values.size() == *count);
  });
  return 0;
}
