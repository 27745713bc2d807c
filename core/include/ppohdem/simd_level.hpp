#pragma once
/// \file simd_level.hpp
/// The SIMD instruction set the optimized kernels use: the widest this CPU runs, or a narrower
/// one forced with the environment variable PPOHDEM_SIMD (docs/portability.md, "SIMD levels").
/// Every run-time dispatch (the SDF packet traversal, the DEM's four-lane contacts and
/// neighbour test) asks simd_level(); the results are the same bits at every level.
#include <optional>
#include <string_view>

namespace ppohdem {

/// Narrowest first. `sse2`: no wide lanes, the code every x86-64 CPU runs (on other machines,
/// e.g. aarch64, the portable code and the only level).
enum class SimdLevel { sse2, avx, avx512 };

/// "sse2", "avx" or "avx512".
const char* simd_level_name(SimdLevel level);

/// The widest level this CPU (and its OS, which must save the wide registers) runs and this
/// build has code for. Checked at run time.
SimdLevel cpu_simd_level();

/// A value of PPOHDEM_SIMD: "sse2", "avx", "avx512", or "auto" / "" (nullopt: the CPU's own).
/// Throws InputError naming the variable and the accepted values for anything else.
std::optional<SimdLevel> parse_simd_level(std::string_view text);

/// The level the kernels use: PPOHDEM_SIMD's if set, else cpu_simd_level(). Read once per
/// process. Throws InputError for a bad value or a level this CPU does not run.
SimdLevel simd_level();

/// True if the CPU is Intel's (on x86-64; false elsewhere).
bool cpu_is_intel();

/// The level of the DEM fast engine's lanes (contacts, kicks and drifts, exact sums):
/// simd_level(), except avx where PPOHDEM_SIMD is unset or auto and the CPU is an Intel one with
/// AVX-512, on which the four-lane kernels are the faster (docs/portability.md "DEM lane
/// width"). PPOHDEM_SIMD=avx512 still forces eight lanes. The same bits either way.
SimdLevel dem_simd_level(SimdLevel level, bool forced, bool intel);
SimdLevel dem_simd_level();

/// Whether the DEM's four-lane contacts may use AVX-512VL's encoding of their 256-bit
/// operations (32 vector registers, mask registers, no 512-bit instruction): exactly where
/// dem_simd_level() is avx by the rule above (the CPU runs avx512, PPOHDEM_SIMD unset or auto,
/// an Intel CPU) and the CPU has AVX-512VL. PPOHDEM_SIMD=avx keeps plain AVX (docs/portability.md
/// "DEM lane width"). The same bits either way.
bool dem_four_lanes_avx512vl(SimdLevel level, bool forced, bool intel, bool vl);
bool dem_four_lanes_avx512vl();

}  // namespace ppohdem
