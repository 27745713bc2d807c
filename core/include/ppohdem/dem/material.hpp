#pragma once
/// \file material.hpp
/// The one material of a scene (particles and walls share it) and the effective pair
/// properties that the contact laws use.
///
///   mass        m = rho (4/3) pi R^3                              [kg]
///   moment      I = (2/5) m R^2  (solid sphere)                   [kg m^2]
///   shear       G = E / (2 (1 + nu))                              [Pa]
///   pair        1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j            [Pa]   (Johnson 1985, 4.22)
///               1/G* = (2-nu_i)/G_i + (2-nu_j)/G_j                [Pa]   (Mindlin 1949)
///               1/R* = 1/R_i + 1/R_j,  1/m* = 1/m_i + 1/m_j        [m], [kg]
/// A planar wall (or, later, a rigid object) has infinite radius and mass but the same
/// elastic constants, so against a boundary R* = R, m* = m, and E*, G* as for a pair.
#include <string>

namespace ppohdem::dem {

struct Material {
  double density = 0.0;      ///< rho [kg/m^3]
  double young = 0.0;        ///< E [Pa] (only Hertz-Mindlin and the Rayleigh check need it)
  double poisson = 0.0;      ///< nu [-]
  double restitution = 1.0;  ///< e: measured normal restitution of a binary collision [-]
  double friction = 0.0;     ///< Coulomb coefficient mu [-]; 0 = frictionless (no history)

  double shear_modulus() const { return young / (2.0 * (1.0 + poisson)); }  ///< G [Pa]
  double effective_young() const { return young / (2.0 * (1.0 - poisson * poisson)); }  ///< E* [Pa]
  double effective_shear() const { return shear_modulus() / (2.0 * (2.0 - poisson)); }  ///< G* [Pa]
  double mass(double radius) const;            ///< m [kg]
  double moment_of_inertia(double radius) const;  ///< I = (2/5) m R^2 [kg m^2]
};

/// Throws InputError (naming `where`, e.g. "scene.toml") if a value is out of range:
/// density > 0, 0 <= e <= 1, mu >= 0, and if `needs_elastic`, E > 0 and -1 < nu < 0.5.
void validate(const Material& material, bool needs_elastic, const std::string& where);

/// Harmonic combination 1/(1/a + 1/b); used for R* and m*. b = infinity gives a.
double harmonic_pair(double a, double b);

}  // namespace ppohdem::dem
