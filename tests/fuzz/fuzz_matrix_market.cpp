// Fuzz target: the Matrix Market reader, hbf::io::read_matrix_market (src/input/matrix_market.cpp).
//
// The input is a .mtx file, written to one file in a private temporary directory (the same
// file every run). The only expected failure is hbf::InvalidInput; anything else (another
// exception, a crash, a sanitizer report, a timeout, too much memory) is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    hbf_fuzz::silence_iostreams();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = hbf_fuzz::write_input("matrix.mtx", data, 0);
    hbf_fuzz::write_input("matrix.mtx", data, size);
    try {
        const hbf::SparseMatrix m = hbf::io::read_matrix_market(path);
        // Accepted: the reader's promises (config.hpp) hold: a non-empty matrix of finite entries.
        if (m.rows() < 1 || m.cols() < 1) hbf_fuzz::die("read_matrix_market accepted an empty matrix");
        for (int k = 0; k < m.outerSize(); ++k)
            for (hbf::SparseMatrix::InnerIterator it(m, k); it; ++it)
                if (!std::isfinite(it.value())) hbf_fuzz::die("read_matrix_market accepted a non-finite entry");
    } catch (const hbf::InvalidInput&) {
        // the documented refusal
    }
    return 0;
}
