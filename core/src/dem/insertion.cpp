// Particle insertion: candidates, their overlap tests and the schedule (insertion.hpp;
// docs/objects.md "Particle insertion").
#include "ppohdem/dem/insertion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "ppohdem/dem/distance_field_object.hpp"
#include "ppohdem/grid/trilinear.hpp"

namespace ppohdem::dem {
namespace {

/// Two unit vectors perpendicular to the unit `axis` and to each other (a fixed choice).
std::pair<Vec3, Vec3> perpendicular_basis(const Vec3& axis) {
  const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = (helper - helper.dot(axis) * axis).normalized();
  return {e1, axis.cross(e1)};
}

/// The region's bounding box [m].
std::pair<Vec3, Vec3> bounding_box(const InsertRegion& region) {
  if (region.kind == InsertRegion::Kind::kBox) return {region.lo, region.hi};
  const Vec3 end = region.point + region.length * region.axis;
  Vec3 half;  // a disc of radius R with unit normal a reaches R sqrt(1 - a_i^2) along axis i
  for (int i = 0; i < 3; ++i) half[i] = region.radius * std::sqrt(std::max(0.0, 1.0 - region.axis[i] * region.axis[i]));
  return {region.point.cwiseMin(end) - half, region.point.cwiseMax(end) + half};
}

/// True if a sphere of radius r (already grown by kInsertGap) touches or has crossed a
/// boundary at `time`. No side effect: an object's outside-grid count is not touched (the
/// candidates are not particles of the run).
bool touches_boundary(const Boundary& boundary, const Vec3& centre, double r, double time) {
  if (const auto* wall = dynamic_cast<const PlaneWall*>(&boundary)) {
    return PlaneWall::signed_distance(wall->point_at(time), wall->normal(), centre) < r;
  }
  if (const auto* object = dynamic_cast<const DistanceFieldObject*>(&boundary)) {
    const Vec3 local = object->pose_at(time).inverse().apply(centre);  // object frame [m]
    const auto sample = sample_trilinear(object->field(), local);
    if (!sample) return false;  // outside the grid: far from the object, as for the engines
    if (!object->contact_mesh()) return sample->value < r;
    // With exact mesh contacts: the field clears a sphere only beyond one cell diagonal
    // (object_mesh_contacts.cpp), the mesh decides nearer; a centre inside is refused.
    const double diagonal = object->field().grid.spacing.norm() * (1.0 + 1e-9);
    if (sample->value >= r + diagonal) return false;
    if (sample->value <= 0.0) return true;
    std::vector<MeshContact> found;
    object->contact_mesh()->contacts(local, r, found);
    return !found.empty();
  }
  std::vector<FeatureContact> contacts;  // any other boundary through its interface
  boundary.contacts(centre, r, time, contacts);
  return !contacts.empty() || boundary.has_escaped(centre, time);
}

/// The number of cells of side `side` along axis i of [lo, hi] (at least one).
double cells_along(const Vec3& lo, const Vec3& hi, double side, int i) {
  return std::max(1.0, std::ceil((hi[i] - lo[i]) / side));
}

/// The particles near the region in cells of side >= the largest sum of two radii, so that
/// a candidate's possible partners lie in the 27 cells around its own. The cells are a dense
/// table of list heads and each particle links to the next of its cell (Hockney & Eastwood,
/// "Computer Simulation Using Particles", 1988, 8-4): a candidate reads nine runs of three
/// adjacent heads, not a cache miss per cell as in a hash map (docs/performance.md "The
/// candidates' cells").
class NearParticles {
 public:
  /// `side` from insert_cell_side.
  NearParticles(const Vec3& lo, const Vec3& hi, double side) : lo_(lo), side_(side) {
    for (int i = 0; i < 3; ++i) dims_[i] = static_cast<long>(cells_along(lo, hi, side_, i));
    head_.assign(static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]), kNone);
  }
  void add(const Vec3& x, double r) {
    const std::size_t k = key(cell(x));
    near_.push_back({x, r, head_[k]});
    head_[k] = static_cast<std::uint32_t>(near_.size() - 1);
  }
  /// True if a sphere (x, r) comes closer than (1 + kInsertGap)(r + R_j) to a particle j.
  bool overlaps(const Vec3& x, double r) const {
    const std::array<long, 3> c = cell(x);
    const long x0 = std::max(c[0] - 1, 0L), x1 = std::min(c[0] + 1, dims_[0] - 1);
    for (long z = std::max(c[2] - 1, 0L); z <= std::min(c[2] + 1, dims_[2] - 1); ++z) {
      for (long y = std::max(c[1] - 1, 0L); y <= std::min(c[1] + 1, dims_[1] - 1); ++y) {
        for (long cx = x0; cx <= x1; ++cx) {
          for (std::uint32_t j = head_[key({cx, y, z})]; j != kNone; j = near_[j].next) {
            const double reach = (1.0 + kInsertGap) * (r + near_[j].radius);
            if ((x - near_[j].centre).squaredNorm() < reach * reach) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::array<long, 3> cell(const Vec3& x) const {
    std::array<long, 3> c{};
    for (int i = 0; i < 3; ++i) {
      const double u = std::floor((x[i] - lo_[i]) / side_);
      c[i] = u < 0.0 ? 0 : (u >= static_cast<double>(dims_[i]) ? dims_[i] - 1 : static_cast<long>(u));
    }
    return c;
  }
  std::size_t key(const std::array<long, 3>& c) const {
    return static_cast<std::size_t>(c[0] + dims_[0] * (c[1] + dims_[1] * c[2]));
  }

  Vec3 lo_;
  double side_;
  std::array<long, 3> dims_{};
  /// A particle and the one added before it to its cell (or kNone): one record, so that a
  /// test of it reads one cache line rather than one per array.
  struct Near {
    Vec3 centre;
    double radius;
    std::uint32_t next;
  };
  std::vector<Near> near_;
  std::vector<std::uint32_t> head_;  ///< per cell: its last added particle, or kNone
};

}  // namespace

Vec3 InsertRegion::centre(double u1, double u2, double u3, double r) const {
  if (kind == Kind::kBox) {
    const Vec3 a = lo + Vec3::Constant(r), b = hi - Vec3::Constant(r);
    return a + Vec3(u1, u2, u3).cwiseProduct(b - a);
  }
  const auto [e1, e2] = perpendicular_basis(axis);
  const double rho = std::sqrt(u1) * (radius - r);  // uniform over the disc of radius R - r
  const double phi = 2.0 * std::numbers::pi * u2;
  return point + (r + u3 * (length - 2.0 * r)) * axis + rho * (std::cos(phi) * e1 + std::sin(phi) * e2);
}

bool InsertRegion::holds(const Vec3& c, double r) const {
  constexpr double slack = 1e-12;  // [m], the rounding of centre() for regions of order 1 m
  if (kind == Kind::kBox) {
    return ((c.array() - r) >= lo.array() - slack).all() && ((c.array() + r) <= hi.array() + slack).all();
  }
  const Vec3 d = c - point;
  const double s = d.dot(axis);
  return s >= r - slack && s <= length - r + slack && (d - s * axis).norm() <= radius - r + slack;
}

bool InsertRegion::fits(double r) const {
  if (kind == Kind::kBox) return ((hi - lo).array() > 2.0 * r).all();
  return radius > r && length > 2.0 * r;
}

double InsertRegion::volume() const {
  if (kind == Kind::kBox) return (hi - lo).prod();
  return std::numbers::pi * radius * radius * length;
}

std::pair<double, std::uint16_t> InsertSizes::draw(double u) const {
  if (kind == Kind::kConstant) return {r_min, material};
  if (kind == Kind::kUniform) return {r_min + u * (r_max - r_min), material};
  double cumulative = 0.0;
  for (const InsertSize& e : entries) {
    cumulative += e.probability;
    if (u < cumulative) return {e.radius, e.material};
  }
  return {entries.back().radius, entries.back().material};
}

double InsertSizes::largest() const {
  if (kind != Kind::kDiscrete) return kind == Kind::kConstant ? r_min : r_max;
  double r = 0.0;
  for (const InsertSize& e : entries) r = std::max(r, e.radius);
  return r;
}

double InsertSizes::smallest() const {
  if (kind != Kind::kDiscrete) return r_min;
  double r = std::numeric_limits<double>::infinity();
  for (const InsertSize& e : entries) r = std::min(r, e.radius);
  return r;
}

bool InsertSchedule::has_event(std::uint64_t k) const {
  if (every_steps == 0) return k == 0 && first_step <= last_step;
  return k <= static_cast<std::uint64_t>((last_step - first_step) / every_steps) && first_step <= last_step;
}

long InsertSchedule::wanted(std::uint64_t k, long requested_so_far, double dt) const {
  long n = count;
  if (rate > 0.0) {
    const double interval = static_cast<double>(every_steps) * dt;  // [s]
    const auto due = [&](std::uint64_t events) {
      return static_cast<long>(std::floor(rate * static_cast<double>(events) * interval + 1e-9));
    };
    n = due(k + 1) - due(k);
  }
  if (total >= 0) n = std::min(n, total - requested_so_far);
  return std::max(0L, n);
}

double insert_uniform(std::uint64_t seed, std::uint64_t u) {
  std::uint64_t z = seed + (u + 1) * 0x9E3779B97F4A7C15ULL;  // SplitMix64 (Steele et al. 2014)
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;  // the top 53 bits: exact, in [0, 1)
}

namespace {

/// Particles farther than this from the region's box cannot touch a candidate [m]: the sum of
/// the largest new and the largest existing radius, the gap kInsertGap included.
double reach_of(const InsertSpec& spec, double largest_radius) {
  const double r_new = spec.sizes.largest();
  return (1.0 + 1e-6) * (r_new + std::max(r_new, largest_radius));
}

constexpr double kCellsWanted = 2097152.0;  ///< 2^21: the cube-root side's count

/// The number of cells of side `side` over [lo, hi] (at least one along each axis).
double cells_over(const Vec3& lo, const Vec3& hi, double side) {
  double count = 1.0;
  for (int i = 0; i < 3; ++i) count *= cells_along(lo, hi, side, i);
  return count;
}

}  // namespace

double insert_cell_side(const Vec3& lo, const Vec3& hi, double reach) {
  double side = std::max(reach, std::cbrt((hi - lo).prod() / kCellsWanted));
  // A thin box's thin axis counts one cell however small the side, so the cube root of its
  // volume can leave many more cells than wanted: grow the side until it does not.
  while (cells_over(lo, hi, side) > 2.0 * kCellsWanted) side *= 1.25;
  return side;
}

std::pair<Vec3, Vec3> insert_reach(const InsertSpec& spec, double largest_radius) {
  const double reach = reach_of(spec, largest_radius);
  const auto [lo, hi] = bounding_box(spec.region);
  return {lo - Vec3::Constant(reach), hi + Vec3::Constant(reach)};
}

Particles insert_event(const InsertSpec& spec, long wanted, InsertCounters& counters, const Particles& existing,
                       const BoundaryList& boundaries, double time, std::int64_t& next_id) {
  double largest = 0.0;
  for (const Particle& p : existing) largest = std::max(largest, p.radius);
  return insert_event(spec, wanted, counters, existing, largest, boundaries, time, next_id);
}

Particles insert_event(const InsertSpec& spec, long wanted, InsertCounters& counters, const Particles& nearby,
                       double largest_radius, const BoundaryList& boundaries, double time, std::int64_t& next_id) {
  Particles added;
  if (wanted <= 0) return added;
  const auto [lo, hi] = insert_reach(spec, largest_radius);
  NearParticles near(lo, hi, insert_cell_side(lo, hi, reach_of(spec, largest_radius)));
  for (const Particle& p : nearby) {
    if (((p.position.array() >= lo.array()) && (p.position.array() <= hi.array())).all()) near.add(p.position, p.radius);
  }
  for (long n = 0; n < wanted; ++n) {
    bool placed = false;
    for (long attempt = 0; attempt < spec.attempts && !placed; ++attempt) {
      const double u0 = insert_uniform(spec.seed, counters.draws++);
      const double u1 = insert_uniform(spec.seed, counters.draws++);
      const double u2 = insert_uniform(spec.seed, counters.draws++);
      const double u3 = insert_uniform(spec.seed, counters.draws++);
      const auto [r, material] = spec.sizes.draw(u0);
      const Vec3 x = spec.region.centre(u1, u2, u3, r);
      if (near.overlaps(x, r)) continue;
      bool blocked = false;
      for (const auto& b : boundaries) blocked = blocked || touches_boundary(*b, x, (1.0 + kInsertGap) * r, time);
      if (blocked) continue;
      Particle p;
      p.id = next_id++;
      p.position = x;
      p.velocity = spec.velocity;
      p.angular_velocity = spec.angular_velocity;
      p.radius = r;
      p.material = material;
      near.add(x, r);
      added.push_back(p);
      placed = true;
    }
    if (placed) ++counters.inserted;
    else ++counters.failed;
  }
  return added;
}

Particles insert_size_probes(const std::vector<InsertSpec>& specs) {
  Particles probes;
  auto add = [&](double r, std::uint16_t material) {
    Particle p;
    p.id = static_cast<std::int64_t>(probes.size()) + 1;
    p.position = Vec3(static_cast<double>(probes.size()) * 1e6, 0.0, 0.0);
    p.radius = r;
    p.material = material;
    probes.push_back(p);
  };
  for (const InsertSpec& s : specs) {
    if (s.sizes.kind == InsertSizes::Kind::kDiscrete) {
      for (const InsertSize& e : s.sizes.entries) add(e.radius, e.material);
    } else {
      add(s.sizes.r_min, s.sizes.material);
      add(s.sizes.r_max, s.sizes.material);
    }
  }
  return probes;
}

}  // namespace ppohdem::dem
