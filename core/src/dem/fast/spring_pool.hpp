// A pool of the fast engine's tangential springs (TangentialSpring), stored as three arrays by
// when the force kernel touches a field: the displacement and stiffness at every evaluation,
// the arms only with the energies tracked, the boundary and rolling fields never in the
// lane law. The lane law then streams 32 (or 80) bytes a contact instead of 136
// (docs/performance.md "Springs in three arrays").
#pragma once

#include <cstddef>
#include <vector>

#include "ppohdem/dem/contact_force.hpp"

namespace ppohdem::dem::fast {

/// What the contact law reads and writes at every evaluation; 32-byte aligned, so that one
/// never straddles two cache lines.
struct alignas(32) SpringCore {
  Vec3 displacement = Vec3::Zero();  ///< xi [m]
  double stiffness = 0.0;            ///< k_t at the last update [N/m]
};

/// The arms at the last update: read and written only with the energies tracked.
struct SpringArms {
  Vec3 branch_i = Vec3::Zero();  ///< r_i [m]
  Vec3 branch_j = Vec3::Zero();  ///< r_j [m]
};

/// The fields a pair spring of the lane law leaves as they are (zero).
struct SpringRest {
  Vec3 surface_velocity = Vec3::Zero();  ///< boundaries only [m/s]
  RollingSpring rolling;                 ///< EPSD2 rolling resistance only
};

/// Entry k's fields are core(k), arms(k) and the rest; get and set move whole springs.
class SpringPool {
 public:
  std::size_t size() const { return core_.size(); }
  bool empty() const { return core_.empty(); }
  std::size_t capacity() const { return core_.capacity(); }
  std::size_t bytes() const {
    return core_.capacity() * sizeof(SpringCore) + arms_.capacity() * sizeof(SpringArms) +
           rest_.capacity() * sizeof(SpringRest);
  }
  void clear() {
    core_.clear();
    arms_.clear();
    rest_.clear();
  }
  /// New entries are empty springs.
  void resize(std::size_t n) {
    core_.resize(n);
    arms_.resize(n);
    rest_.resize(n);
  }
  void push_back(const TangentialSpring& spring) {
    core_.emplace_back();
    arms_.emplace_back();
    rest_.emplace_back();
    set(core_.size() - 1, spring);
  }
  TangentialSpring get(std::size_t k) const {
    TangentialSpring spring;
    spring.displacement = core_[k].displacement;
    spring.stiffness = core_[k].stiffness;
    spring.branch_i = arms_[k].branch_i;
    spring.branch_j = arms_[k].branch_j;
    spring.surface_velocity = rest_[k].surface_velocity;
    spring.rolling = rest_[k].rolling;
    return spring;
  }
  void set(std::size_t k, const TangentialSpring& spring) {
    core_[k].displacement = spring.displacement;
    core_[k].stiffness = spring.stiffness;
    arms_[k].branch_i = spring.branch_i;
    arms_[k].branch_j = spring.branch_j;
    rest_[k].surface_velocity = spring.surface_velocity;
    rest_[k].rolling = spring.rolling;
  }
  SpringCore& core(std::size_t k) { return core_[k]; }
  SpringArms& arms(std::size_t k) { return arms_[k]; }

 private:
  std::vector<SpringCore> core_;
  std::vector<SpringArms> arms_;
  std::vector<SpringRest> rest_;
};

}  // namespace ppohdem::dem::fast
