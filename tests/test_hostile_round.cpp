// What a hostile user found in modes, track, interfaces and reduction, each case against an
// independent reference (a closed form, the unreduced model, time integration) or its expected
// exit code and message. The CLI cases that only check an exit code, a message and the files
// are in hostile_inputs.sh.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"

namespace {
using hbf::test::run_hbf;
using hbf::test::TempDir;

/// A 3-DOF chain with two contacts of the given laws (between m1 and m2, m3 to the ground).
std::string two_contacts(const std::string& first, const std::string& second) {
    return "[structure]\nmass = [1.0, 0.5, 0.25]\n"
           "stiffness = [[3.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]\n"
           "excitation = [1.0, 0.0, 0.0]\n"
           "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"" + first + "\"\nfriction_limit = 0.3\n" +
           (first == "coulomb-reg" ? "regularization = 0.05\n" : "") +
           "[[contact]]\ndof = 3\nlaw = \"" + second + "\"\nfriction_limit = 0.1\n" +
           (second == "coulomb-reg" ? "regularization = 0.05\n" : "") + "[frequency]\nwmin = 0.5\nwmax = 0.6\n";
}
}  // namespace

TEST_CASE("The law names of a system's contacts are listed once each, in order (no substring match)",
          "[hostile][cli]") {
    TempDir dir;
    for (const auto& [a, b] : {std::pair<std::string, std::string>{"coulomb-reg", "coulomb"}, {"coulomb", "coulomb-reg"},
                               {"coulomb", "coulomb"}}) {
        hbf::test::write_file(dir.path / "s.toml", two_contacts(a, b));
        const auto r = run_hbf("frf --config '" + (dir.path / "s.toml").string() + "' --exact off --harmonics 3 --quiet --out /dev/null --summary '" +
                                   (dir.path / "s.json").string() + "'",
                               dir);
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        const auto j = nlohmann::json::parse(hbf::test::slurp(dir.path / "s.json"));
        CHECK(j["parameters"]["law"] == (a == b ? a : a + "," + b));
    }
}
