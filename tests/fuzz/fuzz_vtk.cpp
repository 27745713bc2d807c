// libFuzzer target: legacy VTK STRUCTURED_POINTS (read_vtk_structured_points_bytes).
#include <string>

#include "fuzz_support.hpp"
#include "ppohdem/io/vtk_structured_points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ppohdem;
  fuzz::run_reader([&] {
    std::string array_name;
    const ScalarField field = read_vtk_structured_points_bytes(fuzz::as_text(data, size), "fuzz.vtk", &array_name);
    field.grid.validate("fuzz.vtk");  // an accepted grid is a valid grid (throws InputError if not)
    // The node count is the true product of DIMENSIONS (not wrapped around in size_t).
    PPOHDEM_FUZZ_CHECK(checked_node_count(field.grid.nodes).has_value());
    PPOHDEM_FUZZ_CHECK(field.values.size() == field.grid.node_count());
    PPOHDEM_FUZZ_CHECK(!array_name.empty());
  });
  return 0;
}
