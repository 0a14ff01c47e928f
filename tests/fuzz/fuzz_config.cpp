// Fuzz target: the TOML system reader, hbf::io::read_system_config (src/input/config.cpp).
//
// The input is a system file: it is written to one file in a private temporary directory
// (the same file every run) beside copies of the shipped .mtx files, so that the relative
// Matrix Market names of the seeds (examples/systems) resolve. The only expected failure is
// hbf::InvalidInput, the reader's documented refusal; anything else (another exception, a
// crash, a sanitizer report, a timeout, too much memory) is a finding.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    hbf_fuzz::copy_example_matrices();
    hbf_fuzz::silence_iostreams();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = hbf_fuzz::write_input("system.toml", data, 0);
    hbf_fuzz::write_input("system.toml", data, size);
    try {
        const hbf::io::SystemConfig config = hbf::io::read_system_config(path);
        // Accepted: the reader's promises (config.hpp) hold.
        const auto n = config.system.dofs();
        if (n < 1 || config.system.stiffness.rows() != n || config.system.damping.rows() != n ||
            config.system.excitation.size() != n || config.outputs.empty())
            hbf_fuzz::die("read_system_config accepted an inconsistent system");
    } catch (const hbf::InvalidInput&) {
        // the documented refusal
    }
    return 0;
}
