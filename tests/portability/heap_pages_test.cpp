// Huge pages for the heap (ppohdem/heap_pages.hpp, docs/performance.md "Huge pages for long
// runs"):
// - PPOHDEM_HUGE_PAGES's values are parsed as documented and a bad one stops `simulate` with a
//   clear error;
// - the requests cover the heap's whole huge-page blocks, the new ones only as it grows; the
//   oracle is the kernel's own view, the `hg` (MADV_HUGEPAGE) flag of the mapping in
//   /proc/self/smaps, not the function's return value;
// - a run with the pages asked for writes the same bytes as one without, and says what it asked.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "../apps/cli_runner.hpp"
#include "../dem_fast/bed_scene.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/heap_pages.hpp"
#include "test_paths.hpp"

namespace ppohdem {
namespace {
namespace fs = std::filesystem;
using test::CommandResult;
using test::run_shell;

TEST(HugePages, ParsesTheDocumentedValues) {
  EXPECT_EQ(parse_huge_pages(""), HugePages::kAuto);
  EXPECT_EQ(parse_huge_pages("auto"), HugePages::kAuto);
  EXPECT_EQ(parse_huge_pages("on"), HugePages::kOn);
  EXPECT_EQ(parse_huge_pages("off"), HugePages::kOff);
  for (const char* bad : {"yes", "ON", "1", "auto "}) {
    try {
      (void)parse_huge_pages(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("PPOHDEM_HUGE_PAGES: expected on, off or auto, found '" + std::string(bad) + "'"),
                std::string::npos)
          << e.what();
    }
  }
}

/// The kernel's huge-page size, or 0 where it has none (then nothing is asked).
std::uintptr_t huge_page_bytes() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/hpage_pmd_size");
  std::uintptr_t bytes = 0;
  return in >> bytes ? bytes : 0;
}

/// Whether the mapping that holds `address` carries the MADV_HUGEPAGE flag ("hg") in
/// /proc/self/smaps.
bool flagged_for_huge_pages(std::uintptr_t address) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long long from = 0, to = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> from >> dash >> to && dash == '-' && line.find(' ') != std::string::npos &&
        line.find(':') > line.find(' ')) {
      inside = address >= from && address < to;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return (line + " ").find(" hg ") != std::string::npos;
  }
  return false;
}

TEST(HugePages, RequestsCoverTheHeapAndThenOnlyWhatItGrew) {
#if !defined(__linux__) || !defined(__GLIBC__)
  GTEST_SKIP() << "Linux with glibc only";
#else
  const std::uintptr_t page = huge_page_bytes();
  if (page == 0) GTEST_SKIP() << "this kernel has no transparent huge pages";
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // as apps/main.cpp: MB blocks from the heap
  (void)back_heap_with_huge_pages();
  const std::size_t first = heap_bytes_asked_for_huge_pages();
  EXPECT_EQ(first % page, 0u);
  EXPECT_EQ(back_heap_with_huge_pages(), 0u) << "nothing new: nothing asked";
  // Grow the heap by 6 blocks: the next request covers at least 5 whole new ones, and the
  // kernel flags the block's mapping.
  const std::size_t grown = 6 * page;
  auto* block = static_cast<char*>(std::malloc(grown));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, grown);
  const std::size_t added = back_heap_with_huge_pages();
  EXPECT_GE(added, 5 * page);
  EXPECT_EQ(added % page, 0u);
  EXPECT_EQ(heap_bytes_asked_for_huge_pages(), first + added);
  const auto middle = reinterpret_cast<std::uintptr_t>(block) + grown / 2;
  EXPECT_TRUE(flagged_for_huge_pages(middle)) << "the grown heap's mapping has no hg flag";
  EXPECT_EQ(block[grown / 2], 1) << "the contents survive the collapse";
  std::free(block);
#endif
}

std::string quoted(const fs::path& p) {
  std::string q = "'";  // appended, not "'" + ...: GCC 12 warns falsely on that (-Wrestrict)
  q += p.string();
  q += "'";
  return q;
}

CommandResult simulate_with(const std::string& value, const fs::path& scene, const fs::path& cwd) {
  return run_shell("cd " + quoted(cwd) + " && PPOHDEM_HUGE_PAGES=" + value + " '" + PPOHDEM_EXE + "' simulate --engine fast " +
                   quoted(scene) + " 2>&1");
}

TEST(HugePages, RunsWithThemWriteTheSameBytesAndSaySo) {
  const fs::path root = test::scratch_dir();
  std::vector<std::string> bodies;
  for (const std::string value : {"off", "on"}) {
    const fs::path dir = root / value;
    fs::create_directories(dir);
    const fs::path scene = test::write_bed(dir, 10, 10, 6, 150, 0);
    const CommandResult r = simulate_with(value, scene, dir);
    ASSERT_EQ(r.exit_code, 0) << value << ": " << r.output;
    const bool said = r.output.find("of the heap asked for in huge pages (PPOHDEM_HUGE_PAGES on)") != std::string::npos;
    EXPECT_EQ(said, value == "on") << r.output;
    bodies.push_back(test::body(dir / "out" / "final.csv") + test::body(dir / "out" / "energy.csv"));
    ASSERT_GT(bodies.back().size(), 600u * 10u);
  }
  EXPECT_TRUE(bodies[0] == bodies[1]) << "final.csv or energy.csv differ with the huge pages asked for";
}

TEST(HugePages, BadValueStopsSimulateWithAClearMessage) {
  const fs::path dir = test::scratch_dir();
  const fs::path scene = test::write_bed(dir, 4, 4, 2, 10, 0);
  const CommandResult r = simulate_with("yes", scene, dir);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("PPOHDEM_HUGE_PAGES: expected on, off or auto, found 'yes'"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace ppohdem
