// Benchmark: how the cost of one FRF grows with the model (issue 12). A finite-element-like
// chain of N masses (a fixed-free bar of unit total mass and stiffness: masses 1/N, springs N,
// so that its first mode stays at w1 = pi/2 whatever N), stiffness-proportional damping of 1 %
// at w1, the force cos(w t) at the free end, and 1 to 4 exact Coulomb contacts to the ground
// near the free end (friction limits 0.5, 0.4, 0.3, 0.2: stick-slip across the resonance).
// Each case is one `hbf frf`-like continuation over w in [1.0, 2.2] at H harmonics, in a
// child process so that its peak memory (ru_maxrss) is its own.
//
// Printed per case: N, contacts, H, the formulation (condensed with the direct sparse solve;
// modal, condensed with --modes M modes; full where it still runs), unknowns, branch points,
// seconds per FRF and per point, peak memory, the ratio full / condensed in time, and the time
// per point against the same formulation at the smallest N (the goal: < 2 at 1000
// DOFs). The last line is one JSON object with every case.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "chain.hpp"
#include "child_process.hpp"
#include "hbf/continuation.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/post_processing.hpp"

using namespace hbf;

namespace {

using bench::chain;

struct Case {
    int dofs = 0, contacts = 1, harmonics = 10;
    Formulation formulation = Formulation::condensed;
    int modes = 0;  ///< condensed with the modal receptance (0: direct sparse LU)
};

struct Result {
    bool ran = false;
    std::string status;
    int unknowns = 0, points = 0;
    double seconds = 0, peak_mb = 0;
};

/// Runs the case in a child process; its peak resident memory is measured by wait4.
Result run(const Case& c) {
    const bench::ChildResult child = bench::run_in_child([&] {
        std::ostringstream line;
        try {
            HarmonicBalance hb(chain(c.dofs, c.contacts), HarmonicBalanceOptions{c.harmonics, 0, c.formulation, c.modes});
            ContinuationOptions o;
            o.omega_start = 1.0;
            o.omega_end = 2.2;
            const BranchResult b = continue_branch(hb, o);
            line << to_string(b.status) << ' ' << hb.unknowns() << ' ' << b.points.size() << ' ' << b.seconds;
        } catch (const std::exception& e) {
            line << "error 0 0 0";
        }
        return line.str();
    });
    Result r;
    std::istringstream in(child.text);
    r.ran = static_cast<bool>(in >> r.status >> r.unknowns >> r.points >> r.seconds);
    r.peak_mb = child.peak_mb;
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"hb_scaling: time and memory of one FRF against the model size (condensed vs full harmonic balance)"};
    std::vector<int> sizes = {10, 30, 100, 300, 1000, 3000, 10000};
    std::vector<int> contact_counts = {1, 4};
    std::vector<int> harmonics = {10, 20};
    int full_limit = 100;
    int modes = 20;
    app.add_option("--dofs", sizes, "chain sizes N");
    app.add_option("--contacts", contact_counts, "numbers of contacts (1..4)")->check(CLI::Range(1, 4));
    app.add_option("--harmonics", harmonics, "H values");
    app.add_option("--full-limit", full_limit, "largest N also run with the full (dense all-DOF) formulation");
    app.add_option("--modes", modes, "modes of the modal receptance variant (condensed, --modes M; 0: not run)");
    CLI11_PARSE(app, argc, argv);

    nlohmann::json cases = nlohmann::json::array();
    std::printf("%7s %3s %3s %-9s %8s %6s %10s %12s %9s %10s %9s  %s\n", "N", "n_c", "H", "form", "unknowns", "points",
                "s/FRF", "ms/point", "peak MB", "full/cond", "vs first", "status");
    for (int h : harmonics)
        for (int nc : contact_counts) {
            std::map<std::string, double> first_per_point;  // per form: ms/point at the smallest N
            for (int n : sizes) {
                if (nc * std::max(1, n / 10) >= n) continue;  // contacts must fit near the end
                Result condensed;
                for (const std::string form : {"condensed", "modal", "full"}) {
                    const Formulation f = form == "full" ? Formulation::full : Formulation::condensed;
                    if (f == Formulation::full && n > full_limit) continue;
                    if (form == "modal" && modes <= 0) continue;
                    const Result r = run({n, nc, h, f, form == "modal" ? modes : 0});
                    if (form == "condensed") condensed = r;
                    const double ratio = f == Formulation::full && r.ran && condensed.ran && condensed.seconds > 0
                                             ? r.seconds / condensed.seconds
                                             : NAN;
                    const double per_point = r.points > 0 ? r.seconds / r.points : NAN;
                    if (!first_per_point.count(form) && std::isfinite(per_point)) first_per_point[form] = per_point;
                    const double growth = first_per_point.count(form) ? per_point / first_per_point[form] : NAN;
                    std::printf("%7d %3d %3d %-9s %8d %6d %10.3f %12.3f %9.1f %10s %9.2f  %s\n", n, nc, h,
                                form.c_str(), r.unknowns, r.points, r.seconds, 1e3 * per_point, r.peak_mb,
                                std::isfinite(ratio) ? std::to_string(ratio).substr(0, 6).c_str() : "-", growth,
                                r.ran ? r.status.c_str() : "failed");
                    std::fflush(stdout);
                    cases.push_back({{"dofs", n},
                                     {"contacts", nc},
                                     {"harmonics", h},
                                     {"formulation", form},
                                     {"modes", form == "modal" ? modes : 0},
                                     {"time_per_point_vs_smallest_n", growth},
                                     {"unknowns", r.unknowns},
                                     {"points", r.points},
                                     {"seconds", r.seconds},
                                     {"seconds_per_point", r.points > 0 ? r.seconds / r.points : 0.0},
                                     {"peak_mb", r.peak_mb},
                                     {"status", r.ran ? r.status : "failed"}});
                }
            }
        }
    std::cout << nlohmann::json{{"benchmark", "hb_scaling"}, {"cases", cases}}.dump() << '\n';
    return 0;
}
