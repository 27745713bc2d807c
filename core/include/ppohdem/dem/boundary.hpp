#pragma once
/// \file boundary.hpp
/// Rigid boundaries that particles touch: planar walls now, rigid objects given by distance
/// fields later. A boundary is a body of infinite mass whose motion is prescribed as a
/// function of time, so it is immutable and evaluated at a time t [s] (no per-step state).
/// Engines keep one contact history per (particle id, boundary index, feature) and use the same
/// contact laws as for particle pairs, with j = the boundary: R* = R_i, m* = m_i, and the
/// boundary's velocity at the contact point in v_rel (contact_force.hpp).
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ppohdem/geometry/vector.hpp"

namespace ppohdem::dem {

/// A sphere touching a boundary.
struct BoundaryContact {
  Vec3 normal = Vec3::UnitZ();          ///< unit, from the boundary towards the sphere centre
  double overlap = 0.0;                 ///< delta = R - distance(centre, surface) > 0 [m]
  Vec3 point = Vec3::Zero();            ///< contact point on the boundary surface [m]
  Vec3 surface_velocity = Vec3::Zero();  ///< velocity of the boundary material there [m/s]
  Vec3 surface_spin = Vec3::Zero();  ///< angular velocity of the boundary [rad/s] (rolling resistance)
};

/// One of several contacts of a sphere with a boundary, with the boundary's feature it touches
/// (a face, edge or vertex of a mesh object: mesh_contact.hpp); feature 0 is the single
/// contact of contact(). Engines keep one tangential history per (particle, boundary, feature).
struct FeatureContact {
  BoundaryContact contact;
  std::uint32_t feature = 0;  ///< < 2^31 (see boundary_history_key)
};

/// The contact-history key of a boundary contact (the id_b of a checkpoint's
/// ContactHistoryRecord, engine.hpp): boundary index + 2^32 feature. Feature 0 keeps the key of
/// one contact per boundary (= the boundary index), so checkpoints without features read as before.
inline std::int64_t boundary_history_key(std::size_t boundary, std::uint32_t feature) {
  return static_cast<std::int64_t>(boundary) + (static_cast<std::int64_t>(feature) << 32);
}
inline std::size_t boundary_of_history_key(std::int64_t key) { return static_cast<std::size_t>(key & 0xFFFFFFFF); }
inline std::uint32_t feature_of_history_key(std::int64_t key) { return static_cast<std::uint32_t>(key >> 32); }

/// A world box outside which a boundary neither touches a sphere of radius <= r_max nor counts
/// it (Boundary::reach): an engine may skip such a sphere, with the same results to the bit
/// (docs/objects.md "Far objects cost nothing"). The default box is the whole space.
struct ReachBox {
  Vec3 lo = Vec3::Constant(-std::numeric_limits<double>::infinity());  ///< [m]
  Vec3 hi = Vec3::Constant(std::numeric_limits<double>::infinity());   ///< [m]
  double r_max = std::numeric_limits<double>::infinity();  ///< the radii it holds for [m]
  /// True if a sphere (centre [m], radius [m]) cannot touch the boundary: skip it.
  bool excludes(const Vec3& centre, double radius) const {
    return radius <= r_max && (centre.x() < lo.x() || centre.x() > hi.x() || centre.y() < lo.y() ||
                               centre.y() > hi.y() || centre.z() < lo.z() || centre.z() > hi.z());
  }
};

class Boundary {
 public:
  virtual ~Boundary() = default;
  /// The contact of a sphere (centre [m], radius [m]) with this boundary at time t [s], or
  /// nothing if they do not overlap or the centre has crossed to the solid side.
  virtual std::optional<BoundaryContact> contact(const Vec3& centre, double radius,
                                                 double time) const = 0;
  /// All contacts of the sphere at time t into `out` (cleared first), sorted by feature. The
  /// default is contact() as feature 0; a mesh object gives one per touching face, edge or vertex.
  virtual void contacts(const Vec3& centre, double radius, double time, std::vector<FeatureContact>& out) const {
    out.clear();
    if (auto c = contact(centre, radius, time)) out.push_back({*c, 0});
  }
  /// True if the centre has crossed to the solid side at time t: the particle left the domain.
  virtual bool has_escaped(const Vec3& centre, double time) const = 0;
  /// Where spheres of radius <= r_max [m] can touch this boundary (or be counted by it) at
  /// time t [s]: outside the box, contacts() gives none, has_escaped() is false and nothing is
  /// counted. The default, the whole space, is always right; a far object gives a small box.
  virtual ReachBox reach(double /*time*/, double /*r_max*/) const { return {}; }
  /// Human-readable description for logs, e.g. "wall point (0,0,-0.01) normal (0,0,1)".
  virtual std::string describe() const = 0;
};

using BoundaryList = std::vector<std::shared_ptr<const Boundary>>;

/// A plane through point(t) = point0 + velocity t with a fixed unit normal pointing into the
/// domain (the particles' side). Signed distance of x: d = (x - point(t)) . n [m].
class PlaneWall final : public Boundary {
 public:
  /// Throws InputError if |normal| is zero or not finite; the normal is normalised.
  PlaneWall(const Vec3& point, const Vec3& normal, const Vec3& velocity = Vec3::Zero());

  std::optional<BoundaryContact> contact(const Vec3& centre, double radius,
                                         double time) const override;
  bool has_escaped(const Vec3& centre, double time) const override;
  std::string describe() const override;

  Vec3 point_at(double time) const { return point_ + velocity_ * time; }  ///< [m]
  /// The plane's formulas, written once (the fast engine evaluates walls inline with them):
  /// signed distance d = (x - point) . n [m], > 0 on the domain side ...
  static double signed_distance(const Vec3& point, const Vec3& normal, const Vec3& centre) {
    return (centre - point).dot(normal);
  }
  /// ... and the contact of a sphere at distance 0 < d < R: overlap R - d, foot x - d n.
  static BoundaryContact touching(const Vec3& normal, const Vec3& velocity, const Vec3& centre, double radius,
                                  double distance) {
    BoundaryContact c;
    c.normal = normal;
    c.overlap = radius - distance;
    c.point = centre - distance * normal;
    c.surface_velocity = velocity;
    return c;
  }
  const Vec3& normal() const { return normal_; }
  const Vec3& velocity() const { return velocity_; }  ///< [m/s]

 private:
  Vec3 point_;
  Vec3 normal_;
  Vec3 velocity_;
};

}  // namespace ppohdem::dem
