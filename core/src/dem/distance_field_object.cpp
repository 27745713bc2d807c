// A rigid object from a signed distance field (formulas in distance_field_object.hpp).
#include "ppohdem/dem/distance_field_object.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ppohdem/error.hpp"
#include "ppohdem/grid/trilinear.hpp"

namespace ppohdem::dem {

namespace {

// The program of a single motion, with its checks (an InputError naming the object).
MotionProgram single_program(const RigidMotion& motion, const std::string& name, double start, double stop) {
  if (!motion.velocity.allFinite() || !motion.angular_velocity.allFinite() || !motion.centroid.allFinite()) {
    throw InputError(name, 0, "object motion: expected finite velocity, angular velocity and centroid");
  }
  if (!std::isfinite(start) || std::isnan(stop) || stop < start) {
    throw InputError(name, 0, "object motion: expected a finite start <= stop");
  }
  return MotionProgram::single(motion, start, stop);
}

}  // namespace

DistanceFieldObject::DistanceFieldObject(ScalarField field, const RigidMotion& motion,
                                         std::string name, double start, double stop)
    : field_(std::move(field)), motion_(motion), program_(single_program(motion, name, start, stop)),
      name_(std::move(name)), start_(start), stop_(stop) {
  check_field();
  index_extent();
}

DistanceFieldObject::DistanceFieldObject(ScalarField field, MotionProgram program, std::string name)
    : field_(std::move(field)), program_(std::move(program)), name_(std::move(name)),
      start_(program_.segments().empty() ? 0.0 : program_.segments().front().start),
      stop_(std::numeric_limits<double>::infinity()) {
  motion_.centroid = program_.reference_point();
  check_field();
  index_extent();
}

void DistanceFieldObject::check_field() const {
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
}

RigidTransform DistanceFieldObject::pose_at(double time) const { return program_.pose_at(time); }

Vec3 DistanceFieldObject::centroid_at(double time) const { return program_.reference_point_at(time); }

Vec3 DistanceFieldObject::point_velocity(const Vec3& x, double time) const {
  return program_.point_velocity(x, time);  // zero while at rest
}

std::optional<BoundaryContact> DistanceFieldObject::contact(const Vec3& centre, double radius,
                                                            double time) const {
  const RigidTransform pose = pose_at(time);
  const Vec3 local = pose.inverse().apply(centre);  // y = P^-1 x [m]
  const auto sample = sample_trilinear(field_, local);
  if (!sample) {
    if (within_reach(local, radius)) outside_grid_.fetch_add(1, std::memory_order_relaxed);
    return std::nullopt;  // far away: no contact (counted if the object might reach it)
  }
  const double phi = sample->value;  // signed distance of the centre [m]
  const double gradient_norm = sample->gradient.norm();
  if (phi >= radius || !(gradient_norm > 0.0)) return std::nullopt;
  BoundaryContact c;
  c.normal = pose.rotate(sample->gradient / gradient_norm);  // object -> particle, world frame
  c.overlap = radius - phi;                                  // delta = R - phi [m]
  c.point = centre - phi * c.normal;                         // foot on the tangent plane [m]
  c.surface_velocity = point_velocity(c.point, time);        // v + omega x (p - c(t)) [m/s]
  c.surface_spin = program_.angular_velocity_at(time);       // Omega(t) [rad/s], zero at rest
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
