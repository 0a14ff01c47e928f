// Benchmark: one FRF of an elastic block whose top face of n contact nodes (law elastic:
// stick, slip, lift-off) touches a rigid wall (lattice.hpp), against n, H and the dimension
// (issue 32). Each case is one `hbf frf`-like continuation across the block's first resonance
// with the contacts stuck, in a child process so that its peak memory (ru_maxrss) is its own.
// The structure enters through the modal receptance (20 modes and the residual flexibility:
// the cost of a reduced FE model, independent of its size).
//
// Printed per case: nodes, dimension, H, the Jacobian's form (structured: I + Gr Df kept in its
// structure, Newton with preconditioned GMRES; dense: formed and solved by Ceres' dense normal
// Cholesky, run up to --dense-limit unknowns), unknowns, points, seconds per point, peak
// memory, and where the time goes per point: the contacts' AFT and their blocks, the
// receptances (G_k and dG_k/domega at each new w, the products with them), the GMRES solves,
// the preconditioner's factorisations; GMRES iterations per Newton step. The last line is one
// JSON object with every case.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "hbf/continuation.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/post_processing.hpp"
#include "lattice.hpp"

using namespace hbf;

namespace {

struct Case {
    int nodes = 10, dimension = 3, harmonics = 7;
    JacobianForm form = JacobianForm::structured;
    int modes = 20;
    double force = 0.002;  // per top node (lattice.hpp)
    bool transitions = false;  // locate every node's stick-slip transitions (hbf frf's default)
    double band = 0.3;  // w in [(1 - band) w_s, (1 + band) w_s], w_s the stuck resonance
};

struct Result {
    bool ran = false;
    std::string status;
    int unknowns = 0, points = 0;
    double seconds = 0, peak_mb = 0;
    double aft = 0, structure = 0, jacobian = 0, krylov = 0, factorization = 0, predictor = 0;
    long long iterations = 0, krylov_iterations = 0;
    std::string error;
};

/// nx x ny close to square with nx ny = nodes (3D); nx = nodes (2D).
bench::LatticeOptions lattice_for(const Case& c) {
    bench::LatticeOptions o;
    o.dimension = c.dimension;
    if (c.dimension == 2) {
        o.nx = c.nodes;
        o.ny = 1;
    } else {
        int nx = static_cast<int>(std::sqrt(static_cast<double>(c.nodes)));
        while (c.nodes % nx != 0) --nx;
        o.nx = c.nodes / nx;
        o.ny = nx;
    }
    o.force = c.force;
    return o;
}

/// The lowest eigenfrequency of the block with every contact stuck (its springs added).
double stuck_frequency(const System& s) {
    SparseMatrix k = s.stiffness;
    for (const Contact& c : s.contacts) {
        const Eigen::MatrixXd w = s.contact_directions(c);
        const double stiffness[3] = {c.stiffness, c.values.count("normal_stiffness") ? c.values.at("normal_stiffness") : 0.0,
                                     0.0};
        for (int a = 0; a < w.cols(); ++a) {
            const double ka = a + 1 == w.cols() ? stiffness[1] : stiffness[0];  // tangents, then the normal
            k += (ka * w.col(a) * w.col(a).transpose()).sparseView();
        }
    }
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(k);
    Eigen::VectorXd v = Eigen::VectorXd::Ones(k.rows());
    double lambda = 1.0;
    for (int it = 0; it < 100; ++it) {
        const Eigen::VectorXd w = ldlt.solve(v);
        lambda = v.dot(v) / v.dot(w);
        v = w / w.norm();
    }
    return std::sqrt(lambda);
}

Result run(const Case& c) {
    const bench::ChildResult child = bench::run_in_child([&] {
        std::ostringstream line;
        try {
            const System s = bench::lattice(lattice_for(c));
            const double ws = stuck_frequency(s);
            HarmonicBalanceOptions ho;
            ho.harmonics = c.harmonics;
            ho.formulation = Formulation::condensed;
            ho.modes = c.modes;
            ho.jacobian = c.form;
            HarmonicBalance hb(s, ho);
            ContinuationOptions o;
            o.omega_start = (1.0 - c.band) * ws;
            o.omega_end = (1.0 + c.band) * ws;
            o.max_amplitude = 1e6;
            o.locate_transitions = c.transitions;
            const BranchResult b = continue_branch(hb, o);
            line << to_string(b.status) << ' ' << hb.unknowns() << ' ' << b.points.size() << ' ' << b.seconds << ' '
                 << b.evaluation.aft_seconds << ' ' << b.evaluation.structure_seconds << ' '
                 << b.evaluation.jacobian_seconds << ' ' << b.corrector.krylov_seconds << ' '
                 << b.corrector.factorization_seconds << ' ' << b.predictor_seconds << ' ' << b.corrector.iterations
                 << ' ' << b.corrector.krylov_iterations;
            if (std::getenv("HBF_BENCH_VERBOSE")) std::cerr << b.summary() << " (w_s = " << ws << "; corrections " << b.corrections
                                                       << ", failed " << b.failed_corrections << ")\n";
        } catch (const std::exception& e) {
            line << "error " << e.what();
        }
        return line.str();
    });
    Result r;
    std::istringstream in(child.text);
    r.ran = static_cast<bool>(in >> r.status >> r.unknowns >> r.points >> r.seconds >> r.aft >> r.structure >>
                              r.jacobian >> r.krylov >> r.factorization >> r.predictor >> r.iterations >>
                              r.krylov_iterations);
    if (!r.ran) r.error = child.text;
    r.peak_mb = child.peak_mb;
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"interface_nodes: time per FRF point and memory against the contact nodes of an interface "
                 "(structured vs dense Jacobian)"};
    std::vector<int> nodes = {10, 50, 100, 200, 400};
    std::vector<int> harmonics = {7, 15};
    std::vector<int> dimensions = {2, 3};
    int dense_limit = 2500, modes = 20;
    double band = 0.3, force = 0.002;
    bool transitions = false;
    app.add_flag("--transitions", transitions,
                 "also locate every node's stick-slip transitions by bisection (hbf frf's default; off: the FRF's "
                 "own points, the cost of the continuation)");
    app.add_option("--force", force, "force amplitude per top node (friction limit 0.3 x 0.02 = 0.006)");
    app.add_option("--nodes", nodes, "contact nodes of the interface");
    app.add_option("--harmonics", harmonics, "H values");
    app.add_option("--dimensions", dimensions, "2 and/or 3")->check(CLI::IsMember({2, 3}));
    app.add_option("--dense-limit", dense_limit, "largest unknowns also run with the dense Jacobian (Ceres)");
    app.add_option("--modes", modes, "modes of the modal receptance");
    app.add_option("--band", band, "relative half-width of the frequency band around the stuck resonance");
    CLI11_PARSE(app, argc, argv);

    nlohmann::json cases = nlohmann::json::array();
    std::printf("%5s %2s %3s %-10s %8s %6s %9s %8s | per point [ms]: %7s %7s %7s %7s %7s %7s | %5s %6s  %s\n", "nodes",
                "d", "H", "jacobian", "unknowns", "points", "s/point", "peak MB", "AFT", "G_k", "blocks", "GMRES",
                "LU", "tangent", "newt", "gmres", "status");
    for (int h : harmonics)
        for (int d : dimensions)
            for (int n : nodes)
                for (JacobianForm form : {JacobianForm::structured, JacobianForm::dense}) {
                    const int unknowns = n * d * (2 * h + 1);
                    if (form == JacobianForm::dense && unknowns > dense_limit) continue;
                    Case c{n, d, h, form, modes, force, transitions, band};
                    const Result r = run(c);
                    const double p = r.points > 0 ? 1e3 / r.points : NAN;
                    std::printf("%5d %2d %3d %-10s %8d %6d %9.4f %8.1f | %22.2f %7.2f %7.2f %7.2f %7.2f %7.2f | %5.2f %6.1f  %s\n",
                                n, d, h, to_string(form).c_str(), unknowns, r.points,
                                r.points > 0 ? r.seconds / r.points : NAN, r.peak_mb, r.aft * p, r.structure * p,
                                r.jacobian * p, r.krylov * p, r.factorization * p, r.predictor * p,
                                r.points > 0 ? static_cast<double>(r.iterations) / r.points : NAN,
                                r.iterations > 0 ? static_cast<double>(r.krylov_iterations) / r.iterations : NAN,
                                r.ran ? r.status.c_str() : ("failed: " + r.error).c_str());
                    std::fflush(stdout);
                    cases.push_back({{"nodes", n},
                                     {"dimension", d},
                                     {"harmonics", h},
                                     {"jacobian", to_string(form)},
                                     {"unknowns", unknowns},
                                     {"points", r.points},
                                     {"seconds", r.seconds},
                                     {"seconds_per_point", r.points > 0 ? r.seconds / r.points : 0.0},
                                     {"peak_mb", r.peak_mb},
                                     {"aft_seconds", r.aft},
                                     {"structure_seconds", r.structure},
                                     {"jacobian_seconds", r.jacobian},
                                     {"krylov_seconds", r.krylov},
                                     {"factorization_seconds", r.factorization},
                                     {"predictor_seconds", r.predictor},
                                     {"newton_iterations", r.iterations},
                                     {"krylov_iterations", r.krylov_iterations},
                                     {"status", r.ran ? r.status : "failed"}});
                }
    std::cout << nlohmann::json{{"benchmark", "interface_nodes"}, {"cases", cases}}.dump() << '\n';
    return 0;
}
