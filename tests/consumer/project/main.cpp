// An outside project using the installed ppohdem: place a one-triangle mesh and sample a
// linear field trilinearly; exit non-zero if the library gives a wrong answer.
#include <ppohdem/grid/trilinear.hpp>
#include <ppohdem/mesh/placement.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace ppohdem;
  GridSpec grid;
  grid.nodes = {3, 3, 3};
  grid.spacing = Vec3(0.5, 0.5, 0.5);
  ScalarField f(grid);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) f.at(i, j, k) = grid.position(i, j, k).sum();
  const auto s = sample_trilinear(f, Vec3(0.3, 0.7, 0.9));
  if (!s || std::abs(s->value - 1.9) > 1e-12) return 1;
  std::puts("consumer: ppohdem::core found and working");
  return 0;
}
