/// \file tree_bound_test.cpp
/// The BVH's node lower bound (oriented box, TriangleTree::lower_bound_squared) against
/// an independent oracle: the reference's point-triangle distance, minimized by brute force over
/// the node's triangles. The exact query prunes a node when sqrt(bound) > sqrt(best) + slack, so
/// the bound may never exceed the true minimum by more than slack() (the pruning's own margin).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/reference/closest_point_triangle.hpp"
#include "ppohdem/sdf/fast/nearest_triangle.hpp"
#include "test_paths.hpp"

namespace ppohdem::sdf {
namespace {

/// Triangles [first, end) of the subtree rooted at `id` (depth-first order: contiguous).
std::pair<std::uint32_t, std::uint32_t> subtree_range(const fast::TriangleTree& tree, std::uint32_t id) {
  const auto& nodes = tree.nodes();
  std::uint32_t left = id, right = id;
  while (nodes[left].count == 0) left = left + 1;
  while (nodes[right].count == 0) right = nodes[right].first;
  return {nodes[left].first, nodes[right].first + nodes[right].count};
}

/// `min_tighter_share`: the share of (point, node) pairs whose bound must beat the node's
/// axis-aligned box (0 for a mesh whose faces are all axis-aligned).
void expect_bound_below_brute_force(const char* name, double offset, double min_tighter_share) {
  TriangleMesh mesh = read_stl(test::fixture(std::string("meshes/") + name));
  for (Triangle& t : mesh.triangles) {
    for (Vec3& v : t.v) v += Vec3::Constant(offset);
  }
  const BoundingBox box = bounding_box(mesh);
  const Vec3 centre = 0.5 * (box.min + box.max);
  const Vec3 half = box.max - box.min;  // points up to one box size beyond the mesh
  const double coordinate_scale = (box.max.cwiseAbs().cwiseMax(box.min.cwiseAbs()) + half).maxCoeff();
  const fast::TriangleTree tree(mesh, coordinate_scale);
  ASSERT_EQ(tree.oriented_nodes().size(), tree.nodes().size());
  const fast::TriangleTree aligned_tree(mesh, coordinate_scale, /*oriented_boxes=*/false);
  const auto& triangles = tree.triangles();
  const auto& nodes = tree.nodes();
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(triangles.size() - 1));
  int tighter = 0, checked = 0;
  for (int q = 0; q < 300; ++q) {
    // Half the points anywhere around the mesh, half just off a random triangle (where the
    // slabs of nearly flat clusters are tightest and a wrong bound would show first).
    Vec3 p = centre + Vec3(unit(rng) * half.x(), unit(rng) * half.y(), unit(rng) * half.z());
    if (q % 2 == 1) {
      const auto& t = triangles[pick(rng)];
      const double scale = std::sqrt(t.ab.cross(t.ac).norm());
      p = t.a + 0.3 * t.ab + 0.3 * t.ac + 0.5 * scale * Vec3(unit(rng), unit(rng), unit(rng));
    }
    // End to end (the query reads the children's boxes from ChildPair copies): the pruned
    // query returns exactly the minimum of the computed distances over all triangles, with or
    // without oriented boxes, whatever the hint.
    double all = std::numeric_limits<double>::infinity();
    for (const auto& t : triangles) all = std::min(all, fast::squared_distance(p, t));
    ASSERT_EQ(tree.nearest(p).squared_distance, all) << name;
    ASSERT_EQ(tree.nearest(p, pick(rng)).squared_distance, all) << name;
    ASSERT_EQ(aligned_tree.nearest(p, pick(rng)).squared_distance, all) << name;
    // Packets (TriangleTree::nearest_packet): 4 x 4 neighbours of p (as the grid rows are
    // queried) and, from the packets of 3 points on, one point anywhere (paths that part early);
    // each point's result must be its brute-force minimum and the lowest index among equally
    // near triangles (the tie rule of every traversal), with AVX-512 (16 points per traversal in
    // two registers from 9 points on, 8 in one), AVX (4) and SSE2 (2 lanes), whatever the hints
    // and the packet's size.
    const double step = 0.02 * half.norm();
    constexpr int kPacket = fast::TriangleTree::kPacket;
    static_assert(kPacket == 16);
    Vec3 points[kPacket];
    for (int c = 0; c < kPacket; ++c) {
      points[c] = p + Vec3(0.0, step * (c % 2 + 2 * ((c / 4) % 2)), step * ((c / 2) % 2 + 2 * (c / 8)));
    }
    points[2] = centre + Vec3(unit(rng) * half.x(), unit(rng) * half.y(), unit(rng) * half.z());
    if (q % 4 == 1) points[6] = centre + Vec3(unit(rng) * half.x(), unit(rng) * half.y(), unit(rng) * half.z());
    if (q % 4 == 3) points[13] = centre + Vec3(unit(rng) * half.x(), unit(rng) * half.y(), unit(rng) * half.z());
    std::pair<double, std::uint32_t> expected[kPacket];
    for (int c = 0; c < kPacket; ++c) {
      expected[c] = {std::numeric_limits<double>::infinity(), 0};
      for (std::uint32_t s = 0; s < triangles.size(); ++s) {
        const double d2 = fast::squared_distance(points[c], triangles[s]);
        if (d2 < expected[c].first) expected[c] = {d2, s};
      }
    }
    using Simd = fast::TriangleTree::PacketSimd;
    for (int count = 1; count <= kPacket; ++count) {
      for (const Simd simd : {Simd::best, Simd::avx512, Simd::avx, Simd::sse2}) {
        std::int64_t hints[kPacket];
        for (std::int64_t& h : hints) h = q % 3 == 0 ? -1 : static_cast<std::int64_t>(pick(rng));
        fast::TriangleTree::Nearest found[kPacket];
        tree.nearest_packet(points, hints, count, found, simd);
        for (int c = 0; c < count; ++c) {
          ASSERT_EQ(found[c].squared_distance, expected[c].first)
              << name << " packet " << count << " point " << c << " simd " << static_cast<int>(simd);
          ASSERT_EQ(found[c].triangle, expected[c].second)
              << name << " packet " << count << " point " << c << " simd " << static_cast<int>(simd);
        }
      }
    }
    for (std::uint32_t id = 0; id < nodes.size(); ++id) {
      const auto [first, end] = subtree_range(tree, id);
      double brute = std::numeric_limits<double>::infinity();
      for (std::uint32_t s = first; s < end; ++s) {
        const auto& t = triangles[s];
        brute = std::min(brute, sdf::reference::squared_distance_to_triangle(p, t.a, t.b, t.c));
      }
      const double bound = fast::TriangleTree::lower_bound_squared(tree.oriented_nodes()[id], p);
      ASSERT_LE(std::sqrt(bound), std::sqrt(brute) + tree.slack())
          << name << " node " << id << " point " << p.transpose();
      const auto& n = nodes[id];
      double box_d2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double g = std::max({n.lo[a] - p[a], p[a] - n.hi[a], 0.0});
        box_d2 += g * g;
      }
      tighter += bound > box_d2;
      ++checked;
    }
  }
  // The oriented boxes must do something: most (point, node) pairs are far apart and both bounds
  // are loose there, but on curved meshes a clear share of the bounds beat the axis-aligned box.
  EXPECT_GE(tighter, min_tighter_share * checked) << name;
}

TEST(FastSdfTree, NodeLowerBoundNeverExceedsBruteForceDistance) {
  expect_bound_below_brute_force("fandisk.stl", 0.0, 0.01);
  expect_bound_below_brute_force("icosphere.stl", 0.0, 0.01);
  expect_bound_below_brute_force("box.stl", 0.0, 0.0);
}

TEST(FastSdfTree, PacketInstructionSetsOfThisCpu) {
  // The checks above run every requested instruction set, but one the CPU lacks falls back to the
  // next narrower: say which were really exercised here.
  using Simd = fast::TriangleTree::PacketSimd;
  const Simd available = fast::TriangleTree::packet_simd_available();
  const char* name = available == Simd::avx512 ? "AVX-512, AVX, SSE2" : available == Simd::avx ? "AVX, SSE2" : "SSE2";
  std::printf("packet traversals exercised on this CPU: %s\n", name);
  RecordProperty("packet_simd", name);
  EXPECT_NE(available, Simd::best);
}

TEST(FastSdfTree, NodeLowerBoundHoldsForAMeshOffsetByAMillion) {
  // Large coordinates: the slab's axis.p rounds at 1e6 eps; the slack (1e-12 x 1e6) covers it.
  expect_bound_below_brute_force("fandisk.stl", 1e6, 0.01);
}

}  // namespace
}  // namespace ppohdem::sdf
