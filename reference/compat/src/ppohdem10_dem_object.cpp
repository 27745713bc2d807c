// The original DEM's moving object (ppohDEM_check_objects, ppohDEM_embedding,
// force_from_objects, distance_from_objects); see ppohdem10_dem.hpp.
//
// The object is a signed distance field d on the 20^3 window nodes (spacing h = L/19 [m],
// node (i,j,k) at h (i-1, j-1, k-1)). Once per output frame f it is resampled from the data
// grid (76^3, same spacing h): window node u = (i,j,k) + winstart - 1 (data index units) maps to
//   p = R(f) (u - c) - vel f + c,   c = centroid / h,  R(f) = rotation by f omega_w about omega_axis
// (unit quaternion q = (cos(a/2), axis sin(a/2)), a = f omega_w; Shoemake 1985, SIGGRAPH 19(3)
// 245-254), and d(i,j,k) = trilinear interpolation of the data at p.
// A particle of radius r at x feels, if r - d(x) > 0, the force (per component a)
//   F_a = n_a (Obj_Kn (r - d(x)) - En v_a),   n = grad d / |grad d|        [N]
// with d(x) and grad d interpolated from the window field (Q7 below).
#include <cmath>
#include <string>

#include "ppohdem/error.hpp"
#include "ppohdem/compat/ppohdem10_dem.hpp"

namespace ppohdem::compat {

namespace {
/// floor(q) as an int (Fortran FLOOR); non-finite or huge values are refused, not converted.
int floor_to_int(double q) {
  const double f = std::floor(q);
  if (!(std::abs(f) < 1e8)) {
    throw InputError("--compat ppohdem-1.0: a position for the object field is not finite or far outside the grid");
  }
  return static_cast<int>(f);
}
}  // namespace

double Ppohdem10Object::data(int i, int j, int k) const {
  if (i < 1 || j < 1 || k < 1 || i > data_nodes[0] || j > data_nodes[1] || k > data_nodes[2]) {
    throw InputError("--compat ppohdem-1.0: the object window samples the data grid outside its nodes at (" +
                     std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                     ") (the original reads outside its array there)");
  }
  const auto nx = static_cast<std::size_t>(data_nodes[0]);
  const auto ny = static_cast<std::size_t>(data_nodes[1]);
  return read_distance_3D[static_cast<std::size_t>(i - 1) +
                          nx * (static_cast<std::size_t>(j - 1) + ny * static_cast<std::size_t>(k - 1))];
}

void ppohdem10_update_object_field(Ppohdem10Object& o, int omega_count) {
  // Q6: README "the object field updated once per output frame": the object jumps by one
  // frame's motion every 500 steps and is still in between.
  const Rvec3 rotate_centroid = {o.centroid.x / o.gridsize.x, o.centroid.y / o.gridsize.y,
                                 o.centroid.z / o.gridsize.z};
  const Rvec3& w = o.omega_axis;
  const double norm = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
  const Rvec3 qn = {w.x / norm, w.y / norm, w.z / norm};
  const double half_angle = o.omega_w * omega_count / 2;  // [rad]
  const double q0 = std::cos(half_angle);
  const double q1 = qn.x * std::sin(half_angle);
  const double q2 = qn.y * std::sin(half_angle);
  const double q3 = qn.z * std::sin(half_angle);
  const int nx = o.gridnum[0];
  const int ny = o.gridnum[1];
  const int nz = o.gridnum[2];
  for (int k = 1; k <= nz; ++k) {
    for (int j = 1; j <= ny; ++j) {
      for (int i = 1; i <= nx; ++i) {
        // The original's node number uses ny where nx belongs; the same for the cube's 20^3.
        const int ijk = (k - 1) * nx * ny + (j - 1) * ny + i;
        const Rvec3 moved = {(i + o.winstart[0] - 1) - rotate_centroid.x, (j + o.winstart[1] - 1) - rotate_centroid.y,
                             (k + o.winstart[2] - 1) - rotate_centroid.z};
        // Rotation matrix of q applied to `moved`, row by row, in the original's term order.
        const double dx = (q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3) * moved.x + 2 * (q1 * q2 - q0 * q3) * moved.y +
                          2 * (q1 * q3 + q0 * q2) * moved.z;
        const double dy = 2 * (q1 * q2 + q0 * q3) * moved.x + (q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3) * moved.y +
                          2 * (q2 * q3 - q0 * q1) * moved.z;
        const double dz = 2 * (q1 * q3 - q0 * q2) * moved.x + 2 * (q2 * q3 + q0 * q1) * moved.y +
                          (q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3) * moved.z;
        // the next place [data index units]
        const Rvec3 pi = {dx - (o.vel.x * omega_count) + rotate_centroid.x, dy - (o.vel.y * omega_count) + rotate_centroid.y,
                          dz - (o.vel.z * omega_count) + rotate_centroid.z};
        const int i1 = floor_to_int(pi.x);
        const int j1 = floor_to_int(pi.y);
        const int k1 = floor_to_int(pi.z);
        const int i2 = i1 + 1;
        const int j2 = j1 + 1;
        const int k2 = k1 + 1;
        const double d1 = o.data(i1, j2, k2);
        const double d2 = o.data(i2, j2, k2);
        const double d3 = o.data(i1, j1, k2);
        const double d4 = o.data(i2, j1, k2);
        const double d5 = o.data(i1, j2, k1);
        const double d6 = o.data(i2, j2, k1);
        const double d7 = o.data(i1, j1, k1);
        const double d8 = o.data(i2, j1, k1);
        // Trilinear interpolation, each 1-D step divided by the sum of its weights (which is 1
        // up to rounding): x first at (j2,k2), (j1,k2), then y, then the same at k1, then z.
        const double a = pi.x - i1;
        const double b = i2 - pi.x;
        double pi1 = (b * d1 + a * d2) / (a + b);
        double pi2 = (b * d3 + a * d4) / (a + b);
        const double c = pi.y - j1;
        const double d = j2 - pi.y;
        const double di1 = (c * pi1 + d * pi2) / (c + d);
        pi1 = (b * d5 + a * d6) / (a + b);
        pi2 = (b * d7 + a * d8) / (a + b);
        const double di2 = (c * pi1 + d * pi2) / (c + d);
        const double e = pi.z - k1;
        const double f = k2 - pi.z;
        o.distance[static_cast<std::size_t>(ijk - 1)] = (e * di1 + f * di2) / (e + f);
      }
    }
  }
}

namespace {

/// The 8 window nodes around x and the in-cell offsets, as distance_from_objects computes them.
/// Q7: README "the interpolation cell is floor(pos/gridsize), but the weights use
/// mod(pos, gridsize) WITHOUT dividing by gridsize, so the weight t runs over [0, 0.579) instead
/// of [0, 1)". The interpolated distance is then biased toward the cell's low corner and jumps
/// at every cell face; the gradient below uses the same weights.
struct Cell8 {
  std::size_t ijk[8];  // 0-based
  double vx, vy, vz;   // mod(x, h) [m], used as weights
};
Cell8 object_cell(const Ppohdem10Object& o, const Rvec3& pos, const Ppohdem10Particles& p, std::size_t index,
                  long itime) {
  const int cvx = floor_to_int(pos.x / o.gridsize.x);
  const int cvy = floor_to_int(pos.y / o.gridsize.y);
  const int cvz = floor_to_int(pos.z / o.gridsize.z);
  const int nx = o.gridnum[0];
  const int ny = o.gridnum[1];
  Cell8 c{};
  // gfortran's MOD for reals is the C library's fmod (exact).
  c.vx = std::fmod(pos.x, o.gridsize.x);
  c.vy = std::fmod(pos.y, o.gridsize.y);
  c.vz = std::fmod(pos.z, o.gridsize.z);
  const int ijk1 = cvx + cvy * nx + cvz * nx * ny + 1;
  const int n[8] = {ijk1,           ijk1 + 1,           ijk1 + nx,           ijk1 + 1 + nx,
                    ijk1 + nx * ny, ijk1 + 1 + nx * ny, ijk1 + nx + nx * ny, ijk1 + 1 + nx + nx * ny};
  // Outside the window (a centre that left the box) these are the numbers of other nodes (cvy = -1
  // lands in the layer below), which the original reads as they are; only numbers outside the
  // field's array are refused.
  const int total = nx * ny * o.gridnum[2];
  for (int m = 0; m < 8; ++m) {
    if (n[m] < 1 || n[m] > total) {
      throw InputError("--compat ppohdem-1.0: step " + std::to_string(itime + 1) + ": particle id " +
                       std::to_string(p.id[index]) + " is outside the object grid's array (the original reads outside it)");
    }
    c.ijk[m] = static_cast<std::size_t>(n[m] - 1);
  }
  return c;
}

/// distance_from_objects [m].
double distance_from_objects(const Ppohdem10Object& o, const Cell8& c) {
  const std::vector<double>& d = o.distance;
  const double vx = c.vx, vy = c.vy, vz = c.vz;
  double s = d[c.ijk[0]] * (1. - vx) * (1. - vy) * (1. - vz);
  s = s + d[c.ijk[1]] * vx * (1. - vy) * (1. - vz);
  s = s + d[c.ijk[2]] * (1. - vx) * vy * (1. - vz);
  s = s + d[c.ijk[3]] * vx * vy * (1. - vz);
  s = s + d[c.ijk[4]] * (1. - vx) * (1. - vy) * vz;
  s = s + d[c.ijk[5]] * vx * (1. - vy) * vz;
  s = s + d[c.ijk[6]] * (1. - vx) * vy * vz;
  s = s + d[c.ijk[7]] * vx * vy * vz;
  return s;
}

/// force_from_objects [N].
Rvec3 force_from_objects(const Ppohdem10Object& o, const Ppohdem10Particles& p, std::size_t index, long itime) {
  const Cell8 c = object_cell(o, p.pos[index], p, index, itime);
  const double distance = distance_from_objects(o, c);
  if (!(p.radius[index] - distance > 0)) return Rvec3{0.0, 0.0, 0.0};
  const std::vector<double>& d = o.distance;
  const double vx = c.vx, vy = c.vy, vz = c.vz;
  // The gradient of the trilinear form (per unit weight), term by term as the original; the
  // factor (-1.) is kept where the original writes it (x (-1.) is exact).
  Rvec3 dn;
  dn.x = d[c.ijk[0]] * (-1.) * (1. - vy) * (1. - vz);
  dn.x = dn.x + d[c.ijk[1]] * (1. - vy) * (1. - vz);
  dn.x = dn.x + d[c.ijk[2]] * (-1.) * vy * (1. - vz);
  dn.x = dn.x + d[c.ijk[3]] * vy * (1. - vz);
  dn.x = dn.x + d[c.ijk[4]] * (-1.) * (1. - vy) * vz;
  dn.x = dn.x + d[c.ijk[5]] * (1. - vy) * vz;
  dn.x = dn.x + d[c.ijk[6]] * (-1.) * vy * vz;
  dn.x = dn.x + d[c.ijk[7]] * vy * vz;

  dn.y = d[c.ijk[0]] * (1. - vx) * (-1.) * (1. - vz);
  dn.y = dn.y + d[c.ijk[1]] * vx * (-1.) * (1. - vz);
  dn.y = dn.y + d[c.ijk[2]] * (1. - vx) * (1. - vz);
  dn.y = dn.y + d[c.ijk[3]] * vx * (1. - vz);
  dn.y = dn.y + d[c.ijk[4]] * (1. - vx) * (-1.) * vz;
  dn.y = dn.y + d[c.ijk[5]] * vx * (-1.) * vz;
  dn.y = dn.y + d[c.ijk[6]] * (1. - vx) * vz;
  dn.y = dn.y + d[c.ijk[7]] * vx * vz;

  dn.z = d[c.ijk[0]] * (1. - vx) * (1. - vy) * (-1.);
  dn.z = dn.z + d[c.ijk[1]] * vx * (1. - vy) * (-1.);
  dn.z = dn.z + d[c.ijk[2]] * (1. - vx) * vy * (-1.);
  dn.z = dn.z + d[c.ijk[3]] * vx * vy * (-1.);
  dn.z = dn.z + d[c.ijk[4]] * (1. - vx) * (1. - vy);
  dn.z = dn.z + d[c.ijk[5]] * vx * (1. - vy);
  dn.z = dn.z + d[c.ijk[6]] * (1. - vx) * vy;
  dn.z = dn.z + d[c.ijk[7]] * vx * vy;

  normalize_rvec3(dn);
  // Q7: README "damping is per component, and it uses En, not Obj_En": the dashpot acts on
  // each velocity component along the same axis, not on the normal velocity.
  const double r = p.radius[index];
  const Rvec3& v = p.vel[index];
  using C = Ppohdem10DemConstants;
  return {dn.x * (C::kObjectStiffness * (r - distance) - C::kNormalDamping * v.x),
          dn.y * (C::kObjectStiffness * (r - distance) - C::kNormalDamping * v.y),
          dn.z * (C::kObjectStiffness * (r - distance) - C::kNormalDamping * v.z)};
}

}  // namespace

void ppohdem10_embedding(Ppohdem10Particles& p, const Ppohdem10Object& object, long itime) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.force[i] = add_rvec3(p.force[i], force_from_objects(object, p, i, itime));
  }
}

}  // namespace ppohdem::compat
