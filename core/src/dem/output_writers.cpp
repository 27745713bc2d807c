#include "ppohdem/dem/output_writers.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "ppohdem/comm/comm.hpp"
#include "ppohdem/io/atomic_file.hpp"
#include "ppohdem/io/block_file.hpp"
#include "write_in_rank_order.hpp"

namespace ppohdem::dem {

std::string frame_stem(long step) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%06ld", step);
  return buf;
}

void write_vtk_frame(const std::filesystem::path& file, const Particles& particles,
                     const std::string& header) {
  AtomicFileWriter writer(file);
  std::ostream& out = writer.stream();
  // Legacy VTK: the title line is at most 256 characters.
  out << "# vtk DataFile Version 3.0\n" << header.substr(0, 255) << "\nASCII\nDATASET POLYDATA\n";
  const std::size_t n = particles.size();
  char buf[160];
  out << "POINTS " << n << " double\n";
  for (const Particle& p : particles) {
    std::snprintf(buf, sizeof buf, "%.10g %.10g %.10g\n", p.position.x(), p.position.y(), p.position.z());
    out << buf;
  }
  out << "VERTICES " << n << ' ' << 2 * n << '\n';
  for (std::size_t i = 0; i < n; ++i) out << "1 " << i << '\n';
  out << "POINT_DATA " << n << "\nSCALARS radius double 1\nLOOKUP_TABLE default\n";
  for (const Particle& p : particles) {
    std::snprintf(buf, sizeof buf, "%.10g\n", p.radius);
    out << buf;
  }
  out << "SCALARS id double 1\nLOOKUP_TABLE default\n";
  for (const Particle& p : particles) out << p.id << '\n';
  auto vectors = [&](const char* name, auto get) {
    out << "VECTORS " << name << " double\n";
    for (const Particle& p : particles) {
      const Vec3 v = get(p);
      std::snprintf(buf, sizeof buf, "%.10g %.10g %.10g\n", v.x(), v.y(), v.z());
      out << buf;
    }
  };
  vectors("velocity", [](const Particle& p) { return p.velocity; });
  vectors("angular_velocity", [](const Particle& p) { return p.angular_velocity; });
  writer.commit();
}

namespace {

/// The POV-Ray scene's head: the run header, then camera and light framing the box [lo, hi].
std::string pov_head(const std::string& header, const Vec3& lo, const Vec3& hi) {
  std::string head = "// " + header + "\n// POV-Ray scene: <x, z, y> because POV-Ray is y-up (as the seed).\n";
  // Frame the particles: camera on the -y side (POV -z), looking at the centre.
  const Vec3 c = 0.5 * (lo + hi);
  const double size = std::max((hi - lo).maxCoeff(), 1e-12);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "#include \"colors.inc\"\nbackground { color White }\n"
                "camera { location <%.8g, %.8g, %.8g> look_at <%.8g, %.8g, %.8g> }\n"
                "light_source { <%.8g, %.8g, %.8g> color White }\n",
                c.x(), c.z() + 0.5 * size, c.y() - 2.0 * size, c.x(), c.z(), c.y(),
                c.x() + size, c.z() + 2.0 * size, c.y() - 2.0 * size);
  return head + buf;
}

/// One particle's POV-Ray sphere, with its newline, into buf; returns the length.
int pov_sphere(char* buf, std::size_t size, const Particle& p) {
  return std::snprintf(buf, size, "sphere { <%.10g, %.10g, %.10g>, %.10g pigment { color rgb <0.8, 0.5, 0.2> } }\n",
                       p.position.x(), p.position.z(), p.position.y(), p.radius);
}

/// The objects' display meshes at pose_at(time), one POV-Ray `mesh` each.
std::string pov_objects(const std::vector<std::shared_ptr<const DistanceFieldObject>>& objects, double time) {
  std::string text;
  char buf[256];
  // Objects: the display mesh at the object's pose, in the same <x, z, y> order. (Swapping y and
  // z mirrors the scene; POV-Ray triangles have no facing side, so the order is harmless.)
  for (const auto& object : objects) {
    const TriangleMesh* mesh = object ? object->display_mesh() : nullptr;
    if (!mesh || mesh->empty()) continue;
    const RigidTransform pose = object->pose_at(time);
    text += "mesh {\n";
    for (const Triangle& t : mesh->triangles) {
      text += "  triangle {";
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = pose.apply(t.v[static_cast<std::size_t>(k)]);
        std::snprintf(buf, sizeof buf, "%s<%.10g, %.10g, %.10g>", k == 0 ? " " : ", ", p.x(), p.z(), p.y());
        text += buf;
      }
      text += " }\n";
    }
    text += "  pigment { color rgb <0.3, 0.5, 0.8> }\n}\n";
  }
  return text;
}

}  // namespace

void write_pov_frame(const std::filesystem::path& file, const Particles& particles,
                     const std::string& header,
                     const std::vector<std::shared_ptr<const DistanceFieldObject>>& objects, double time) {
  AtomicFileWriter writer(file);
  std::ostream& out = writer.stream();
  Vec3 lo = Vec3::Constant(0.0), hi = Vec3::Constant(0.0);
  if (!particles.empty()) {
    lo = hi = particles.front().position;
    for (const Particle& p : particles) {
      lo = lo.cwiseMin(p.position - Vec3::Constant(p.radius));
      hi = hi.cwiseMax(p.position + Vec3::Constant(p.radius));
    }
  }
  out << pov_head(header, lo, hi);
  char buf[256];
  for (const Particle& p : particles) {
    pov_sphere(buf, sizeof buf, p);
    out << buf;
  }
  out << pov_objects(objects, time);
  writer.commit();
}

namespace {

void append(Bytes& text, const char* s, std::size_t n) { text.insert(text.end(), s, s + n); }

/// One rank's lines of the legacy VTK frame's section `section` (0 POINTS, 1 VERTICES, 2 radius,
/// 3 id, 4 velocity, 5 angular_velocity), formatted as write_vtk_frame's loops format them.
Bytes vtk_section(const Particles& mine, std::size_t first, int section) {
  Bytes text;
  char buf[160];
  auto vector_lines = [&](auto get) {
    for (const Particle& p : mine) {
      const Vec3 v = get(p);
      append(text, buf, static_cast<std::size_t>(std::snprintf(buf, sizeof buf, "%.10g %.10g %.10g\n", v.x(), v.y(), v.z())));
    }
  };
  switch (section) {
    case 0: vector_lines([](const Particle& p) { return p.position; }); break;
    case 1:
      for (std::size_t k = 0; k < mine.size(); ++k) {
        char* at = std::to_chars(buf + 2, buf + sizeof buf - 1, first + k).ptr;  // 1: room for '\n'
        buf[0] = '1';
        buf[1] = ' ';
        *at++ = '\n';
        append(text, buf, static_cast<std::size_t>(at - buf));
      }
      break;
    case 2:
      for (const Particle& p : mine) append(text, buf, static_cast<std::size_t>(std::snprintf(buf, sizeof buf, "%.10g\n", p.radius)));
      break;
    case 3:
      for (const Particle& p : mine) {
        char* at = std::to_chars(buf, buf + sizeof buf - 1, p.id).ptr;
        *at++ = '\n';
        append(text, buf, static_cast<std::size_t>(at - buf));
      }
      break;
    case 4: vector_lines([](const Particle& p) { return p.velocity; }); break;
    default: vector_lines([](const Particle& p) { return p.angular_velocity; }); break;
  }
  return text;
}

}  // namespace

void write_vtk_frame(const std::filesystem::path& file, const Particles& mine, std::size_t first,
                     std::size_t total, const std::string& header, const Comm& comm) {
  std::unique_ptr<BlockFileWriter> writer;
  const std::string n = std::to_string(total);
  const std::string section_heads[6] = {
      "# vtk DataFile Version 3.0\n" + header.substr(0, 255) + "\nASCII\nDATASET POLYDATA\nPOINTS " + n + " double\n",
      "VERTICES " + n + ' ' + std::to_string(2 * total) + '\n',
      "POINT_DATA " + n + "\nSCALARS radius double 1\nLOOKUP_TABLE default\n",
      "SCALARS id double 1\nLOOKUP_TABLE default\n",
      "VECTORS velocity double\n",
      "VECTORS angular_velocity double\n"};
  if (comm.rank() == 0) writer = std::make_unique<BlockFileWriter>(file);
  for (int section = 0; section < 6; ++section) {
    const std::string& head = section_heads[section];
    if (writer) writer->write(head.data(), head.size());
    write_in_rank_order(writer.get(), vtk_section(mine, first, section), comm);
  }
  if (writer) writer->commit();
}

void write_pov_frame(const std::filesystem::path& file, const Particles& mine, std::size_t first,
                     std::size_t total, const std::string& header, const Comm& comm,
                     const std::vector<std::shared_ptr<const DistanceFieldObject>>& objects, double time) {
  // The one-rank writer's box: lo = hi = the first particle's position, then lo = min(lo,
  // x - r) and hi = max(hi, x + r) over the particles in order, by Eigen's cwiseMin/cwiseMax,
  // which are std::min(lo, v) and std::max(hi, v) per coordinate: the accumulator unless v
  // is strictly smaller (larger). So a NaN v is skipped (a NaN first position stays), and
  // among equal values (-0 and +0) the first one kept. Over values without NaN that fold is
  // associative, so each rank's fold over its part (its first value that is not NaN, then
  // std::min/max), combined in rank order after the first position, is the same bits.
  // Record: [count, first, has first position, its x y z, then per coordinate: has lo, lo,
  // has hi, hi] (the counts exact as doubles below 2^53).
  constexpr std::size_t kWords = 18;
  std::vector<double> record(kWords, 0.0);
  record[0] = static_cast<double>(mine.size());
  record[1] = static_cast<double>(first);
  if (first == 0 && !mine.empty()) {
    record[2] = 1.0;
    for (int k = 0; k < 3; ++k) record[3 + static_cast<std::size_t>(k)] = mine.front().position[k];
  }
  for (const Particle& p : mine) {
    for (int k = 0; k < 3; ++k) {
      double* box = &record[6 + 4 * static_cast<std::size_t>(k)];  // has lo, lo, has hi, hi
      const double lo = p.position[k] - p.radius, hi = p.position[k] + p.radius;
      if (box[0] != 0.0) {
        box[1] = std::min(box[1], lo);
      } else if (!std::isnan(lo)) {
        box[0] = 1.0;
        box[1] = lo;
      }
      if (box[2] != 0.0) {
        box[3] = std::max(box[3], hi);
      } else if (!std::isnan(hi)) {
        box[2] = 1.0;
        box[3] = hi;
      }
    }
  }
  const std::vector<double> records = comm.gather_to_root(record);
  std::unique_ptr<BlockFileWriter> writer;
  if (comm.rank() == 0) {
    const std::size_t ranks = static_cast<std::size_t>(comm.size());
    if (records.size() != ranks * kWords) throw std::logic_error("write_pov_frame: unequal records");
    Vec3 lo = Vec3::Constant(0.0), hi = Vec3::Constant(0.0);
    std::size_t count = 0;
    for (std::size_t r = 0; r < ranks; ++r) {  // the parts must follow each other
      const double* rec = &records[r * kWords];
      if (static_cast<std::size_t>(rec[1]) != count && rec[0] != 0.0) {
        throw std::invalid_argument("write_pov_frame: rank " + std::to_string(r) + "'s part does not follow the one before");
      }
      if (rec[2] != 0.0) lo = hi = Vec3(rec[3], rec[4], rec[5]);
      count += static_cast<std::size_t>(rec[0]);
    }
    if (count != total) throw std::invalid_argument("write_pov_frame: the parts do not hold `total` particles");
    for (std::size_t r = 0; r < ranks && total > 0; ++r) {
      const double* rec = &records[r * kWords];
      for (int k = 0; k < 3; ++k) {
        const double* box = rec + 6 + 4 * k;
        if (box[0] != 0.0) lo[k] = std::min(lo[k], box[1]);
        if (box[2] != 0.0) hi[k] = std::max(hi[k], box[3]);
      }
    }
    writer = std::make_unique<BlockFileWriter>(file);
    const std::string head = pov_head(header, lo, hi);
    writer->write(head.data(), head.size());
  }
  Bytes spheres;
  char buf[256];
  for (const Particle& p : mine) append(spheres, buf, static_cast<std::size_t>(pov_sphere(buf, sizeof buf, p)));
  write_in_rank_order(writer.get(), std::move(spheres), comm);
  if (!writer) return;
  const std::string tail = pov_objects(objects, time);
  writer->write(tail.data(), tail.size());
  writer->commit();
}

TriangleMesh transformed(const TriangleMesh& mesh, const RigidTransform& pose) {
  TriangleMesh moved = mesh;
  for (Triangle& t : moved.triangles) {
    for (Vec3& v : t.v) v = pose.apply(v);
    t.file_normal = pose.rotate(t.file_normal);
  }
  return moved;
}

void write_mesh_vtk(const std::filesystem::path& file, const TriangleMesh& mesh, const std::string& header) {
  AtomicFileWriter writer(file);
  std::ostream& out = writer.stream();
  out << "# vtk DataFile Version 3.0\n" << header.substr(0, 255) << "\nASCII\nDATASET POLYDATA\n";
  const std::size_t n = mesh.size();
  out << "POINTS " << 3 * n << " double\n";
  char buf[200];
  for (const Triangle& t : mesh.triangles) {
    for (const Vec3& v : t.v) {
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", v.x(), v.y(), v.z());
      out << buf;
    }
  }
  out << "POLYGONS " << n << ' ' << 4 * n << '\n';
  for (std::size_t i = 0; i < n; ++i) out << "3 " << 3 * i << ' ' << 3 * i + 1 << ' ' << 3 * i + 2 << '\n';
  writer.commit();
}

std::string object_mesh_file_name(std::size_t object_index, long step) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "object_%zu_%06ld.vtk", object_index, step);
  return buf;
}

EnergyLog::EnergyLog(std::filesystem::path file, std::string header)
    : file_(std::move(file)), header_(std::move(header)) {}

void EnergyLog::add(long step, double time, const Energies& e) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "%ld,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", step, time,
                e.kinetic, e.rotational, e.gravitational, e.elastic, e.dissipated, e.boundary_work);
  rows_.emplace_back(buf);
}

void EnergyLog::flush() const {
  AtomicFileWriter writer(file_);
  std::ostream& out = writer.stream();
  out << "# " << header_ << '\n';
  out << "step,time,kinetic,rotational,gravitational,elastic,dissipated,boundary_work\n";
  for (const std::string& row : rows_) out << row << '\n';
  writer.commit();
}

ObjectLog::ObjectLog(std::filesystem::path file, std::string header)
    : file_(std::move(file)), header_(std::move(header)) {}

void ObjectLog::add(long step, double time, std::size_t object_index, const DistanceFieldObject& object,
                    const BoundaryLoad& load, std::int64_t outside_grid_offset) {
  const RigidTransform pose = object.pose_at(time);
  const Vec3 c = object.centroid_at(time);
  const Vec3 torque = load.torque_about(c);  // about the current centroid [N m]
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "%ld,%.17g,%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                "%.17g,%.17g,%.17g,%.17g,%lld",
                step, time, object_index, c.x(), c.y(), c.z(), pose.rotation.w(), pose.rotation.x(),
                pose.rotation.y(), pose.rotation.z(), pose.translation.x(), pose.translation.y(),
                pose.translation.z(), load.force.x(), load.force.y(), load.force.z(), torque.x(),
                torque.y(), torque.z(),
                static_cast<long long>(static_cast<std::int64_t>(object.outside_grid_count()) + outside_grid_offset));
  rows_.emplace_back(buf);
}

void ObjectLog::flush() const {
  AtomicFileWriter writer(file_);
  std::ostream& out = writer.stream();
  out << "# " << header_ << '\n';
  out << "step,time,object,centroid_x,centroid_y,centroid_z,qw,qx,qy,qz,translation_x,translation_y,"
         "translation_z,force_x,force_y,force_z,torque_x,torque_y,torque_z,outside_grid\n";
  for (const std::string& row : rows_) out << row << '\n';
  writer.commit();
}

}  // namespace ppohdem::dem
