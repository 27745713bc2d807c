#pragma once
// Helpers shared by the mesh tests: capture an InputError, build meshes and binary STL bytes
// independently of the code under test.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "ppohdem/error.hpp"
#include "ppohdem/mesh/triangle_mesh.hpp"

namespace ppohdem::test {

/// The InputError `action` throws; records a test failure if it throws nothing.
inline InputError capture_input_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError, none was thrown";
  return InputError("(no error)");
}

inline Triangle make_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  Triangle t;
  t.v = {a, b, c};
  return t;
}

/// Unit cube [0,1]^3, 12 triangles, counter-clockwise seen from outside (outward normals).
inline TriangleMesh unit_cube() {
  // corner index = x + 2y + 4z
  auto p = [](int i) { return Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1); };
  // each face as a quad (a, b, c, d) counter-clockwise from outside -> (a,b,c), (a,c,d)
  const int quads[6][4] = {{0, 2, 3, 1},   // z = 0, normal -z
                           {4, 5, 7, 6},   // z = 1, normal +z
                           {0, 1, 5, 4},   // y = 0, normal -y
                           {2, 6, 7, 3},   // y = 1, normal +y
                           {0, 4, 6, 2},   // x = 0, normal -x
                           {1, 3, 7, 5}};  // x = 1, normal +x
  TriangleMesh mesh;
  for (const auto& q : quads) {
    mesh.triangles.push_back(make_triangle(p(q[0]), p(q[1]), p(q[2])));
    mesh.triangles.push_back(make_triangle(p(q[0]), p(q[2]), p(q[3])));
  }
  return mesh;
}

/// Binary STL bytes written field by field (independent of write_stl). Host must be
/// little-endian, as the format is.
inline std::string binary_stl_bytes(const std::vector<std::array<float, 12>>& records,
                                    const std::string& header_text = "test",
                                    std::uint32_t count_override = UINT32_MAX) {
  static_assert(std::endian::native == std::endian::little);
  std::string bytes(80, '\0');
  std::memcpy(bytes.data(), header_text.data(), std::min<std::size_t>(80, header_text.size()));
  const std::uint32_t count =
      count_override == UINT32_MAX ? static_cast<std::uint32_t>(records.size()) : count_override;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& r : records) {
    bytes.append(reinterpret_cast<const char*>(r.data()), 48);
    bytes.append(2, '\0');
  }
  return bytes;
}

}  // namespace ppohdem::test
