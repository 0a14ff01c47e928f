// Benchmarks: a state vector as text, one number a line (the starts and orbits saved between runs).
#pragma once

#include <Eigen/Dense>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hbf::bench {

/// The numbers of `file`, lines starting with '#' skipped (the saved orbits under tests/data
/// carry a header); `flag` names it in the error.
inline Eigen::VectorXd read_state(const std::string& flag, const std::string& file) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error(flag + " " + file + ": cannot be read");
    std::vector<double> values;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        try {
            values.push_back(std::stod(line));
        } catch (const std::exception&) {
            throw std::runtime_error(flag + " " + file + ": not a number: " + line);
        }
    }
    if (values.empty()) throw std::runtime_error(flag + " " + file + ": no numbers read");
    return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

/// `state` into `file`, 17 digits a number; `flag` names it in the error.
inline void write_state(const std::string& flag, const std::string& file, const Eigen::VectorXd& state) {
    std::FILE* out = std::fopen(file.c_str(), "w");
    if (!out) throw std::runtime_error(flag + " " + file + ": cannot be written");
    for (double v : state) std::fprintf(out, "%.17g\n", v);
    std::fclose(out);
}

}  // namespace hbf::bench
