#pragma once
/// \file mesh_contact.hpp
/// Exact contacts of a sphere with a triangle mesh: one contact per touching face, edge or
/// vertex, each along the true normal (docs/objects.md "Exact contacts for mesh objects").
///
/// Features. Vertices are welded when their coordinates are bit-identical (as mesh_stats.hpp).
/// Triangles that share an edge and whose unit normals differ by less than kFlatAngle [rad]
/// belong to one FACE (a flat face made of several triangles); an edge all of whose triangles
/// are in one face, and a vertex all of whose triangles are in one face, are part of that face.
/// The other edges (creases, open borders) and vertices (corners) are features of their own.
/// Feature ids (stable: a function of the mesh only): face f -> 1 + f, edge e -> 1 + F + e,
/// vertex v -> 1 + F + E + v, in the order of first appearance in the triangle list (0 is left
/// for the distance field's single contact).
///
/// Contacts of a sphere (centre c, radius R, object frame):
///   1. the triangles whose bounding box is within R of c (a BVH: sdf/fast/nearest_triangle.hpp);
///   2. each one's closest point q to c and its region (interior, one of its edges, one of its
///      vertices; Ericson 2005 sec. 5.1.5), kept if d = |c - q| < R;
///   3. a point in an edge or vertex region is a contact only if it is a local minimum of the
///      distance on the mesh: no triangle around that edge or vertex is strictly nearer
///      (a Voronoi-region test: a crease point seen from inside a concave notch is dominated by
///      the faces), and c is strictly in front of one of those triangles (a thin plate's far
///      side never pushes);
///   4. a point in a triangle's interior is a contact if c is strictly in front of the triangle;
///   5. contacts of the same feature, and contacts whose points coincide to round-off (a centre
///      on the border of two Voronoi regions), are merged: the nearest is kept (ties: lower
///      feature id);
///   n = (c - q) / d (unit, mesh -> centre), delta = R - d.
/// Degenerate (zero-area) triangles are skipped: their edges are also edges of their neighbours.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "ppohdem/geometry/vector.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::sdf::fast {
class TriangleTree;
}

namespace ppohdem::dem {

/// One contact of a sphere with a mesh (object frame).
struct MeshContact {
  Vec3 normal = Vec3::UnitZ();  ///< unit, from the mesh towards the centre: (c - q) / |c - q|
  double overlap = 0.0;         ///< delta = R - |c - q| > 0 [m]
  Vec3 point = Vec3::Zero();    ///< q, the closest point of the feature [m]
  std::uint32_t feature = 0;    ///< stable feature id (>= 1), see the file comment
};

/// Where on a triangle the closest point lies (Ericson's Voronoi regions).
enum class TriangleRegion : std::uint8_t { kInterior, kEdge, kVertex };

/// Closest point of triangle (a, b, c) to p, with its region and which edge or vertex:
/// edge k joins vertex k and vertex (k + 1) % 3; vertex k is v[k].
struct TriangleClosest {
  Vec3 point = Vec3::Zero();
  TriangleRegion region = TriangleRegion::kInterior;
  int index = 0;  ///< edge or vertex number (0..2); unused for the interior
};
TriangleClosest closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

class MeshContactGeometry {
 public:
  /// Angle [rad] below which two triangles sharing an edge are one flat face: far above the
  /// round-off of normals of float-precision STL coordinates, far below any modelled crease.
  static constexpr double kFlatAngle = 1e-6;

  /// Welds the vertices, groups the faces and builds the triangle tree. Throws InputError if
  /// the mesh has no triangle of non-zero area.
  explicit MeshContactGeometry(const TriangleMesh& mesh);
  ~MeshContactGeometry();
  MeshContactGeometry(MeshContactGeometry&&) noexcept;
  MeshContactGeometry& operator=(MeshContactGeometry&&) noexcept;

  /// The contacts of the sphere (centre [m], radius [m]), sorted by feature id, into `out`
  /// (cleared first).
  void contacts(const Vec3& centre, double radius, std::vector<MeshContact>& out) const;

  std::size_t face_count() const { return face_count_; }
  std::size_t edge_count() const { return edge_count_; }
  std::size_t vertex_count() const { return vertices_.size(); }
  std::size_t feature_count() const { return 1 + face_count_ + edge_count_ + vertices_.size(); }

 private:
  struct TriangleTopology {
    std::uint32_t vertex[3];  ///< welded vertex ids
    std::uint32_t edge[3];    ///< edge k joins vertex[k] and vertex[(k + 1) % 3]
    std::uint32_t face;       ///< flat face id
    Vec3 unit_normal;         ///< counter-clockwise = outward
    bool degenerate;          ///< zero area: skipped
  };
  std::uint32_t feature_of_edge(std::uint32_t edge) const;
  std::uint32_t feature_of_vertex(std::uint32_t vertex) const;

  std::vector<Vec3> vertices_;
  std::vector<TriangleTopology> triangles_;
  std::vector<std::uint32_t> edge_first_, edge_triangles_;      ///< CSR: triangles around each edge
  std::vector<std::uint32_t> vertex_first_, vertex_triangles_;  ///< CSR: triangles around each vertex
  std::vector<std::int64_t> edge_face_;    ///< the face an edge lies inside, or -1 (a feature)
  std::vector<std::int64_t> vertex_face_;  ///< the face a vertex lies inside, or -1 (a feature)
  std::size_t face_count_ = 0;
  std::size_t edge_count_ = 0;
  double coordinate_scale_ = 0.0;  ///< largest |coordinate| of the mesh [m]
  std::unique_ptr<sdf::fast::TriangleTree> tree_;
};

}  // namespace ppohdem::dem
