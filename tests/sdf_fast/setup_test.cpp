/// \file setup_test.cpp
/// The fast builder's setup, made parallel and cheaper for small grids (docs/performance.md
/// "The whole voxelize process"), against independent oracles:
///  - the BVH built as OpenMP tasks against the same constructor run serially, node for node
///    and bit for bit (the claim in TriangleTree's constructor);
///  - the sign's edge census (open-addressing weld, counting sort of edge uses) against
///    compute_mesh_stats() (a std::unordered_map weld and a std::sort of the edges, written
///    separately in core/src/mesh/mesh_stats.cpp), on the fixtures and on a fan whose centre is
///    used by more edges than the census's small per-vertex sort takes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <string>

#include "ppohdem/mesh/mesh_stats.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/fast/column_sign.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"
#include "test_paths.hpp"

#if defined(PPOHDEM_WITH_OPENMP)
#include <omp.h>
#endif

namespace ppohdem::sdf {
namespace {

template <class T>
bool same_bytes(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

void expect_same_tree(const fast::TriangleTree& serial, const fast::TriangleTree& tasks) {
  ASSERT_EQ(serial.nodes().size(), tasks.nodes().size());
  ASSERT_EQ(serial.oriented_nodes().size(), tasks.oriented_nodes().size());
  ASSERT_EQ(serial.triangles().size(), tasks.triangles().size());
  for (std::size_t i = 0; i < serial.nodes().size(); ++i) {
    ASSERT_TRUE(same_bytes(serial.nodes()[i], tasks.nodes()[i])) << "node " << i;
  }
  for (std::size_t i = 0; i < serial.oriented_nodes().size(); ++i) {
    ASSERT_TRUE(same_bytes(serial.oriented_nodes()[i], tasks.oriented_nodes()[i])) << "oriented node " << i;
  }
  for (std::size_t t = 0; t < serial.triangles().size(); ++t) {
    const auto& a = serial.triangles()[t];
    const auto& b = tasks.triangles()[t];
    ASSERT_EQ(a.original_index, b.original_index) << "triangle " << t;
    ASSERT_EQ(a.kind, b.kind) << "triangle " << t;
  }
}

TEST(FastSdfSetup, TreeBuiltAsTasksIsTheSerialTreeBitForBit) {
  // The dragon (100,000 triangles) is split into tasks down to subtrees of 4,096 triangles.
  const TriangleMesh mesh = read_stl(test::fixture("meshes/dragon_100k.stl"));
  for (const bool oriented : {true, false}) {
    SCOPED_TRACE(oriented ? "oriented boxes" : "axis-aligned boxes");
    const fast::TriangleTree serial(mesh, 20.0, oriented);
    std::optional<fast::TriangleTree> tasks;
#if defined(PPOHDEM_WITH_OPENMP)
    int threads = 0;
#pragma omp parallel num_threads(2)
#pragma omp single
    {
      threads = omp_get_num_threads();
      tasks.emplace(mesh, 20.0, oriented);
    }
    EXPECT_EQ(threads, 2);
#else
    tasks.emplace(mesh, 20.0, oriented);
#endif
    expect_same_tree(serial, *tasks);
  }
}

void expect_census_as_mesh_stats(const TriangleMesh& mesh) {
  const MeshStats stats = compute_mesh_stats(mesh);
  const fast::EdgeCensus census = fast::count_edges(mesh);
  EXPECT_EQ(census.welded_vertices, stats.vertices);
  EXPECT_EQ(census.boundary_edges, stats.boundary_edges);
  EXPECT_EQ(census.non_manifold_edges, stats.non_manifold_edges);
  EXPECT_EQ(census.misoriented_edges, stats.inconsistent_edges);
}

TEST(FastSdfSetup, EdgeCensusAgreesWithMeshStatsOnTheFixtures) {
  for (const std::string name : {"bunny", "bunny_closed", "dragon_100k", "fandisk", "box", "icosphere"}) {
    SCOPED_TRACE(name);
    expect_census_as_mesh_stats(read_stl(test::fixture("meshes/" + name + ".stl")));
  }
}

TEST(FastSdfSetup, EdgeCensusAgreesWithMeshStatsOnAFanWithDefects) {
  // 40 triangles around one centre (40 edge uses at the centre: the census's std::sort branch);
  // one triangle flipped (2 misoriented edges), one duplicated (3 non-manifold edges, with the
  // flipped one's), a -0.0 coordinate that must weld with +0.0, and the rim left open.
  TriangleMesh mesh;
  const int n = 40;
  const auto rim = [&](int k) {
    const double a = 2.0 * std::numbers::pi * (k % n) / n;
    return Vec3(std::cos(a), std::sin(a), 0.0);
  };
  for (int k = 0; k < n; ++k) {
    Triangle t;
    t.v = {Vec3(0.0, 0.0, k == 7 ? -0.0 : 0.0), rim(k), rim(k + 1)};
    if (k == 3) std::swap(t.v[1], t.v[2]);
    mesh.triangles.push_back(t);
  }
  mesh.triangles.push_back(mesh.triangles[10]);
  const fast::EdgeCensus census = fast::count_edges(mesh);
  EXPECT_EQ(census.welded_vertices, 41u);  // the centre and 40 rim points
  EXPECT_GT(census.boundary_edges, 0u);
  EXPECT_GT(census.non_manifold_edges, 0u);
  EXPECT_GT(census.misoriented_edges, 0u);
  expect_census_as_mesh_stats(mesh);
}

}  // namespace
}  // namespace ppohdem::sdf
