#pragma once
/// \file yade_checks.hpp
/// YADE reference runs (issue 8 item 3, docs/yade.md): the same scenes run in YADE 2023.02a
/// (validation/yade/*.py, outputs stored in fixtures/yade/) and in every ppohdem engine
/// (twins in validation/yade/scenes/), compared number by number:
///   * two-sphere Hertz impact (e = 0.5): max overlap, max force, duration, restitution;
///   * sphere-wall oblique impact with friction (alumina, 3.9 m/s, 5..80 degrees): rebound
///     normal velocity; tangential velocity and spin as the difference ours - YADE against the
///     difference of the two tangential laws (ppohdem total form, YADE incremental) predicted
///     by a reduced one-sphere model integrated with RK4 (zero in gross sliding);
///   * sphere on a translating floor (conveyor belt): sliding-phase velocity, rolling velocity
///     and spin (also against the rigid-body values 2V/7, -5V/(7R));
///   * settling bed of 1,000 spheres, 3 lattice jitters: packing fraction, mean coordination
///     number, potential energy, with the tolerance from the run-to-run spread.
/// Tolerances (two spheres: 2 (dt/T_c)|q|, two first-order schemes) of the other single-particle
/// scenes: the sum of both codes' time-step errors, each
/// estimated by halving dt (1.5 x the first-order bound 2 |q(dt) - q(dt/2)|), plus the model
/// differences where they matter (docs/yade.md). With CheckContext::live, YADE is rerun into
/// work_dir (quick: the single-particle scenes; full: also the bed) and the rerun is compared
/// with the stored fixture too.
#include "ppohdem/validation/check_registry.hpp"

namespace ppohdem::validation {

CheckGroup make_yade_checks();

}  // namespace ppohdem::validation
