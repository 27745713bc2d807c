#pragma once
/// \file run_diagnostics.hpp
/// Checks run_scene makes after EVERY step, so that a run that goes wrong stops within a
/// step or two with a diagnosis instead of writing NaNs (docs/reliability.md); the energy
/// balance every kEnergyCheckEvery steps and at the energy rows (energy.csv). The per-particle
/// scans run only when a cheap screen (DemEngine::motion_finite false, or the energy sums not
/// finite where they are summed; the engine's escape count grown) says a particle is to be
/// named: run_diagnostics.cpp. A failed check
/// names the step, the particle id(s) and the likely cause; run_scene then writes
/// failed_checkpoint.bin and throws RunFailure (`ppohdem simulate` exits with status 1).
///   non-finite   a position, velocity, angular velocity, force or torque is NaN or infinite
///                (always checked)
///   overlap      a contact's overlap delta exceeds (max_overlap + r0) x the smaller radius (a
///                boundary: the particle's radius), r0 = the deepest overlap / radius of the
///                initial state (accepted as given: validate_setup bounds particle pairs at 1%
///                unless allow_overlap, walls not at all; the seed's sample starts with
///                particles 18% into a wall)
///   energy       the balance E = kinetic + rotational + gravitational + elastic + dissipated
///                - boundary_work (conserved up to the integrator error, engine.hpp) has grown
///                since step 0 by more than max_energy_growth x S, where
///                S = K0 + Kr0 + U_el0 + K + Kr + U_el + D + |W_b| + |U_g - U_g0| (0 = step 0;
///                every term that can exchange energy, so S > 0 once anything moves)
///   escape       a particle centre crossed to the solid side of a boundary (Boundary::
///                has_escaped) or left the optional box [domain_min, domain_max]
/// Scene table [checks] (all optional): max_overlap, max_energy_growth, stop_on_escape,
/// domain_min, domain_max.
#include <optional>
#include <stdexcept>
#include <string>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/simulation_setup.hpp"

namespace ppohdem::dem {

/// Steps between two checks of the energy balance [-]. Summing the energies of the state is a
/// pass over every particle with seven exact sums; every 10 steps it costs a few per cent of a
/// step's time, while an instability (growing by a factor per step) is still caught within
/// tens of steps (docs/reliability.md "Runs that go wrong stop with a diagnosis").
inline constexpr long kEnergyCheckEvery = 10;

struct RunChecks {
  /// Largest accepted overlap / smaller radius [-], beyond the initial state's deepest. 0.1:
  /// ten times the 1% accepted in an initial state (validate_setup), 3.5 times the 2.84% of
  /// the 10,000-particle settling scene (docs/reliability.md), while a contact missed by a
  /// too-large dt or a too-soft spring passes it within a step or two.
  double max_overlap = 0.1;
  /// Largest accepted growth of the energy balance relative to S above [-]. 0.05: the
  /// bundled scenes stay below 0.071% (docs/reliability.md); an instability grows
  /// exponentially and passes it within a few steps.
  double max_energy_growth = 0.05;
  bool stop_on_escape = true;  ///< false: only the warning of the engine, the run goes on
  std::optional<Vec3> domain_min;  ///< optional box the centres must stay in [m]
  std::optional<Vec3> domain_max;  ///< [m]
};

/// A run stopped by a failed check (message: the diagnosis).
class RunFailure : public std::runtime_error {
 public:
  explicit RunFailure(const std::string& diagnosis) : std::runtime_error(diagnosis) {}
};

/// The largest values seen so far (reported at the end of a run).
struct CheckMargins {
  double overlap = 0.0;        ///< largest overlap / radius [-]
  double energy_growth = 0.0;  ///< largest (E - E0) / S [-]
};

class RunDiagnostics {
 public:
  /// `initial`: the energies at step 0 of the run (also after a restart);
  /// `initial_overlap`: the deepest overlap / radius of the initial state (r0 above).
  /// `limit`: the setup's stability limit if the caller has it (setup.particles may then be
  /// empty); otherwise time_step_limit(setup).
  RunDiagnostics(const SimulationSetup& setup, const RunChecks& checks, const Energies& initial,
                 double initial_overlap = 0.0, std::optional<TimeStepLimit> limit = std::nullopt);
  /// Checks the engine's state after a step; returns the diagnosis of the first failed check.
  /// `balance`: check the energy balance too (energies tracked), which sums the energies of the
  /// state (run_scene: every kEnergyCheckEvery steps and at the energy rows).
  std::optional<std::string> check(const DemEngine& engine, bool balance = true);
  /// The non-finite check alone (the state before the first step: forces of the initial
  /// evaluation, e.g. two particles at the same point).
  std::optional<std::string> check_finite(const DemEngine& engine) const;
  const CheckMargins& margins() const { return margins_; }
  /// Energy brought in since step 0 by inserted particles (their kinetic, rotational and
  /// gravitational energy; insertion_run.hpp): the balance is checked against initial + input.
  void set_input(const Energies& input) { input_ = input; }

 private:
  std::optional<std::string> check_overlap(const DemEngine& engine);
  std::optional<std::string> check_energy(const DemEngine& engine, const Energies& energies);
  std::optional<std::string> check_domain(const DemEngine& engine) const;
  std::string time_step_note() const;

  const SimulationSetup& setup_;
  RunChecks checks_;
  Energies initial_;
  Energies input_;  ///< set_input
  double initial_overlap_;
  TimeStepLimit limit_;
  CheckMargins margins_;
  std::size_t escaped_seen_ = 0;  ///< the engine's escape count at the last check
};

}  // namespace ppohdem::dem
