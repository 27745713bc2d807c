#include "ppohdem/dem/output_writers.hpp"

#include <algorithm>
#include <cstdio>

#include "ppohdem/io/atomic_file.hpp"

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
