// A rigid object from a signed distance field (formulas in distance_field_object.hpp).
#include "ppohdem/dem/distance_field_object.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ppohdem/error.hpp"
#include "ppohdem/grid/trilinear.hpp"

namespace ppohdem::dem {

DistanceFieldObject::DistanceFieldObject(ScalarField field, const RigidMotion& motion,
                                         std::string name, double start, double stop)
    : field_(std::move(field)), motion_(motion), name_(std::move(name)), start_(start), stop_(stop) {
  field_.grid.validate(name_);
  if (field_.values.size() != field_.grid.node_count()) {
    throw InputError(name_, 0, "distance field: expected " + std::to_string(field_.grid.node_count()) +
                                   " values, found " + std::to_string(field_.values.size()));
  }
  for (std::size_t i = 0; i < field_.values.size(); ++i) {
    if (!std::isfinite(field_.values[i])) {
      throw InputError(name_, 0, "distance field: value " + std::to_string(i) + " is not finite");
    }
  }
  if (!motion_.velocity.allFinite() || !motion_.angular_velocity.allFinite() ||
      !motion_.centroid.allFinite()) {
    throw InputError(name_, 0, "object motion: expected finite velocity, angular velocity and centroid");
  }
  if (!std::isfinite(start_) || std::isnan(stop_) || stop_ < start_) {
    throw InputError(name_, 0, "object motion: expected a finite start <= stop");
  }
}

double DistanceFieldObject::motion_time(double time) const {
  return std::min(std::max(time, start_), stop_) - start_;
}

RigidTransform DistanceFieldObject::pose_at(double time) const {
  return motion_.pose_at(motion_time(time));
}

Vec3 DistanceFieldObject::centroid_at(double time) const {
  return motion_.centroid_at(motion_time(time));
}

Vec3 DistanceFieldObject::point_velocity(const Vec3& x, double time) const {
  if (time < start_ || time >= stop_) return Vec3::Zero();  // at rest outside [start, stop)
  return motion_.point_velocity(x, motion_time(time));
}

std::optional<BoundaryContact> DistanceFieldObject::contact(const Vec3& centre, double radius,
                                                            double time) const {
  const RigidTransform pose = pose_at(time);
  const Vec3 local = pose.inverse().apply(centre);  // y = P^-1 x [m]
  const auto sample = sample_trilinear(field_, local);
  if (!sample) {
    outside_grid_.fetch_add(1, std::memory_order_relaxed);
    return std::nullopt;  // far away: no contact (counted)
  }
  const double phi = sample->value;  // signed distance of the centre [m]
  const double gradient_norm = sample->gradient.norm();
  if (phi >= radius || !(gradient_norm > 0.0)) return std::nullopt;
  BoundaryContact c;
  c.normal = pose.rotate(sample->gradient / gradient_norm);  // object -> particle, world frame
  c.overlap = radius - phi;                                  // delta = R - phi [m]
  c.point = centre - phi * c.normal;                         // foot on the tangent plane [m]
  c.surface_velocity = point_velocity(c.point, time);        // v + omega x (p - c(t)) [m/s]
  c.surface_spin = motion_.angular_velocity;                 // omega [rad/s]
  return c;
}

std::string DistanceFieldObject::describe() const {
  std::ostringstream s;
  const GridSpec& g = field_.grid;
  s << "object '" << name_ << "' (distance field " << g.nodes[0] << " x " << g.nodes[1] << " x "
    << g.nodes[2] << " nodes, h = " << g.min_spacing() << " m)";
  return s.str();
}

}  // namespace ppohdem::dem
