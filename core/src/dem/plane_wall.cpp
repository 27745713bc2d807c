#include <cmath>
#include <sstream>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/error.hpp"

namespace ppohdem::dem {

PlaneWall::PlaneWall(const Vec3& point, const Vec3& normal, const Vec3& velocity)
    : point_(point), normal_(normal), velocity_(velocity) {
  const double length = normal.norm();
  if (!(length > 0.0) || !std::isfinite(length) || !point.allFinite() || !velocity.allFinite()) {
    throw InputError("wall: expected a finite point, velocity and a non-zero normal");
  }
  normal_ /= length;
}

std::optional<BoundaryContact> PlaneWall::contact(const Vec3& centre, double radius,
                                                  double time) const {
  const double distance = signed_distance(point_at(time), normal_, centre);  // [m]
  if (distance <= 0.0 || distance >= radius) return std::nullopt;
  return touching(normal_, velocity_, centre, radius, distance);
}

bool PlaneWall::has_escaped(const Vec3& centre, double time) const {
  return signed_distance(point_at(time), normal_, centre) <= 0.0;
}

std::string PlaneWall::describe() const {
  std::ostringstream s;
  s << "wall point (" << point_.x() << ", " << point_.y() << ", " << point_.z() << ") normal ("
    << normal_.x() << ", " << normal_.y() << ", " << normal_.z() << ")";
  if (velocity_.squaredNorm() > 0.0) {
    s << " velocity (" << velocity_.x() << ", " << velocity_.y() << ", " << velocity_.z() << ")";
  }
  return s.str();
}

}  // namespace ppohdem::dem
