// Where a distance-field object can touch a particle, or count it outside its grid
// (distance_field_object.hpp "Outside the grid" and "Far particles"; docs/objects.md "Far
// objects cost nothing"): engines skip the particles outside this box, with the same results.
#include <algorithm>
#include <cmath>

#include "ppohdem/dem/distance_field_object.hpp"

namespace ppohdem::dem {

void DistanceFieldObject::index_extent() {
  const GridSpec& g = field_.grid;
  for (int a = 0; a < 3; ++a) {
    slab_min_[a].assign(static_cast<std::size_t>(g.nodes[a]), std::numeric_limits<double>::infinity());
  }
  // The inside nodes' box; where they reach a face of the grid, the object goes on beyond it
  // (at least to the next node's place): that face moves out by one cell.
  std::array<int, 3> in_lo{g.nodes[0], g.nodes[1], g.nodes[2]};
  std::array<int, 3> in_hi{-1, -1, -1};
  for (int k = 0; k < g.nodes[2]; ++k) {
    for (int j = 0; j < g.nodes[1]; ++j) {
      for (int i = 0; i < g.nodes[0]; ++i) {
        const double phi = field_.at(i, j, k);
        const std::array<int, 3> n{i, j, k};
        for (std::size_t a = 0; a < 3; ++a) {
          double& m = slab_min_[a][static_cast<std::size_t>(n[a])];
          m = std::min(m, phi);
          if (phi <= 0.0) {
            in_lo[a] = std::min(in_lo[a], n[a]);
            in_hi[a] = std::max(in_hi[a], n[a]);
          }
        }
      }
    }
  }
  field_box_ = BoundingBox{};
  if (in_hi[0] < 0) return;  // no inside node: an empty body box
  for (int a = 0; a < 3; ++a) {
    field_box_.min[a] = g.origin[a] + (in_lo[a] == 0 ? -1 : in_lo[a]) * g.spacing[a];
    field_box_.max[a] = g.origin[a] + (in_hi[a] == g.nodes[a] - 1 ? in_hi[a] + 1 : in_hi[a]) * g.spacing[a];
  }
}

bool DistanceFieldObject::within_reach(const Vec3& local, double radius) const {
  const BoundingBox& b = body_box();
  if (b.empty()) return false;
  const Vec3 gap = (b.min - local).cwiseMax(local - b.max).cwiseMax(Vec3::Zero());  // to the box [m]
  return gap.norm() < radius;
}

ReachBox DistanceFieldObject::reach(double time, double r_max) const {
  const GridSpec& g = field_.grid;
  // Cells with a contact hold a node with phi < r_max + c (trilinear.cpp: the interpolant
  // stays within its corner values, exactly): the nodes' index range per axis, one cell out.
  const double threshold = r_max + contact_range();
  BoundingBox box;
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& m = slab_min_[a];
    const auto first = std::find_if(m.begin(), m.end(), [&](double v) { return v < threshold; });
    if (first == m.end()) {  // no contact anywhere
      box = BoundingBox{};
      break;
    }
    const auto last = std::find_if(m.rbegin(), m.rend(), [&](double v) { return v < threshold; });
    const int lo = std::max(static_cast<int>(first - m.begin()) - 1, 0);
    const int hi = std::min(static_cast<int>(m.rend() - last), g.nodes[a] - 1);  // last index + 1
    box.min[a] = g.origin[a] + lo * g.spacing[a];
    box.max[a] = g.origin[a] + hi * g.spacing[a];
  }
  // ... and the counted particles lie within r_max of the body box.
  const BoundingBox& body = body_box();
  if (!body.empty()) {
    box.expand(body.min - Vec3::Constant(r_max));
    box.expand(body.max + Vec3::Constant(r_max));
  }
  ReachBox reach;
  reach.r_max = r_max;
  if (box.empty()) {  // nothing anywhere: every sphere up to r_max is excluded
    reach.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    reach.hi = -reach.lo;
    return reach;
  }
  // Moved by the pose: the world box around the turned box. The slack (far above the
  // round-off of P^-1 x in contact(), far below a cell) keeps the test on the safe side.
  const RigidTransform pose = pose_at(time);
  const Vec3 centre = pose.apply(box.centre());
  const Vec3 half = pose.rotation.toRotationMatrix().cwiseAbs() * (0.5 * box.extent());
  const Vec3 slack = Vec3::Constant(1e-6 * g.spacing.maxCoeff() + 1e-12 * (centre.norm() + half.norm()));
  reach.lo = centre - half - slack;
  reach.hi = centre + half + slack;
  return reach;
}

}  // namespace ppohdem::dem
