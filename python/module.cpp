// hbfriction._core — the C++ half of the Python bindings (pybind11).
//
// It binds the library's own types and calls (model.hpp, frf.hpp, time_integration.hpp,
// analytic.hpp, table.hpp) with their C++ names; python/hbfriction/__init__.py turns the results
// into NumPy arrays and the Branch, Solution and Table objects. No NumPy C API is used (only
// the buffer protocol and calls into the numpy module), so the module works with any NumPy.
//
// Conventions:
//  - InvalidInput (bad input) becomes ValueError with the library's message (pybind11 maps
//    std::invalid_argument); other failures RuntimeError. Non-convergence is never an
//    exception: it is a status in the result.
//  - The GIL is released during every computation (FRFs, solves, time integration, searches);
//    Python callables (optimize's system of p) are called with the GIL re-acquired.
#include "bindings.hpp"
#include "hbf/version.hpp"

using namespace hbf::python;

PYBIND11_MODULE(_core, m) {
    m.doc() = "hbfriction's C++ core (use the hbfriction package, not this module)";
    m.attr("__version__") = hbf::version();
    hbf::capture_library_messages();  // Ceres' glog output is counted (the verdicts' warnings), not printed
    bind_model(m);
    bind_options(m);
    bind_studies(m);
}
