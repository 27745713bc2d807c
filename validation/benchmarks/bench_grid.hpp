#pragma once
/// \file bench_grid.hpp
/// The benchmark's grid, shared by every program it runs (ours, CGAL, OpenVDB): n nodes per
/// axis, the same spacing h on every axis, spanning a cube centred on the mesh's bounding box
/// with side 1.1 x its largest extent (5 % margin on each side of the longest axis).
/// Fields are exchanged as raw little-endian doubles, x fastest (GridSpec::index order).
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ppohdem/grid/grid_spec.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::bench {

/// The cube's corners (lo, hi): what `ppohdem voxelize --box` takes for the same grid.
inline std::pair<Vec3, Vec3> benchmark_box(const TriangleMesh& mesh) {
  const BoundingBox box = bounding_box(mesh);
  const double half = 0.55 * box.extent().maxCoeff();
  const Vec3 c = box.centre();
  return {c - Vec3::Constant(half), c + Vec3::Constant(half)};
}

inline GridSpec benchmark_grid(const TriangleMesh& mesh, int n) {
  const auto [lo, hi] = benchmark_box(mesh);
  return GridSpec::spanning(lo, hi, {n, n, n});
}

inline void write_raw(const std::string& path, const std::vector<double>& values) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) throw std::runtime_error("cannot write " + path);
  const std::size_t written = std::fwrite(values.data(), sizeof(double), values.size(), f);
  std::fclose(f);
  if (written != values.size()) throw std::runtime_error("short write to " + path);
}

inline std::vector<double> read_raw(const std::string& path, std::size_t count) {
  std::vector<double> values(count);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw std::runtime_error("cannot read " + path);
  const std::size_t read = std::fread(values.data(), sizeof(double), count, f);
  std::fclose(f);
  if (read != count) throw std::runtime_error(path + ": expected " + std::to_string(count) + " doubles");
  return values;
}

}  // namespace ppohdem::bench
