/// \file openvdb_sdf_main.cpp
/// ppohdem-openvdb-sdf: the peer OpenVDB builds, on the benchmark's grid (bench_grid.hpp).
///
///   ppohdem-openvdb-sdf --mesh M.stl --n N --band B|whole [--threads T] [--out field.f64]
///
/// openvdb::tools::meshToVolume<FloatGrid> with the QuadAndTriangleDataAdapter, whose points are
/// in INDEX space: p_index = (x - origin) / h, so voxel (i, j, k)'s centre is our node (i, j, k)
/// (OpenVDB puts voxel centres on integer index coordinates). The transform is linear with voxel
/// size h, so values come out in world units. --band B sets the exterior and interior band
/// widths to B voxels; "whole" sets both to sqrt(3) N voxels, which covers the grid. Nodes
/// outside the active band get the background (+-B h, sign by OpenVDB's inside flood fill).
/// Notes from OpenVDB's documentation: "Requires a closed surface but not necessarily a
/// manifold surface"; values are float32. Threads: TBB limited by tbb::global_control.
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <string>

#include "../../benchmarks/bench_grid.hpp"
#include "ppohdem/mesh/stl_io.hpp"
#include "ppohdem/sdf/fast/fast_sdf_builder.hpp"

int main(int argc, char** argv) {
  try {
    std::map<std::string, std::string> args;
    for (int a = 1; a + 1 < argc; a += 2) args[argv[a] + 2] = argv[a + 1];
    const ppohdem::TriangleMesh mesh = ppohdem::read_stl(args.at("mesh"));
    const int n = std::stoi(args.at("n"));
    const ppohdem::GridSpec grid = ppohdem::bench::benchmark_grid(mesh, n);
    const int threads = args.count("threads") ? std::stoi(args.at("threads")) : 2;
    const std::string band_arg = args.at("band");
    const float band = band_arg == "whole" ? static_cast<float>(std::sqrt(3.0) * n) : std::stof(band_arg);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    openvdb::initialize();

    const double h = grid.spacing.x();
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    points.reserve(3 * mesh.size());
    for (const auto& t : mesh.triangles) {
      const auto first = static_cast<openvdb::Index32>(points.size());
      for (const auto& v : t.v) {
        const ppohdem::Vec3 p = (v - grid.origin) / h;
        points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
      }
      triangles.emplace_back(first, first + 1, first + 2);
    }
    const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points, triangles);
    const openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(h);
    const openvdb::FloatGrid::Ptr vdb =
        openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *transform, band, band);
    const double build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::vector<double> values(grid.node_count());
    auto accessor = vdb->getConstAccessor();
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) values[grid.index(i, j, k)] = accessor.getValue(openvdb::Coord(i, j, k));
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (args.count("out")) ppohdem::bench::write_raw(args.at("out"), values);
    std::printf("method=openvdb-%s n=%d threads=%d precision=float triangles=%zu nodes=%zu seconds=%.6f "
                "nodes_per_second=%.6g peak_rss_bytes=%zu field_bytes=%zu build_seconds=%.6f active_voxels=%llu\n",
                band_arg.c_str(), n, threads, mesh.size(), grid.node_count(), seconds,
                static_cast<double>(grid.node_count()) / seconds, ppohdem::peak_resident_bytes(),
                static_cast<std::size_t>(vdb->memUsage()), build_seconds,
                static_cast<unsigned long long>(vdb->activeVoxelCount()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ppohdem-openvdb-sdf: error: %s\n", e.what());
    return 1;
  }
}
