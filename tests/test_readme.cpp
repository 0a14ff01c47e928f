// The README's quickstart runs as written: its system file (the TOML block after
// "# my_system.toml") through hbf frf, hbf modes and hbf timeint, and the FRF's peak against
// time integration at the peak's frequency.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>

#include "cli_support.hpp"
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
