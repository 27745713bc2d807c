#pragma once
// Hertz-Mindlin contacts with tangential history, four at a time (AVX, 4 doubles per register)
// or eight (AVX-512F, where the CPU has it: dem_simd_level() avx512).
// Private to core/src/dem/fast. The formulas are those of ppohdem/dem/contact_force.hpp and
// ppohdem/dem/contact_law.hpp, written lane-wise with the same operations in the same order:
// IEEE addition, multiplication, division and square root are correctly rounded in every lane
// exactly as in scalar code, and no FMA is used ("avx" has none; the file is built with
// -ffp-contract=off for "avx512f"), so every
// lane's result is bitwise the scalar evaluation's (tested: FastEngine.VectorContactsAreBitwise*
// and the fast-against-reference tests, which run this path on an AVX machine).
//
// Why by hand: the contact law is branch-free apart from three selections (f_n > 0, a nonzero
// tangential projection, Coulomb slip), which become lane masks; GCC does not vectorize across
// the contacts of a gathered list by itself. The figures: docs/performance.md "Four contacts
// at a time".
#include "fast_state.hpp"
#include "ppohdem/dem/contact_law.hpp"

namespace ppohdem::dem::fast {

/// True if this CPU runs the AVX path (checked once; false off x86-64).
bool x4_contacts_available();
/// True if hertz_mindlin_x4 takes eight contacts at a time (dem_simd_level() avx512).
bool x8_contacts_available();
/// True if its four lanes are encoded with AVX-512VL (dem_four_lanes_avx512vl: an Intel CPU
/// with AVX-512 and PPOHDEM_SIMD unset or auto).
bool x4_contacts_in_avx512vl();

/// What the law can also do for the force kernel's first pass ("Each pair once",
/// force_kernel.cpp), in place of a second loop over the evaluated entries: add each contact
/// whose entry is kContactUpper to its particle's sums s.f[i] and s.t[i] (force and r_i x
/// force, in the order of the entries; the kernel zeroes them first) and, with kEnergy, its
/// elastic and dissipated energy to elastic[i - first] and dissipated[i - first] (the chunk's
/// arrays, zeroed by the kernel), count it, and offer it as the deepest contact (overlap /
/// smaller radius, keep_deeper).
struct OwnSums {
  std::optional<LargestOverlap>* deepest = nullptr;  ///< the range's deepest contact so far
  std::size_t pairs = 0;                             ///< contacts added
  std::size_t first = 0;                             ///< the chunk's first particle
  double* elastic = nullptr;                         ///< kEnergy: per particle of the chunk [J]
  double* dissipated = nullptr;                      ///< kEnergy: per particle of the chunk [J]
};

/// Evaluates the contacts entries[0, count) of one
/// Hertz-Mindlin law (one material), four at a time: the relative kinematics from the
/// particles' state in `s`, the normal force, the tangential spring update (each contact's
/// spring's s.spring_core(code): displacement and stiffness), the pair result
/// (s.result_at(code): force on i and the torque the sum pass adds); with kEnergy also the spring's branch
/// vectors (s.spring_arms(code)) and the entry's elastic and dissipated energy (contact_force.hpp). `dt` is the
/// history increment interval [s]. With `sums`, also what OwnSums says; without, the entry's
/// overlap (for the booking). Requires x4_contacts_available(). Eight at a time where
/// x8_contacts_available(): the same bits.
template <bool kEnergy>
void hertz_mindlin_x4(const HertzMindlin& law, FastState& s, PairEntry* entries, std::size_t count, double dt,
                      OwnSums* sums = nullptr);

}  // namespace ppohdem::dem::fast
