#pragma once
/// \file distance_field_object.hpp
/// A rigid object given by a signed distance field and a prescribed rigid motion (the seed's
/// DEM-Util objects_update), seen by the engine as a Boundary (boundary.hpp).
///
/// The field phi is stored in the OBJECT frame, which is the world frame at the start of the
/// motion: phi [m] at the nodes of `field.grid`, negative inside the object. With the pose
/// P(t) = motion.pose_at(tau(t)) (rigid_motion.hpp), a sphere of centre x and radius R:
///   y     = P(t)^-1 x                        centre in the object frame [m]
///   phi, g = trilinear value and exact gradient of the interpolant at y (trilinear.hpp)
///   n     = R(t) g / |g|                     unit normal, object -> particle (world frame)
///   delta = R - phi                          overlap [m]; contact when phi < R
///   p     = x - phi n                        contact point: the foot of the centre on the
///                                            local tangent plane of the zero level set
///                                            (the point PlaneWall uses for a wall) [m]
///   v_s   = v + omega x (p - c(t))           surface velocity at p [m/s]
/// The engine uses the contact laws with the object as body j of infinite mass and ZERO
/// CURVATURE (a local tangent plane): R* = R_particle, m* = m_particle, E* and G* as for a
/// wall. (For a sphere object of radius R_o the Hertz pair value would be R* = R R_o/(R + R_o);
/// this model deliberately uses the tangent plane, see docs/objects.md.)
/// A centre inside the object (phi <= 0) still gets a contact (delta >= R) pushing it out
/// along the gradient; a zero gradient gives no contact. has_escaped() is always false.
///
/// Time limits: the object moves for t in [start, stop] and rests outside it:
///   tau(t) = min(max(t, start), stop) - start,  v_s = 0 outside [start, stop).
/// The motion is a MotionProgram (motion_program.hpp): the single motion above is the program
/// MotionProgram::single(motion, start, stop); a program of several segments (translations,
/// rotations, vibrations, switched at given times) replaces it (P(t), v_s and the spin Omega(t)
/// come from the program; c(t) is the program's reference point).
///
/// Outside the grid: a centre whose object-frame position is outside the node box has no
/// contact (the object is treated as far away). It is counted (outside_grid_count()) only if it
/// lies within its radius R of the object's body box B (the contact mesh's box, else the
/// display mesh's, else the box of the inside nodes, phi <= 0, pushed one cell h out where they
/// reach the grid's faces): a particle that could touch the object, so the grid is too small
/// for it. The caller warns once (run_scene does). Particles merely far from a small object's
/// grid are not counted.
///
/// Far particles (reach(); docs/objects.md "Far objects cost nothing"): a sphere of radius
/// R <= r_max has a contact only where some node of its cell has phi < r_max + c (the
/// interpolant lies within its corners' range; c = 0 for the field's contact, one cell diagonal
/// for the mesh contacts' candidates), and is counted only within B + R. The box of both, moved
/// by the pose, bounds where anything can happen: an engine skips the spheres outside it.
///
/// Display mesh (optional, for pictures): a TriangleMesh in the object
/// frame (the frame of `field.grid`); the frame writers draw it moved by pose_at(t).
///
/// Contact mesh (optional, use_mesh_contacts()): contacts() then gives the exact contacts of
/// the mesh's faces, edges and vertices (mesh_contact.hpp), the field only finding the
/// candidates (object_mesh_contacts.cpp; docs/objects.md "Exact contacts for mesh objects").
/// contact() stays the field's single trilinear contact (the seed's method).
#include <array>
#include <atomic>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "ppohdem/dem/boundary.hpp"
#include "ppohdem/dem/mesh_contact.hpp"
#include "ppohdem/geometry/motion_program.hpp"
#include "ppohdem/geometry/rigid_motion.hpp"
#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::dem {

class DistanceFieldObject final : public Boundary {
 public:
  /// Throws InputError (naming `name`) if the grid is invalid, the value count does not match,
  /// a value is not finite, the motion is not finite or stop < start.
  DistanceFieldObject(ScalarField field, const RigidMotion& motion, std::string name,
                      double start = 0.0, double stop = std::numeric_limits<double>::infinity());
  /// An object moved by a motion program (checked by its constructor); throws InputError naming
  /// `name` if the grid or the values are invalid.
  DistanceFieldObject(ScalarField field, MotionProgram program, std::string name);

  std::optional<BoundaryContact> contact(const Vec3& centre, double radius,
                                         double time) const override;
  /// With a contact mesh: its contacts (feature ids of mesh_contact.hpp) where the field says
  /// phi < R + one cell diagonal; the field's contact (feature 0) for a centre inside (phi <= 0).
  /// Without: contact() as feature 0.
  void contacts(const Vec3& centre, double radius, double time, std::vector<FeatureContact>& out) const override;
  bool has_escaped(const Vec3& /*centre*/, double /*time*/) const override { return false; }
  /// The world box outside which spheres of radius <= r_max [m] have no contact and are not
  /// counted at time t [s] (see "Far particles" above; object_reach.cpp).
  ReachBox reach(double time, double r_max) const override;
  std::string describe() const override;

  /// The object's pose at time t [s]: object frame -> world.
  RigidTransform pose_at(double time) const;
  /// Centroid in the world at time t [m] (the point forces' torques are taken about).
  Vec3 centroid_at(double time) const;
  /// Velocity of the object's material at world point x at time t [m/s].
  Vec3 point_velocity(const Vec3& x, double time) const;
  /// Number of contact() and contacts() calls so far whose centre was outside the grid and
  /// within its radius of the object's body box (see "Outside the grid" above).
  std::size_t outside_grid_count() const { return outside_grid_.load(std::memory_order_relaxed); }

  const ScalarField& field() const { return field_; }
  /// The single motion it was built with (for a program: zero velocities, centroid = the
  /// program's reference point).
  const RigidMotion& motion() const { return motion_; }
  const MotionProgram& program() const { return program_; }
  const std::string& name() const { return name_; }
  double start() const { return start_; }  ///< the single motion's (a program: its first segment's)
  double stop() const { return stop_; }    ///< the single motion's (a program: infinity)

  /// Attach the display mesh (object frame, m); call before the object is shared.
  void set_display_mesh(TriangleMesh mesh) {
    if (!contact_mesh_) mesh_box_ = bounding_box(mesh);
    display_mesh_ = std::move(mesh);
  }
  /// The display mesh, or nullptr if the object has none.
  const TriangleMesh* display_mesh() const { return display_mesh_ ? &*display_mesh_ : nullptr; }

  /// Contacts from `mesh` (object frame, the mesh the field was built from); call before the
  /// object is shared. Throws InputError if the mesh has no triangle of non-zero area.
  void use_mesh_contacts(const TriangleMesh& mesh);
  /// The contact mesh, or nullptr if contacts come from the field alone.
  const MeshContactGeometry* contact_mesh() const { return contact_mesh_.get(); }
  /// The object's body box B in the object frame [m] (see "Outside the grid" above).
  const BoundingBox& body_box() const { return mesh_box_.empty() ? field_box_ : mesh_box_; }

 private:
  void check_field() const;
  /// The per-axis minima of the field and its inside box (object_reach.cpp); after check_field().
  void index_extent();
  /// Whether a centre at object-frame position `local`, outside the grid, is within `radius`
  /// of the body box (counted in outside_grid_count()).
  bool within_reach(const Vec3& local, double radius) const;
  /// How far beyond R the object looks for a contact [m]: the mesh contacts' candidates lie
  /// within R + one cell diagonal (object_mesh_contacts.cpp), the field's contact within R.
  double contact_range() const { return contact_mesh_ ? field_.grid.spacing.norm() * (1.0 + 1e-9) : 0.0; }

  ScalarField field_;
  RigidMotion motion_;
  MotionProgram program_;
  std::string name_;
  double start_;
  double stop_;
  std::optional<TriangleMesh> display_mesh_;
  std::shared_ptr<const MeshContactGeometry> contact_mesh_;
  mutable std::atomic<std::size_t> outside_grid_{0};
  /// slab_min_[a][i]: the smallest value of the nodes with index i along axis a [m].
  std::array<std::vector<double>, 3> slab_min_;
  BoundingBox field_box_;  ///< the inside nodes' box (see "Outside the grid") [m]
  BoundingBox mesh_box_;   ///< the contact mesh's, else the display mesh's box; empty if none [m]
};

}  // namespace ppohdem::dem
