#pragma once
// The Python Field: a shared ScalarField (views keep the Python object, hence it, alive).
#include <memory>
#include <string>

#include "ppohdem/grid/scalar_field.hpp"
#include "ppohdem/sdf/signed_distance.hpp"

namespace ppohdem::python {

struct PyField {
  std::shared_ptr<ScalarField> field;
  SdfReport report;
  std::string method;
  int threads = 0;  // of the build; the VTK title records it as `ppohdem voxelize` does
};

}  // namespace ppohdem::python
