// hbf — command-line front end of hbfriction. Thin: parse, validate, call the library, write
// (program.cpp).
#include "commands.hpp"
#include "hbf/diagnostics.hpp"
#include "hbf/memory.hpp"

int main(int argc, char** argv) {
    // Large blocks (Ceres' per-solve Jacobian and normal matrix: 300 KB at H = 49) stay in the
    // heap for reuse instead of being faulted in afresh on every correction (memory.hpp).
    hbf::retain_freed_memory();
    // Ceres' (glog's) and CVODE's warnings are counted and summarised, never dumped.
    hbf::capture_library_messages();
    return hbf::cli::run_program(argc, argv);
}
