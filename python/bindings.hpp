#pragma once
// The Python module `tagbench` (pybind11): module.cpp binds the detector, families.cpp the families.
#include <pybind11/pybind11.h>

namespace tagbench::python {

void bind_families(pybind11::module_& m);

}  // namespace tagbench::python
