// Huge pages for the heap (heap_pages.hpp). glibc's own switch, GLIBC_TUNABLES=
// glibc.malloc.hugetlb=1, is read only when the process starts and covers every run, short
// ones too; this asks for the heap of a run already known to be long (docs/performance.md
// "Huge pages for long runs").
#include "ppohdem/heap_pages.hpp"

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <string>

#include "ppohdem/error.hpp"

#if defined(__linux__) && defined(__GLIBC__)
#include <sys/mman.h>
#include <unistd.h>
#define PPOHDEM_HEAP_PAGES 1
#ifndef MADV_COLLAPSE
#define MADV_COLLAPSE 25  // Linux 6.1; glibc 2.36's headers do not name it
#endif
#endif

namespace ppohdem {

HugePages parse_huge_pages(std::string_view text) {
  if (text.empty() || text == "auto") return HugePages::kAuto;
  if (text == "on") return HugePages::kOn;
  if (text == "off") return HugePages::kOff;
  throw InputError("environment variable PPOHDEM_HUGE_PAGES: expected on, off or auto, found '" + std::string(text) +
                   "'");
}

HugePages huge_pages_setting() {
  const char* text = std::getenv("PPOHDEM_HUGE_PAGES");
  return parse_huge_pages(text != nullptr ? text : "");
}

namespace {
std::mutex heap_mutex;
std::uintptr_t covered_begin = 0;  ///< the first call's start of the heap's whole blocks; 0 before it
std::uintptr_t covered_end = 0;    ///< where the last call ended

#ifdef PPOHDEM_HEAP_PAGES
/// The kernel's huge-page size (2 MiB on x86-64; other sizes on some aarch64 kernels).
std::uintptr_t huge_page_bytes() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/hpage_pmd_size");
  std::uintptr_t bytes = 0;
  if (!(in >> bytes) || bytes == 0 || (bytes & (bytes - 1)) != 0) return 0;  // no THP, or unreadable
  return bytes;
}

/// The start of the [heap] mapping (/proc/self/maps), or the current break if there is none yet.
std::uintptr_t heap_start() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    if (line.size() >= 6 && line.compare(line.size() - 6, 6, "[heap]") == 0) {
      return static_cast<std::uintptr_t>(std::stoull(line.substr(0, line.find('-')), nullptr, 16));
    }
  }
  return reinterpret_cast<std::uintptr_t>(sbrk(0));
}
#endif
}  // namespace

std::size_t back_heap_with_huge_pages() {
#ifdef PPOHDEM_HEAP_PAGES
  static const std::uintptr_t page = huge_page_bytes();
  if (page == 0) return 0;
  const std::lock_guard lock(heap_mutex);
  if (covered_begin == 0) covered_begin = covered_end = (heap_start() + page - 1) & ~(page - 1);
  const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(page - 1);
  if (end <= covered_end) return 0;
  void* const from = reinterpret_cast<void*>(covered_end);
  const std::size_t bytes = end - covered_end;
  if (madvise(from, bytes, MADV_HUGEPAGE) != 0) return 0;  // a kernel without THP: stay small
  (void)madvise(from, bytes, MADV_COLLAPSE);  // may fail (older kernel, no free huge page): khugepaged may later
  covered_end = end;
  return bytes;
#else
  return 0;
#endif
}

std::size_t heap_bytes_asked_for_huge_pages() {
  const std::lock_guard lock(heap_mutex);
  return covered_end - covered_begin;
}

}  // namespace ppohdem
