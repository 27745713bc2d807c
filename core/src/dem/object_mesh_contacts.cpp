// Exact contacts of a distance-field object that carries its mesh (distance_field_object.hpp;
// docs/objects.md "Exact contacts for mesh objects"): the field finds the candidates, the mesh
// gives the contacts.
#include <cmath>

#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/grid/trilinear.hpp"

namespace ppohdem::dem {

void DistanceFieldObject::use_mesh_contacts(const TriangleMesh& mesh) {
  contact_mesh_ = std::make_shared<const MeshContactGeometry>(mesh);
  mesh_box_ = bounding_box(mesh);
}

void DistanceFieldObject::contacts(const Vec3& centre, double radius, double time,
                                   std::vector<FeatureContact>& out) const {
  if (!contact_mesh_) {
    Boundary::contacts(centre, radius, time, out);
    return;
  }
  out.clear();
  const RigidTransform pose = pose_at(time);
  const Vec3 local = pose.inverse().apply(centre);  // y = P^-1 x [m]
  const auto sample = sample_trilinear(field_, local);
  if (!sample) {
    if (within_reach(local, radius)) outside_grid_.fetch_add(1, std::memory_order_relaxed);
    return;  // far away: no contact (counted if the object might reach it)
  }
  // The interpolant of an exact distance d exceeds d by at most the cell diagonal (d is
  // 1-Lipschitz and the interpolant a convex combination of the cell's nodes), so
  // phi >= R + diagonal means no point of the mesh within R; 1e-9 covers the round-off.
  if (sample->value >= radius + contact_range()) return;
  if (sample->value <= 0.0) {  // centre inside the object: the field pushes it out (seed's rule)
    Boundary::contacts(centre, radius, time, out);
    return;
  }
  thread_local std::vector<MeshContact> found;
  contact_mesh_->contacts(local, radius, found);
  out.reserve(found.size());
  for (const MeshContact& m : found) {
    FeatureContact f;
    BoundaryContact& c = f.contact;
    c.normal = pose.rotate(m.normal);  // object -> particle, world frame
    c.overlap = m.overlap;             // delta = R - |y - q| [m]
    c.point = centre - (radius - m.overlap) * c.normal;  // the closest point q, in the world [m]
    c.surface_velocity = point_velocity(c.point, time);
    c.surface_spin = program_.angular_velocity_at(time);  // Omega(t) [rad/s], zero at rest
    f.feature = m.feature;
    out.push_back(f);
  }
}

}  // namespace ppohdem::dem
