#include "ppohdem/dem/pair_laws.hpp"

#include <algorithm>
#include <type_traits>


namespace ppohdem::dem {

PairCoefficients pair_coefficients(const SimulationSetup& setup, std::size_t a, std::size_t b) {
  const Material& ma = setup.material_at(a);
  const Material& mb = setup.material_at(b);
  PairCoefficients c{std::min(ma.restitution, mb.restitution), std::min(ma.friction, mb.friction),
                     std::min(ma.rolling_friction, mb.rolling_friction)};
  if (a == b) return c;
  for (const MaterialPairRule& r : setup.material_pairs) {
    if ((r.a == a && r.b == b) || (r.a == b && r.b == a)) {
      if (r.restitution) c.restitution = *r.restitution;
      if (r.friction) c.friction = *r.friction;
      if (r.rolling_friction) c.rolling_friction = *r.rolling_friction;
    }
  }
  return c;
}

template <class Law>
PairLaws<Law>::PairLaws(const SimulationSetup& setup, const Law& law)
    : n_(setup.material_count()), laws_(n_ * n_, law), boundary_material_(setup.boundary_materials),
      rolling_(setup.rolling != RollingModel::kNone) {
  for (std::size_t a = 0; a < n_; ++a) {
    for (std::size_t b = a; b < n_; ++b) {
      Law l = law;  // (0, 0): the setup's own law
      if constexpr (std::is_same_v<Law, LinearSpringDashpot>) {
        if (a != 0 || b != 0) {  // the setup's stiffness rule with the pair's e and mu
          const PairCoefficients c = pair_coefficients(setup, a, b);
          l = law.for_pair(setup.material_at(a), setup.material_at(b), c.restitution, c.friction);
        }
      } else {
        if (a == b && a != 0) {
          l = Law::from_material(setup.material_at(a));
        } else if (a != b) {
          const PairCoefficients c = pair_coefficients(setup, a, b);
          l = Law::from_pair(setup.material_at(a), setup.material_at(b), c.restitution, c.friction);
        }
        l.set_tangential_damping(law.tangential_damping());
      }
      if (rolling_) l.set_rolling({setup.rolling, pair_coefficients(setup, a, b).rolling_friction});
      laws_[a * n_ + b] = l;  // the same object both ways: symmetric bit for bit
      laws_[b * n_ + a] = l;
    }
  }
}

template <class Law>
bool PairLaws<Law>::any_friction() const {
  return rolling_ || std::any_of(laws_.begin(), laws_.end(), [](const Law& l) { return l.friction() > 0.0; });
}

template class PairLaws<LinearSpringDashpot>;
template class PairLaws<HertzMindlin>;

}  // namespace ppohdem::dem
