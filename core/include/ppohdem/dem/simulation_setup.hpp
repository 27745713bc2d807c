#pragma once
/// \file simulation_setup.hpp
/// Everything an engine needs to start, independent of any file format: the scene reader
/// (scene.hpp) produces one, tests build them directly. Copyable (boundaries are shared and
/// immutable).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/contact_law.hpp"
#include "ppohdem/dem/material.hpp"
#include "ppohdem/dem/particle.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem {
class Comm;
}

namespace ppohdem::dem {

using ContactLaw = std::variant<LinearSpringDashpot, HertzMindlin>;

/// Restitution and/or friction of one pair of DIFFERENT materials, given explicitly (scene
/// [[material_pair]]); what is not given follows the mixing rule of pair_laws.hpp.
struct MaterialPairRule {
  std::uint16_t a = 0;  ///< material index
  std::uint16_t b = 0;  ///< material index, != a
  std::optional<double> restitution;  ///< e of the pair [-]
  std::optional<double> friction;     ///< mu of the pair [-]
  std::optional<double> rolling_friction = std::nullopt;  ///< mu_r of the pair [-]
};

/// At most this many materials in a scene (the pair-law table has count^2 entries).
inline constexpr std::size_t kMaxMaterials = 64;

/// Where a rank's `particles` sit when several ranks read one particle file and each keeps a
/// share (read_scene with a Comm; docs/dem.md "Reading on every rank"): its particles are the
/// file's particles [first, first + particles.size()) of `total`, in file order. Without
/// `comm`, `particles` are all of them.
struct ParticleShare {
  const Comm* comm = nullptr;  ///< the ranks whose shares make up the particles
  std::size_t first = 0;       ///< file index of this rank's first particle
  std::size_t total = 0;       ///< particles over all the ranks
};

/// The first of the consecutive items [first(k), first(k + 1)) that part k gets when `total`
/// items are split over `parts` parts as evenly as they go (the first total mod parts parts
/// hold one more): DemEngine::ordered_part's ranks, a piped particle file's shares.
inline std::size_t even_part_first(std::size_t total, std::size_t parts, std::size_t k) {
  return total / parts * k + std::min(k, total % parts);
}
/// The part k that holds item `index` < total (the inverse of even_part_first).
inline std::size_t even_part_of(std::size_t total, std::size_t parts, std::size_t index) {
  const std::size_t base = total / parts, bigger = total % parts;  // the first `bigger` parts hold base + 1
  return index < bigger * (base + 1) ? index / (base + 1) : bigger + (index - bigger * (base + 1)) / base;
}

struct SimulationSetup {
  double dt = 0.0;                 ///< time step [s]
  Vec3 gravity = Vec3::Zero();     ///< g [m/s^2]
  Material material;               ///< material 0: the only one of a one-material scene
  ContactLaw law;                  ///< the law of two particles of material 0 (pair_laws.hpp)
  RollingModel rolling = RollingModel::kNone;  ///< [contact] rolling (rolling_resistance.hpp)
  /// Multi-material scenes (Hertz-Mindlin only): materials 1, 2, ... (a particle with
  /// Particle::material = k >= 1 is made of more_materials[k - 1]); empty for one material.
  std::vector<Material> more_materials;
  std::vector<std::string> material_names;  ///< names of all materials, or empty (unnamed)
  std::vector<MaterialPairRule> material_pairs;  ///< explicit pair values (a != b)
  /// Per boundary (same order as `boundaries`; missing entries mean -1): the index of the
  /// boundary's material, or -1 for the material of the particle touching it (which is what
  /// a one-material scene does).
  std::vector<std::int32_t> boundary_materials;
  Particles particles;
  ParticleShare share;  ///< set: `particles` is this rank's share of the file's (above)
  /// Particles still to come (scene [[insert]]: one per size extreme and material,
  /// insertion.hpp insert_size_probes): counted in time_step_limit only.
  Particles insert_probes;
  BoundaryList boundaries;         ///< walls (and later rigid objects)
  bool allow_initial_overlap = false;  ///< accept overlaps > 1% of the smaller radius
  bool force_time_step = false;        ///< accept dt above the stability limit (--force)
  /// Track the contact energies (elastic, dissipated, boundary work) and check the balance.
  /// false ([simulation] energy_balance = false): the engines skip that book-keeping (the
  /// fast engine's kernel has no energy terms: docs/performance.md "Energy book-keeping
  /// optional"), report those
  /// three terms as NaN, and the run's energy check is off; trajectories are the same bit
  /// for bit. Kinetic, rotational and gravitational energies are always computed.
  bool energy_balance = true;
  std::string source;              ///< where it came from (scene file), for messages

  std::size_t material_count() const { return 1 + more_materials.size(); }
  /// Each rank holds a share of the particles (functions taking the setup are then collective).
  bool shared() const { return share.comm != nullptr; }
  /// The particles over all the ranks.
  std::size_t particle_total() const { return shared() ? share.total : particles.size(); }
  /// Material k (0: `material`); k < material_count().
  const Material& material_at(std::size_t k) const { return k == 0 ? material : more_materials[k - 1]; }
  /// "material 'steel' (1)" or "material 1", for messages.
  std::string material_label(std::size_t k) const;
};

/// A dt limit and how it was obtained (for the error message).
struct TimeStepLimit {
  double limit = 0.0;  ///< [s]
  std::string reason;  ///< e.g. "0.2 * Rayleigh time 4.33e-05 s of the smallest particle"
};

/// Rayleigh time of a sphere: T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766) [s]
/// (Li, Xu & Thornton 2005; Thornton & Randall 1988).
double rayleigh_time(double radius, const Material& material);

/// Hertz-Mindlin: 0.2 min_i T_R(R_i, material_i) (the customary 20% of the Rayleigh time;
/// LIGGGHTS warns above it; with one material the smallest particle's). Linear: 0.2 pi
/// sqrt(m*_min / k_n), 20% of the undamped half period of the lightest pair (Verlet is
/// unstable above 2/omega_0 = 0.64 of it; 0.2 keeps ~15 steps per contact, the usual accuracy
/// rule). m*_min = m_min/2 (pair), also covering walls (m* = m).
TimeStepLimit time_step_limit(const SimulationSetup& setup);

/// Validates a setup before a run; throws InputError naming setup.source and the record:
/// dt > 0 and finite; radius > 0 and every value finite; ids unique; material ranges; with
/// several materials: Hertz-Mindlin law, at most kMaxMaterials, every particle's and
/// boundary's material index in range, pair rules between two different known materials;
/// dt <= time_step_limit (unless force_time_step; the message gives the limit); no pair
/// overlapping by more than 1% of the smaller radius (unless allow_initial_overlap), the message
/// naming the pair with the smallest ids. A shared setup (collective): every rank throws the
/// same error, the first particle in file order; the overlaps are left to the engine, which
/// places the shares first (overlap_error).
void validate_setup(const SimulationSetup& setup);

/// The error validate_setup gives for `count` overlapping pairs, `a` and `b` (ids a < b) the
/// pair with the smallest ids.
InputError overlap_error(const std::string& source, std::size_t count, const Particle& a, const Particle& b);

/// Pairs (index i < index j) overlapping by more than `fraction` of the smaller radius.
/// Cells of side 2 R_max (overlapping_pairs.cpp): O(N) for finite positions and fraction >= 0.
std::vector<std::pair<std::size_t, std::size_t>> overlapping_pairs(const Particles& particles,
                                                                   double fraction);

}  // namespace ppohdem::dem
