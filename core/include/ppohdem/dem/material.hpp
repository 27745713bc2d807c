#pragma once
/// \file material.hpp
/// The material of a particle (a scene has one or several, simulation_setup.hpp) and the
/// effective pair properties that the contact laws use.
///
///   mass        m = rho (4/3) pi R^3                              [kg]
///   moment      I = (2/5) m R^2  (solid sphere)                   [kg m^2]
///   shear       G = E / (2 (1 + nu))                              [Pa]
///   pair        1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j            [Pa]   (Johnson 1985, 4.22)
///               1/G* = (2-nu_i)/G_i + (2-nu_j)/G_j                [Pa]   (Mindlin 1949)
///               1/R* = 1/R_i + 1/R_j,  1/m* = 1/m_i + 1/m_j        [m], [kg]
/// A planar wall or a rigid object has infinite radius and mass and, unless the scene gives it
/// a material, the elastic constants of the particle touching it, so against a boundary
/// R* = R, m* = m, and E*, G* as for a pair of that material.
/// Two DIFFERENT materials: E*, G* from the pair formulas above (pair_effective_young/_shear);
/// when E and nu are equal they are evaluated in the one-material form E/(2(1-nu^2)),
/// G/(2(2-nu)), so a pair of equal constants gives bitwise a one-material scene's numbers.
#include <string>

namespace ppohdem::dem {

struct Material {
  double density = 0.0;      ///< rho [kg/m^3]
  double young = 0.0;        ///< E [Pa] (only Hertz-Mindlin and the Rayleigh check need it)
  double poisson = 0.0;      ///< nu [-]
  double restitution = 1.0;  ///< e: measured normal restitution of a binary collision [-]
  double friction = 0.0;     ///< Coulomb coefficient mu [-]; 0 = frictionless (no history)
  double rolling_friction = 0.0;  ///< mu_r [-] ([contact] rolling, rolling_resistance.hpp)

  double shear_modulus() const { return young / (2.0 * (1.0 + poisson)); }  ///< G [Pa]
  double effective_young() const { return young / (2.0 * (1.0 - poisson * poisson)); }  ///< E* [Pa]
  double effective_shear() const { return shear_modulus() / (2.0 * (2.0 - poisson)); }  ///< G* [Pa]
  double mass(double radius) const;            ///< m [kg]
  double moment_of_inertia(double radius) const;  ///< I = (2/5) m R^2 [kg m^2]
};

/// Throws InputError (naming `where`, e.g. "scene.toml") if a value is out of range:
/// density > 0, 0 <= e <= 1, mu >= 0, and if `needs_elastic`, E > 0 and -1 < nu < 0.5.
void validate(const Material& material, bool needs_elastic, const std::string& where);

/// E* of two materials: 1/E* = (1-nu_a^2)/E_a + (1-nu_b^2)/E_b [Pa] (Johnson 1985, eq. 4.22);
/// a.effective_young() if E and nu are equal. Symmetric bit for bit in (a, b).
double pair_effective_young(const Material& a, const Material& b);
/// G* of two materials: 1/G* = (2-nu_a)/G_a + (2-nu_b)/G_b [Pa] (Mindlin 1949; the tangential
/// stiffness k_t = 8 G* sqrt(R* delta)); a.effective_shear() if E and nu are equal.
double pair_effective_shear(const Material& a, const Material& b);

/// Harmonic combination 1/(1/a + 1/b); used for R* and m*. b = infinity gives a.
double harmonic_pair(double a, double b);

}  // namespace ppohdem::dem
