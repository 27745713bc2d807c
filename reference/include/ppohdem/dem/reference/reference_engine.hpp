#pragma once
/// \file reference_engine.hpp
/// The readable serial DEM engine: the answer every faster engine is checked against.
///
/// Per step (velocity Verlet, contract in ppohdem/dem/engine.hpp):
///   1. half kick + drift of every particle;
///   2. contact detection with a cell list of cell size 2 R_max (cell_list.hpp), pairs sorted
///      by (id_i, id_j) so the result does not depend on storage order;
///   3. force passes, chosen ONCE at construction from the scene (force_passes.hpp):
///      particle pairs with the scene's law, with or without tangential history (friction
///      zero or not), and a boundary pass only if the scene has walls;
///   4. second half kick.
/// Contact histories: std::map keyed by (id_i, id_j), id_i < id_j, and by (id, boundary
/// index), the seed's contact_list and contact_list_wall.
/// Checkpoints (save_state/restore_state, engine.hpp): the state between two steps is the
/// particles (with force and torque of the last evaluation, needed by the next half kick), the
/// step count, the energy accumulators, the passes' contact histories, escaped ids, loads and
/// contact counts. The predicted velocities are recomputed at the start of every step, so
/// they are not state. No random numbers are drawn while stepping.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/dem/engine.hpp"
#include "ppohdem/dem/exact_sum.hpp"

namespace ppohdem::dem::reference {

using ppohdem::dem::ContactCounts;
using ppohdem::dem::Energies;
using ppohdem::dem::EngineState;
using ppohdem::dem::Particles;
using ppohdem::dem::SimulationSetup;

/// Everything a force pass may read or add to during one force evaluation.
struct ForceContext {
  Particles& particles;                 ///< force and torque are accumulated here; their
                                        ///< velocities are v(n+1/2), w(n+1/2)
  const std::vector<Vec3>& velocity;    ///< v(n+1) predicted = v(n+1/2) + a(n) dt/2 [m/s]
  const std::vector<Vec3>& angular_velocity;  ///< w(n+1) predicted [rad/s]
  const std::vector<double>& mass;      ///< m [kg], same order as particles
  double time = 0.0;                    ///< t of the evaluation [s]
  double dt = 0.0;                      ///< history increment interval [s] (0 at start-up)
  // The contacts' energy terms, summed exactly and rounded once when read (exact_sum.hpp:
  // the correctly rounded sum of the terms, whatever their order) [J].
  ppohdem::dem::ExactSum elastic;        ///< stored energy summed by the passes [J]
  ppohdem::dem::ExactSum dissipated;     ///< energy removed in this evaluation [J]
  ppohdem::dem::ExactSum boundary_work;  ///< work done by moving boundaries [J]
  std::optional<ppohdem::dem::LargestOverlap> deepest = std::nullopt;  ///< deepest contact so far

  /// Record a contact's overlap delta [m] relative to `radius` [m] (the smaller radius).
  void note_overlap(double overlap, double radius, std::int64_t id_a, std::int64_t id_b,
                    bool boundary) {
    const double ratio = overlap / radius;
    if (!deepest || ratio > deepest->ratio) deepest = ppohdem::dem::LargestOverlap{ratio, overlap, id_a, id_b, boundary};
  }
};

/// One kind of interaction (particle pairs, particle-boundary), made for one law.
class ForcePass {
 public:
  virtual ~ForcePass() = default;
  virtual void add_forces(ForceContext& context) = 0;
  virtual std::size_t active_contacts() const = 0;
  /// Particles that have crossed a boundary so far (boundary passes only).
  virtual std::size_t escaped() const { return 0; }
  /// Reaction on each boundary from the last add_forces (boundary passes only).
  virtual std::vector<ppohdem::dem::BoundaryLoad> loads() const { return {}; }
  /// Checkpoints: append this pass's contact histories (sorted), escaped ids, loads and count
  /// to `state`; restore them from it (throws InputError on records this pass cannot hold).
  virtual void save(EngineState& state) const = 0;
  virtual void restore(const EngineState& state) = 0;
};

class ReferenceEngine final : public ppohdem::dem::DemEngine {
 public:
  /// Validates the setup (ppohdem::dem::validate_setup; throws InputError) and evaluates the
  /// forces of the initial state.
  explicit ReferenceEngine(const SimulationSetup& setup);
  ~ReferenceEngine() override;

  static std::unique_ptr<ppohdem::dem::DemEngine> make(const SimulationSetup& setup);

  std::string name() const override { return "reference"; }
  void step() override;
  long step_count() const override { return steps_; }
  double time() const override { return static_cast<double>(steps_) * dt_; }
  const Particles& particles() const override { return particles_; }
  Energies energies() const override;
  ContactCounts contact_counts() const override;
  std::size_t escaped_count() const override;
  std::vector<ppohdem::dem::BoundaryLoad> boundary_loads() const override;
  EngineState save_state() const override;
  void restore_state(const EngineState& state) override;
  std::optional<ppohdem::dem::LargestOverlap> largest_overlap() const override;
  /// Appends the particles (DemEngine::insert_particles): their masses from their materials.
  void insert_particles(const Particles& added) override;

 private:
  void evaluate_forces(double history_dt);

  Particles particles_;
  std::vector<double> mass_;     ///< m [kg]
  std::vector<double> inertia_;  ///< I = (2/5) m R^2 [kg m^2]
  std::vector<ppohdem::dem::Material> materials_;  ///< material k of the scene (inserted particles)
  std::vector<Vec3> predicted_velocity_;          ///< v(n+1/2) + a(n) dt/2 [m/s]
  std::vector<Vec3> predicted_angular_velocity_;  ///< w(n+1/2) + alpha(n) dt/2 [rad/s]
  double dt_;
  Vec3 gravity_;
  long steps_ = 0;
  std::unique_ptr<ForcePass> pair_pass_;
  std::unique_ptr<ForcePass> boundary_pass_;  ///< null without boundaries
  std::size_t boundary_count_ = 0;
  double elastic_ = 0.0;
  double dissipated_ = 0.0;
  double boundary_work_ = 0.0;
  bool energy_balance_ = true;  ///< SimulationSetup::energy_balance
  std::optional<ppohdem::dem::LargestOverlap> deepest_;  ///< of the last evaluation
};

}  // namespace ppohdem::dem::reference
