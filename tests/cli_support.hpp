// Helpers of the end-to-end tests: run the built `hbf` in a scratch directory, read files,
// split CSV.
#pragma once
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hbf/config.hpp"
#include "hbf/error.hpp"

// In hbf::test with the helpers of support.hpp, and reachable as test:: (the alias below): the
// test sources are compiled in unity batches, where a file's `using namespace hbf` meets
// another's `test::`.
namespace hbf::test {
namespace fs = std::filesystem;

struct Result {
    int exit_code = -1;
    std::string out, err;
};

inline std::string slurp(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream buffer;
    buffer << in.rdbuf();
    return buffer.str();
}

/// Writes `text` to `path` (replacing it).
inline void write_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
}

/// A fresh empty directory per test case, removed afterwards.
struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("hbf_cli_" + std::to_string(::getpid()) + "_" +
                                            std::to_string(reinterpret_cast<std::uintptr_t>(this)));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    bool empty() const { return fs::is_empty(path); }
};

/// Runs `hbf <args>` (args are passed through the shell, quote as needed), after `environment`
/// (e.g. "env PATH=/none") if given.
inline Result run_hbf(const std::string& args, const TempDir& dir, const std::string& environment = "") {
    const fs::path out = dir.path / "stdout.txt", err = dir.path / "stderr.txt";
    const std::string command = environment + (environment.empty() ? "" : " ") + "'" + HBF_EXECUTABLE + "' " + args + " >'" + out.string() +
                                "' 2>'" + err.string() + "' </dev/null";
    const int status = std::system(command.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
}

inline std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::string field;
        std::istringstream cells(line);
        while (std::getline(cells, field, ',')) fields.push_back(field);
        if (!line.empty() && line.back() == ',') fields.emplace_back();
        rows.push_back(fields);
    }
    return rows;
}

/// The row of the sample at frequency w (point = sample), empty when there is none.
inline std::vector<std::string> sample_row(const std::vector<std::vector<std::string>>& rows, double w) {
    const auto& header = rows.front();
    const auto point = static_cast<std::size_t>(std::find(header.begin(), header.end(), "point") - header.begin());
    for (std::size_t k = 1; k < rows.size(); ++k)
        if (rows[k][point] == "sample" && std::stod(rows[k][0]) == w) return rows[k];
    return {};
}

/// The value of column `name` (by the header) in `row`.
inline double column(const std::vector<std::vector<std::string>>& rows, const std::vector<std::string>& row,
              const std::string& name) {
    const auto& header = rows.front();
    const auto at = std::find(header.begin(), header.end(), name);
    REQUIRE(at != header.end());
    return std::stod(row[static_cast<std::size_t>(at - header.begin())]);
}

/// `hbf <args>` (a command that takes --out) is refused as bad input: exit 2, every text of
/// `expected` in the message, nothing on stdout and no output file.
inline void check_bad_input(const std::string& args, const std::vector<std::string>& expected, const TempDir& dir) {
    const fs::path out = dir.path / "refused.csv";
    const Result r = run_hbf(args + " --out '" + out.string() + "'", dir);
    INFO(args << "\n-> " << r.err);
    CHECK(r.exit_code == 2);
    for (const std::string& e : expected) CHECK_THAT(r.err, Catch::Contains(e));
    CHECK(r.out.empty());
    CHECK(!fs::exists(out));
}

/// The same for `hbf frf --config FILE` with a system file holding `text` (system.toml).
inline void check_bad_config(const std::string& text, const std::vector<std::string>& expected, const TempDir& dir) {
    const fs::path file = dir.path / "system.toml";
    write_file(file, text);
    INFO(text);
    check_bad_input("frf --config '" + file.string() + "'", expected, dir);
    fs::remove(file);
}

/// Writes `text` to `file` and expects the system-file reader to refuse it, with every part of
/// `expected` in its message.
inline void check_refused_config(const fs::path& file, const std::string& text, const std::vector<std::string>& expected) {
    write_file(file, text);
    INFO(text);
    try {
        hbf::io::read_system_config(file.string());
        FAIL("accepted");
    } catch (const hbf::InvalidInput& error) {
        for (const std::string& part : expected) CHECK_THAT(error.what(), Catch::Contains(part));
    }
}

}  // namespace hbf::test

namespace test = hbf::test;
