// The README's quickstart runs as written: its system file (the TOML block after
// "# my_system.toml") through hbf frf, hbf modes and hbf timeint, and the FRF's peak against
// time integration at the peak's frequency; and the release's one version number everywhere.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>

#include "cli_support.hpp"
#include "hbf/version.hpp"
#include "support.hpp"

namespace readme_quickstart {

/// The lines of README.md from the one that starts `first` to the end of its code block.
std::string block_starting(const std::string& first) {
    std::ifstream in(std::string(HBF_SOURCE_DIR) + "/README.md");
    std::string line, out;
    bool inside = false;
    while (std::getline(in, line)) {
        if (!inside && line.rfind(first, 0) == 0) inside = true;
        if (inside && line.rfind("```", 0) == 0) break;
        if (inside) out += line + "\n";
    }
    return out;
}

}  // namespace readme_quickstart

TEST_CASE("The README's quickstart system runs as written: hbf frf, modes and timeint complete, the FRF's peak "
          "equals time integration there",
          "[cli][readme]") {
    using namespace hbf::test;
    const std::string toml = readme_quickstart::block_starting("# my_system.toml");
    REQUIRE(toml.find("[structure]") != std::string::npos);
    TempDir dir;
    const fs::path file = dir.path / "my_system.toml";
    write_file(file, toml);
    const std::string config = " --config '" + file.string() + "'";
    const Result frf = run_hbf("frf" + config + " --quiet", dir);
    INFO(frf.err);
    REQUIRE(frf.exit_code == 0);
    const auto rows = parse_csv(frf.out);
    REQUIRE(rows.size() > 20);
    // the largest y1_max of the branch and its frequency
    double peak = 0.0, peak_w = 0.0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double y = column(rows, rows[k], "y1_max");
        if (y > peak) {
            peak = y;
            peak_w = column(rows, rows[k], "w");
        }
    }
    const Result ti = run_hbf("timeint" + config + " --quiet --w " + std::to_string(peak_w), dir);
    INFO(ti.err);
    REQUIRE(ti.exit_code == 0);
    const auto ti_rows = parse_csv(ti.out);
    REQUIRE(ti_rows.size() == 2);
    // harmonic balance at the file's default H against the integrated steady state (the peak is
    // single-valued: the Jenkins contact slips there, no fold)
    CHECK(relative_difference(column(ti_rows, ti_rows[1], "y1_max"), peak) <= 1e-3);
    const Result modes = run_hbf("modes" + config + " --quiet --amin 1e-3 --amax 1", dir);
    INFO(modes.err);
    CHECK(modes.exit_code == 0);
}

namespace readme_quickstart {

std::string slurp_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace readme_quickstart

TEST_CASE("One version everywhere: the header, the library, hbf --version, the CMake package, CITATION.cff and "
          "the changelog's latest release",
          "[cli][readme]") {
    using namespace hbf::test;
    const std::string v = hbf::version();
    CHECK(v == HBF_VERSION_STRING);
    CHECK(v == std::to_string(HBF_VERSION_MAJOR) + "." + std::to_string(HBF_VERSION_MINOR) + "." +
                   std::to_string(HBF_VERSION_PATCH));
    CHECK(v != "0.0.0");
    TempDir dir;
    const Result r = run_hbf("--version", dir);
    CHECK(r.exit_code == 0);
    CHECK(r.out == "hbf " + v + "\n");
    const std::string package = readme_quickstart::slurp_file(std::string(HBF_BINARY_DIR) + "/hbfrictionConfigVersion.cmake");
    CHECK_THAT(package, Catch::Contains("set(PACKAGE_VERSION \"" + v + "\")"));
    const std::string citation = readme_quickstart::slurp_file(std::string(HBF_SOURCE_DIR) + "/CITATION.cff");
    CHECK_THAT(citation, Catch::Contains("\nversion: " + v + "\n"));
    // the first release heading of the changelog (after [Unreleased]) is this version
    const std::string changelog = readme_quickstart::slurp_file(std::string(HBF_SOURCE_DIR) + "/CHANGELOG.md");
    const std::size_t unreleased = changelog.find("## [Unreleased]");
    REQUIRE(unreleased != std::string::npos);
    const std::size_t next = changelog.find("## [", unreleased + 1);
    REQUIRE(next != std::string::npos);
    CHECK(changelog.substr(next, 4 + v.size() + 1) == "## [" + v + "]");
}
