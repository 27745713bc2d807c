#pragma once
/// \file pair_laws.hpp
/// The contact law of every pair of materials of a scene, computed once per scene: an
/// M x M table (M = SimulationSetup::material_count()), symmetric bit for bit, looked up by
/// the particles' material indices (Particle::material) in both engines.
///
///   elastic part (Hertz-Mindlin):  E*, G* of the two materials (material.hpp,
///                                  pair_effective_young/_shear; Johnson 1985 eq. 4.22,
///                                  Mindlin 1949)
///   restitution e_ab, friction mu_ab, rolling friction mu_r,ab of two DIFFERENT materials a, b:
///     explicit   SimulationSetup::material_pairs (scene [[material_pair]]), else
///     mixing     e_ab = min(e_a, e_b),  mu_ab = min(mu_a, mu_b),  mu_r,ab = min(mu_r,a, mu_r,b)
///   diagonal   (a, a): the material's own law; (0, 0) is SimulationSetup::law itself, so a
///              one-material scene runs exactly the law it always ran.
/// The mixing rule: the more dissipative, the less rough material sets the contact, and equal
/// materials give their own values exactly. Peers: YADE's Ip2_FrictMat_FrictMat_FrictPhys takes
/// the smaller friction angle by default too (other combinations through a MatchMaker table
/// of explicit pairs, as our [[material_pair]]); LIGGGHTS has no mixing rule: its
/// coefficientRestitution and coefficientFriction are peratomtypepair matrices that the user
/// gives in full. So a YADE or LIGGGHTS comparison of a multi-material scene is reproduced by
/// giving every pair explicitly.
/// Boundaries: a boundary with a material (SimulationSetup::boundary_materials) uses the law
/// (particle's material, boundary's material); without one, the particle's own (a, a).
/// The linear law (constant k_n): that k_n and k_t for every pair (a linear contact has no
/// material stiffness; [contact] stiffness or collision_time), e_ab and mu_ab as above, so
/// gamma_n per pair from e_ab. Hooke (LinearSpringDashpot::hooke): E*_ab as for Hertz, so the
/// stiffness follows the materials, e_ab and mu_ab as above. Every pair has the setup law's
/// tangential ratio and tangential-dashpot switch.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ppohdem/dem/simulation_setup.hpp"

namespace ppohdem::dem {

/// Restitution and friction of materials a and b (rule above).
struct PairCoefficients {
  double restitution = 1.0;  ///< e [-]
  double friction = 0.0;     ///< mu [-]
  double rolling_friction = 0.0;  ///< mu_r [-], mixed and given like mu
};
PairCoefficients pair_coefficients(const SimulationSetup& setup, std::size_t a, std::size_t b);

template <class Law>
class PairLaws {
 public:
  /// The table of `setup` whose (0, 0) law is `law` (the alternative held by setup.law).
  PairLaws(const SimulationSetup& setup, const Law& law);

  std::size_t materials() const { return n_; }
  const Law& pair(std::size_t a, std::size_t b) const { return laws_[a * n_ + b]; }
  /// The material index against which a particle of material m touches boundary b.
  std::size_t boundary_partner(std::size_t m, std::size_t b) const {
    const std::int32_t w = b < boundary_material_.size() ? boundary_material_[b] : -1;
    return w < 0 ? m : static_cast<std::size_t>(w);
  }
  const Law& boundary(std::size_t m, std::size_t b) const { return pair(m, boundary_partner(m, b)); }
  /// Some pair has mu > 0 or rolling resistance: the kernels then keep histories.
  bool any_friction() const;
  bool any_rolling() const { return rolling_; }  ///< [contact] rolling is not "none"
  /// [contact] tangential_damping (the same for every pair).
  bool any_tangential_damping() const { return laws_[0].tangential_damping(); }

 private:
  std::size_t n_ = 1;
  std::vector<Law> laws_;  ///< row-major n x n
  std::vector<std::int32_t> boundary_material_;
  bool rolling_ = false;
};

extern template class PairLaws<LinearSpringDashpot>;
extern template class PairLaws<HertzMindlin>;

}  // namespace ppohdem::dem
