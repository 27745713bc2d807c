#pragma once
/// \file heap_pages.hpp
/// Transparent huge pages (2 MiB) for the process's heap, asked for by long runs: the DEM reads
/// its whole state (MBs to GBs) at every step, and in 2 MiB pages it misses the TLB far less,
/// which on a virtual machine (two levels of page tables to walk) is worth a few per cent of a
/// step. Touching a huge page the first time costs more than the small pages it replaces, so
/// only runs long enough to repay it ask (docs/performance.md "Huge pages for long runs").
/// Results are unaffected: only speed and resident memory.
#include <cstddef>
#include <string_view>

namespace ppohdem {

/// The environment variable PPOHDEM_HUGE_PAGES: "auto" or unset (the caller's rule: `simulate`
/// asks for runs of at least 1,000 steps with at least 10,000 particles a thread), "on" or "off".
enum class HugePages { kAuto, kOn, kOff };

/// A value of PPOHDEM_HUGE_PAGES ("" is auto). Throws InputError naming the variable and the
/// accepted values for anything else.
HugePages parse_huge_pages(std::string_view text);

/// PPOHDEM_HUGE_PAGES's value, read at each call.
HugePages huge_pages_setting();

/// Asks the kernel to back the heap's whole huge-page blocks that no earlier call covered (from
/// the heap's start, or from where the last call ended, to the heap's current end) with huge
/// pages: madvise MADV_HUGEPAGE for the pages touched from now on, then MADV_COLLAPSE for those
/// already touched. The heap grows as a run goes on, so a long run calls this now and then; a
/// call that finds nothing new costs a comparison. Returns the bytes newly covered: 0 when
/// nothing is new, or on systems without transparent huge pages (not Linux, or the kernel
/// refuses; a refusal is not an error, the pages stay small).
std::size_t back_heap_with_huge_pages();

/// The bytes of the heap covered by back_heap_with_huge_pages so far.
std::size_t heap_bytes_asked_for_huge_pages();

}  // namespace ppohdem
