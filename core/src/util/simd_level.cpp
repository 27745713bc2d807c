#include "ppohdem/simd_level.hpp"

#include <cstdlib>
#include <string>

#include "ppohdem/error.hpp"

namespace ppohdem {

const char* simd_level_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::avx512: return "avx512";
    case SimdLevel::avx: return "avx";
    case SimdLevel::sse2: break;
  }
  return "sse2";
}

SimdLevel cpu_simd_level() {
#if defined(__x86_64__) && defined(__GNUC__)
  // Also checks that the OS saves the AVX / AVX-512 registers (XGETBV).
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") != 0) return SimdLevel::avx512;
  if (__builtin_cpu_supports("avx") != 0) return SimdLevel::avx;
#endif
  return SimdLevel::sse2;
}

std::optional<SimdLevel> parse_simd_level(std::string_view text) {
  if (text.empty() || text == "auto") return std::nullopt;
  for (const SimdLevel level : {SimdLevel::sse2, SimdLevel::avx, SimdLevel::avx512}) {
    if (text == simd_level_name(level)) return level;
  }
  throw InputError("environment variable PPOHDEM_SIMD: expected sse2, avx, avx512 or auto, found '" +
                   std::string(text) + "'");
}

namespace {
/// PPOHDEM_SIMD's level, or nullopt when it is unset or auto.
std::optional<SimdLevel> forced_simd_level() {
  const char* text = std::getenv("PPOHDEM_SIMD");
  return parse_simd_level(text != nullptr ? text : "");
}

SimdLevel resolve_simd_level() {
  const SimdLevel cpu = cpu_simd_level();
  const std::optional<SimdLevel> forced = forced_simd_level();
  if (!forced) return cpu;
  if (*forced > cpu) {
    throw InputError(std::string("environment variable PPOHDEM_SIMD: '") + simd_level_name(*forced) +
                     "' is wider than this CPU or build runs (at most '" + simd_level_name(cpu) + "')");
  }
  return *forced;
}
}  // namespace

SimdLevel simd_level() {
  // A throw leaves the static uninitialized: the next call reports the error again.
  static const SimdLevel level = resolve_simd_level();
  return level;
}

bool cpu_is_intel() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  return __builtin_cpu_is("intel") != 0;
#else
  return false;
#endif
}

SimdLevel dem_simd_level(SimdLevel level, bool forced, bool intel) {
  return !forced && intel && level == SimdLevel::avx512 ? SimdLevel::avx : level;
}

bool dem_four_lanes_avx512vl(SimdLevel level, bool forced, bool intel, bool vl) {
  // Exactly where dem_simd_level's rule narrowed the lanes (its one definition of that case).
  return vl && level == SimdLevel::avx512 && dem_simd_level(level, forced, intel) == SimdLevel::avx;
}

bool dem_four_lanes_avx512vl() {
  static const bool vl = [] {
    const SimdLevel chosen = simd_level();  // throws first for a bad PPOHDEM_SIMD
    bool cpu_vl = false;
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    cpu_vl = __builtin_cpu_supports("avx512vl") != 0;
#endif
    return dem_four_lanes_avx512vl(chosen, forced_simd_level().has_value(), cpu_is_intel(), cpu_vl);
  }();
  return vl;
}

SimdLevel dem_simd_level() {
  static const SimdLevel level = [] {
    const SimdLevel chosen = simd_level();  // throws first for a bad PPOHDEM_SIMD
    return dem_simd_level(chosen, forced_simd_level().has_value(), cpu_is_intel());
  }();
  return level;
}

}  // namespace ppohdem
