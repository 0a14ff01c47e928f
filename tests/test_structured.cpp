// The condensed Jacobian kept in its structure (structured_jacobian.hpp, issue 32): equal to the
// dense condensed Jacobian, its bordered GMRES solve equal to a dense LU (and exact in one
// iteration where every contact sticks: the preconditioner is then the operator), Newton with
// it converging to the dense corrector's solutions, and the choices and refusals of the form.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "../benchmarks/lattice.hpp"
#include "cli_support.hpp"
#include "nodes_model.hpp"
#include "hbf/continuation.hpp"
#include "hbf/frf.hpp"
#include "hbf/error.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/structured_jacobian.hpp"
#include "studies/hb_error.hpp"

using namespace hbf;
using ::test::TempDir;
namespace fs = std::filesystem;

namespace {

/// A 3 x 2 face of a two-layer block (6 contact nodes of law elastic, 18 signals).
System small_block(double force = 0.002) {
    bench::LatticeOptions o;
    o.nx = 3;
    o.ny = 2;
    o.force = force;
    return bench::lattice(o);
}

HarmonicBalanceOptions options(int harmonics, JacobianForm form, int modes = 0) {
    HarmonicBalanceOptions o;
    o.harmonics = harmonics;
    o.formulation = Formulation::condensed;
    o.modes = modes;
    o.jacobian = form;
    return o;
}

double max_abs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

/// small_block's contacts as law unilateral's massless nodes on the elastic element's springs
/// (6 rigid 3D contacts: 18 signals and 18 multiplier signals).
System rigid_block(double force = 0.002) { return test::nodes_model(small_block(force)); }

/// small_block with a Dahl contact (a bristle state) and an exact Coulomb contact (its
/// multiplier) added on two of its DOFs.
System stateful_block() {
    System s = small_block();
    for (const char* law : {"dahl", "coulomb"}) {
        Contact c;
        c.dof = law[0] == 'd' ? 0 : 4;
        c.law = parse_friction_law(law);
        c.friction_limit = 0.01;
        c.stiffness = 1.0;
        s.contacts.push_back(c);
    }
    return s;
}

/// The solution at omega: the first point of hbf frf's start there (from the static state).
Eigen::VectorXd solution_at(HarmonicBalance& hb, double omega) {
    ContinuationOptions start;
    start.omega_start = omega;
    start.omega_end = omega * 1.001;
    const BranchResult first = continue_branch(hb, start);
    REQUIRE(first.points.size() > 0);
    REQUIRE(first.points.front().omega == omega);
    return first.points.front().x;
}

/// The largest amplitude bound over a branch's points.
double peak(HarmonicBalance& hb, const BranchResult& r) {
    double best = 0;
    for (const SolutionPoint& p : r.points) best = std::max(best, hb.amplitude_bound(p.x, p.omega));
    return best;
}

/// The FRF band of the block's first resonance, transitions not located.
ContinuationOptions band() {
    ContinuationOptions o;
    o.omega_start = 0.6;
    o.omega_end = 1.2;
    o.locate_transitions = false;
    return o;
}

}  // namespace

TEST_CASE("Structured Jacobian: S (I + Gr Df) equals the dense condensed Jacobian, stuck, slipping and open",
          "[structured]") {
    for (int modes : {0, 12}) {
        CAPTURE(modes);
        HarmonicBalance hb(small_block(), options(3, JacobianForm::structured, modes));
        REQUIRE(hb.structured());
        const double omega = 0.8;
        // The stuck linear response, enlarged: some nodes slip, some lift off, some stick.
        for (double scale : {0.01, 30.0, 300.0}) {
            CAPTURE(scale);
            Eigen::VectorXd x = scale * hb.linear_guess(omega);
            x(3) += 1e-3 * scale;  // a harmonic the linear guess leaves empty
            Eigen::VectorXd r_dense, r_structured, w_dense, w_structured;
            Eigen::MatrixXd j_dense;
            hb.evaluate(x, omega, r_dense, &j_dense, &w_dense);  // the per-pair dense assembly
            StructuredJacobian j;
            hb.evaluate(x, omega, r_structured, j, &w_structured);  // batched per harmonic
            REQUIRE(max_abs(r_structured - r_dense) <= 1e-13 * max_abs(r_dense));
            REQUIRE(max_abs(w_structured - w_dense) <= 1e-12 * max_abs(w_dense));
            const Eigen::MatrixXd j_structured = j.dense();
            REQUIRE(max_abs(j_structured - j_dense) <= 1e-12 * max_abs(j_dense));
            // abs_row_sums bounds the row sums of |dR/dX| from above.
            const Eigen::VectorXd sums = j_dense.cwiseAbs().rowwise().sum(), bound = j.abs_row_sums();
            REQUIRE((bound.array() >= sums.array() * (1.0 - 1e-12)).all());
        }
    }
}

TEST_CASE("Structured Jacobian with internal states: equal to the dense condensed Jacobian, law unilateral, "
          "a bristle and exact Coulomb",
          "[structured]") {
    for (int which : {0, 1}) {
        for (int modes : {0, 12}) {  // the modal receptance needs mass at every DOF: not the nodes
            if (which == 0 && modes > 0) continue;
            CAPTURE(which, modes);
            HarmonicBalance hb(which == 0 ? rigid_block() : stateful_block(), options(3, JacobianForm::structured, modes));
            REQUIRE(hb.structured());
            const double omega = 0.8;
            std::mt19937 rng(11);
            std::uniform_real_distribution<double> u(-1.0, 1.0);
            for (double scale : {0.01, 30.0, 300.0}) {
                CAPTURE(scale);
                // The linear guess enlarged, every unknown (multipliers and states too) perturbed:
                // samples stuck, slipping and open.
                Eigen::VectorXd x = scale * hb.linear_guess(omega);
                const double size = max_abs(x);
                for (Eigen::Index i = 0; i < x.size(); ++i) x(i) += 0.2 * size * u(rng);
                Eigen::VectorXd r_dense, r_structured, w_dense, w_structured;
                Eigen::MatrixXd j_dense;
                hb.evaluate(x, omega, r_dense, &j_dense, &w_dense);
                StructuredJacobian j;
                hb.evaluate(x, omega, r_structured, j, &w_structured);
                REQUIRE(j.states() * j.coefficients() == hb.unknowns() - j.signals() * j.coefficients());
                REQUIRE(j.states() > 0);
                REQUIRE(max_abs(r_structured - r_dense) <= 1e-13 * max_abs(r_dense));
                REQUIRE(max_abs(w_structured - w_dense) <= 1e-12 * max_abs(w_dense));
                REQUIRE(max_abs(j.dense() - j_dense) <= 1e-12 * max_abs(j_dense));
                const Eigen::VectorXd sums = j_dense.cwiseAbs().rowwise().sum(), bound = j.abs_row_sums();
                REQUIRE((bound.array() >= sums.array() * (1.0 - 1e-12)).all());
            }
        }
    }
}

TEST_CASE("Structured Jacobian: the bordered GMRES solve equals a dense LU, in three iterations at most where all stick",
          "[structured]") {
    for (int which : {0, 1}) {  // law elastic's block; its contacts as law unilateral's nodes
        CAPTURE(which);
        const double omega = 0.8;
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (bool stuck : {true, false}) {
            CAPTURE(stuck);
            // Stuck: law elastic's linear response, small; law unilateral's solution at a small
            // force (its linear guess has no multipliers: it slips). Else the solution near
            // resonance.
            HarmonicBalance hb(which == 0 ? small_block() : rigid_block(stuck ? 1e-5 : 0.002),
                               options(4, JacobianForm::structured));
            const Eigen::VectorXd x = !stuck       ? solution_at(hb, 0.92)
                                      : which == 0 ? Eigen::VectorXd(1e-3 * hb.linear_guess(omega))
                                                   : solution_at(hb, omega);
            Eigen::VectorXd r, w;
            StructuredJacobian j;
            hb.evaluate(x, omega, r, j, &w);
            const int n = j.size();
            Eigen::VectorXd c(n), b(n), rhs(n), sol;
            for (int i = 0; i < n; ++i) {
                c(i) = u(rng);
                b(i) = u(rng);
                rhs(i) = u(rng);
            }
            const double d = 0.7, rho = -0.3;
            const BlockPreconditioner p(j);
            double mu = 0;
            const KrylovReport report = solve_bordered(j, p, c, b, d, rhs, rho, sol, mu, 1e-12);
            REQUIRE(report.converged);
            Eigen::MatrixXd a(n + 1, n + 1);
            a.topLeftCorner(n, n) = j.row_scale().cwiseInverse().asDiagonal() * j.dense();  // A = S^-1 dR/dX
            a.topRightCorner(n, 1) = c;
            a.bottomLeftCorner(1, n) = b.transpose();
            a(n, n) = d;
            Eigen::VectorXd full(n + 1);
            full << rhs, rho;
            const Eigen::VectorXd reference = a.partialPivLu().solve(full);
            REQUIRE(max_abs(sol - reference.head(n)) <= 1e-9 * max_abs(reference));
            REQUIRE(std::abs(mu - reference(n)) <= 1e-9 * max_abs(reference));
            // Stuck everywhere, each contact's tangent is constant over the period: the
            // preconditioner is A itself up to the mean force's coupling of harmonic 0 (the elastic
            // law's stuck offset, law unilateral's centring rows), and GMRES needs three
            // iterations at most.
            INFO("GMRES iterations " << report.iterations);
            if (stuck) REQUIRE(report.iterations <= 3);
            if (!stuck) REQUIRE(report.iterations > 6);  // the slipping nodes are not (the test's premise)
        }
    }
}

TEST_CASE("Structured Jacobian: Newton with GMRES lands on the dense corrector's solutions across the resonance",
          "[structured]") {
    const System s = small_block();
    HarmonicBalance structured(s, options(5, JacobianForm::structured));
    HarmonicBalance dense(s, options(5, JacobianForm::dense));
    REQUIRE_FALSE(dense.structured());
    CorrectorOptions co;
    co.tolerance = 1e-11;
    Corrector newton(structured, co);
    // Newton (with a backtracking line search) converges locally; from a far start on this
    // nonsmooth problem (lift-off, stick-slip) it may crawl where Ceres' Levenberg-Marquardt
    // still converges (measured: from the stuck linear guess at w = 0.6 the exact dense Newton
    // step too reduces |R| by 1 % per step): so each solve starts 10 % off the dense solution.
    for (double omega : {0.6, 0.85, 0.9, 0.95, 1.2}) {
        CAPTURE(omega);
        const Eigen::VectorXd xd = solution_at(dense, omega);
        int it_s = 0;
        double res_s = 0;
        const double scale = dense.unknown_scale(xd);
        Eigen::VectorXd xs = 0.9 * xd;
        for (Eigen::Index i = 0; i < xs.size(); i += 7) xs(i) += 0.05 * max_abs(xd);
        const bool solved = newton.solve_at(xs, omega, scale, it_s, res_s);
        INFO("newton " << it_s << " iterations, residual " << res_s << ", GMRES " << newton.statistics().krylov_iterations);
        REQUIRE(solved);
        REQUIRE(max_abs(xs - xd) <= 1e-8 * max_abs(xd));
    }
    REQUIRE(newton.statistics().krylov_iterations > 0);
    REQUIRE(newton.statistics().factorizations > 0);
    // The whole FRF: the same branch (status, folds) and the same largest response.
    const BranchResult a = continue_branch(structured, band()), b = continue_branch(dense, band());
    REQUIRE(a.status == ContinuationStatus::completed);
    REQUIRE(b.status == ContinuationStatus::completed);
    REQUIRE(a.located_folds == b.located_folds);
    // Different steps sample the peak differently: a loose bound, the points themselves are
    // solutions to 1e-9 (the corrector's tolerance) on both.
    REQUIRE(std::abs(peak(structured, a) - peak(dense, b)) <= 0.02 * peak(dense, b));
}

TEST_CASE("A correction hears CorrectorOptions::stop between its iterations, by Newton with GMRES and by Ceres",
          "[structured]") {
    // From 10 % off the solution at w = 0.9 (stick-slip) each corrector needs several iterations;
    // asked to stop, it ends unconverged after at most one, and converges again without the stop.
    const System s = small_block();
    for (const JacobianForm form : {JacobianForm::structured, JacobianForm::dense}) {
        HarmonicBalance hb(s, options(5, form));
        const double omega = 0.9;
        const Eigen::VectorXd solution = solution_at(hb, omega);
        const double scale = hb.unknown_scale(solution);
        const Eigen::VectorXd start = 0.9 * solution;
        CorrectorOptions co;
        co.tolerance = 1e-11;
        Eigen::VectorXd x = start;
        int free_iterations = 0;
        double residual = 0;
        {
            Corrector free(hb, co);
            REQUIRE(free.solve_at(x, omega, scale, free_iterations, residual));
        }
        int asked = 0;
        co.stop = [&asked]() {
            ++asked;
            return std::string("the test's stop");
        };
        Corrector stopped(hb, co);
        x = start;
        int iterations = 0;
        INFO((form == JacobianForm::structured ? "structured" : "dense") << ": " << free_iterations
                                                                           << " iterations without the stop");
        CHECK(free_iterations >= 2);
        CHECK_FALSE(stopped.solve_at(x, omega, scale, iterations, residual));
        CHECK(asked >= 1);
        CHECK(iterations <= 1);
    }
}

TEST_CASE("Structured Jacobian with law unilateral: Newton with GMRES lands on the dense corrector's solutions "
          "through stick, slip and lift-off, and the FRF peak equals the dense one",
          "[structured]") {
    const System s = rigid_block(0.004);
    HarmonicBalance structured(s, options(5, JacobianForm::structured));
    HarmonicBalance dense(s, options(5, JacobianForm::dense));
    CorrectorOptions co;
    co.tolerance = 1e-11;
    Corrector newton(structured, co);
    for (double omega : {0.6, 0.85, 0.9, 0.95, 1.2}) {
        CAPTURE(omega);
        const Eigen::VectorXd xd = solution_at(dense, omega);
        const double scale = dense.unknown_scale(xd);
        // Newton from 2 % off the dense solution (a predictor's distance: the dynamic
        // Lagrangian's residual is nonsmooth, Newton converges locally).
        Eigen::VectorXd xs = 0.98 * xd;
        int iterations = 0;
        double residual = 0;
        const bool solved = newton.solve_at(xs, omega, scale, iterations, residual);
        INFO("newton " << iterations << " iterations, residual " << residual << ", GMRES "
                       << newton.statistics().krylov_iterations);
        REQUIRE(solved);
        REQUIRE(max_abs(xs - xd) <= 1e-8 * max_abs(xd));
    }
    REQUIRE(newton.statistics().krylov_iterations > 0);
    const BranchResult a = continue_branch(structured, band()), b = continue_branch(dense, band());
    REQUIRE(a.status == ContinuationStatus::completed);
    REQUIRE(b.status == ContinuationStatus::completed);
    REQUIRE(std::abs(peak(structured, a) - peak(dense, b)) <= 0.02 * peak(dense, b));
}

TEST_CASE("Structured Jacobian: chosen automatically above the threshold (laws with internal states but unilateral: above the dense "
          "bound), refused where it does not apply",
          "[structured]") {
    // 100 nodes in 3D at H = 15: 9300 unknowns, beyond the dense bound, allowed structured.
    bench::LatticeOptions big;
    big.nx = big.ny = 10;
    const System s = bench::lattice(big);
    REQUIRE_NOTHROW(HarmonicBalance::validate(s, options(15, JacobianForm::automatic, 20)));
    try {
        HarmonicBalance::validate(s, options(15, JacobianForm::dense, 20));
        FAIL("dense beyond max_unknowns was accepted");
    } catch (const InvalidInput& e) {
        REQUIRE_THAT(e.what(), Catch::Contains("9300") && Catch::Contains("jacobian = structured"));
    }
    HarmonicBalance small(small_block(), options(3, JacobianForm::automatic));
    REQUIRE_FALSE(small.structured());  // 270 unknowns: the dense form
    // odd harmonics only: a named refusal.
    HarmonicBalanceOptions odd = options(3, JacobianForm::structured);
    odd.odd_harmonics = true;
    System symmetric = small_block();
    REQUIRE_THROWS_WITH(HarmonicBalance(symmetric, odd), Catch::Contains("jacobian = structured") &&
                                                             Catch::Contains("odd_harmonics"));
    // Laws with internal states (but unilateral): structured when asked; automatically only
    // beyond the dense bound.
    REQUIRE(HarmonicBalance(stateful_block(), options(3, JacobianForm::structured)).structured());
    const HarmonicBalance stateful(stateful_block(), options(40, JacobianForm::automatic));
    INFO("stateful_block at H = 40: " << stateful.unknowns() << " unknowns");
    REQUIRE(stateful.unknowns() > HarmonicBalance::structured_threshold);
    REQUIRE(stateful.unknowns() <= HarmonicBalance::max_unknowns);
    REQUIRE_FALSE(stateful.structured());
    // Law unilateral's multipliers do not hold it back: structured above structured_threshold,
    // as the memoryless laws (36 unknowns a coefficient: 1476 at H = 20, 2196 at H = 30).
    const HarmonicBalance below(rigid_block(), options(20, JacobianForm::automatic));
    REQUIRE(below.unknowns() == 1476);
    REQUIRE_FALSE(below.structured());
    REQUIRE(HarmonicBalance(rigid_block(), options(30, JacobianForm::automatic)).structured());
    REQUIRE(HarmonicBalance(rigid_block(), options(90, JacobianForm::automatic)).structured());
    REQUIRE(HarmonicBalance::fitting_harmonics(rigid_block(), options(3, JacobianForm::automatic), 90) == 90);
    REQUIRE(HarmonicBalance::fitting_harmonics(rigid_block(), options(3, JacobianForm::dense), 90) == 82);
    REQUIRE_THROWS_WITH(parse_jacobian_form("sparse"), Catch::Contains("allowed automatic, dense, structured"));
}

TEST_CASE("Factored modal receptance: G_B (I + S G_B)^-1 applied equals the formed G_k and its derivative",
          "[structured]") {
    const System s = small_block();
    Eigen::MatrixXd w(s.dofs(), 0);
    for (const Contact& c : s.contacts) {
        const Eigen::MatrixXd d = s.contact_directions(c);
        w.conservativeResize(Eigen::NoChange, w.cols() + d.cols());
        w.rightCols(d.cols()) = d;
    }
    const auto ns = w.cols();
    Receptance r(s.mass, s.damping, s.stiffness, w, s.excitation, Eigen::MatrixXd(0, s.dofs()));
    r.use_modes(12, Eigen::VectorXd::Constant(ns, 0.7), Eigen::VectorXd::Constant(ns, 0.05));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXcd z(ns);
    for (Eigen::Index i = 0; i < ns; ++i) z(i) = {u(rng), u(rng)};
    for (int k : {1, 3}) {
        CAPTURE(k);
        const Receptance::Harmonic formed = r.solve(k, 0.8, true, false, true);
        Receptance::Harmonic factored = r.solve(k, 0.8, true, false, false);
        REQUIRE(formed.ok);
        REQUIRE(factored.ok);
        REQUIRE(factored.contact.size() == 0);
        REQUIRE(factored.factored != nullptr);
        const Eigen::VectorXcd gz = formed.contact * z, gz_omega = formed.contact_omega * z;
        REQUIRE((factored.apply(z) - gz).cwiseAbs().maxCoeff() <= 1e-12 * gz.cwiseAbs().maxCoeff());
        REQUIRE((factored.apply_omega(z) - gz_omega).cwiseAbs().maxCoeff() <= 1e-12 * gz_omega.cwiseAbs().maxCoeff());
        REQUIRE((factored.contact_load - formed.contact_load).cwiseAbs().maxCoeff() <=
                1e-12 * formed.contact_load.cwiseAbs().maxCoeff());
        REQUIRE((factored.contact_load_omega - formed.contact_load_omega).cwiseAbs().maxCoeff() <=
                1e-12 * formed.contact_load_omega.cwiseAbs().maxCoeff());
        factored.materialize();
        REQUIRE((factored.contact - formed.contact).cwiseAbs().maxCoeff() <= 1e-12 * formed.contact.cwiseAbs().maxCoeff());
    }
}

TEST_CASE("hbf frf --jacobian structured: the lift-off examples' FRFs and peaks equal the dense corrector's, "
          "law elastic and law unilateral, bad forms refused",
          "[structured]") {
    TempDir dir;
    for (const std::string name : {"liftoff3", "liftoff3_rigid"}) {
        CAPTURE(name);
        const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/" + name + ".toml";
        nlohmann::json summary[2];
        int k = 0;
        for (const std::string form : {"structured", "dense"}) {
            const fs::path out = dir.path / (form + ".csv"), json = dir.path / (form + ".json");
            const auto r = ::test::run_hbf("frf --config '" + example + "' --jacobian " + form + " --out '" + out.string() +
                                               "' --summary '" + json.string() + "'",
                                           dir);
            INFO(r.err);
            REQUIRE(r.exit_code == 0);
            summary[k++] = nlohmann::json::parse(::test::slurp(json));
        }
        CHECK(summary[0]["parameters"]["structured_jacobian"] == 1);
        CHECK(summary[1]["parameters"]["structured_jacobian"] == 0);
        CHECK(summary[0]["solver"]["krylov_iterations"].get<long long>() > 0);
        // The located peak (a stick-slip corner or a smooth maximum, polished): the same solution.
        const auto& a = summary[0]["peaks"][0];
        const auto& b = summary[1]["peaks"][0];
        INFO(a.dump() << "\n" << b.dump());
        CHECK(std::abs(a["w"].get<double>() - b["w"].get<double>()) <= 1e-7 * b["w"].get<double>());
        CHECK(std::abs(a["y_max"].get<double>() - b["y_max"].get<double>()) <= 1e-7 * b["y_max"].get<double>());
    }
    const std::string example = std::string(HBF_SOURCE_DIR) + "/examples/systems/liftoff3.toml";
    ::test::check_bad_input("frf --config '" + example + "' --jacobian sparse", {"--jacobian", "allowed automatic, dense, structured"},
                            dir);
    ::test::check_bad_config(::test::slurp(example) + "\n[solver]\njacobian = 3\n", {"solver.jacobian", "expected a string"},
                             dir);
    ::test::check_bad_input("frf --law dahl --jacobian structured --harmonics odd:5",
                            {"jacobian = structured", "odd_harmonics"}, dir);
}

TEST_CASE("HB error estimate: above structured_threshold unknowns at 2H, automatic solves it with the structured "
          "Jacobian, the dense estimate's value",
          "[structured]") {
    // The rigid block (36 unknowns a coefficient) at H = 11: the branch dense (828 unknowns),
    // the estimate at H = 22 (1,620 unknowns) structured under automatic, dense when asked.
    const System s = rigid_block();
    std::vector<double> estimates;
    for (JacobianForm form : {JacobianForm::automatic, JacobianForm::dense}) {
        FrfSettings settings = default_frf_settings(s, {Output::dof(0)});
        settings.harmonic_balance = options(11, form);
        settings.continuation.omega_start = 0.95;
        settings.continuation.omega_end = 1.0;
        settings.continuation.locate_transitions = false;
        settings.exact = false;
        settings.peaks = false;
        settings.error_points = 1;
        HarmonicBalance hb(s, settings.harmonic_balance);
        REQUIRE_FALSE(hb.structured());
        FrfResult r = compute_frf(hb, settings);
        REQUIRE(r.branch.status == ContinuationStatus::completed);
        REQUIRE(r.error_harmonics == 22);
        REQUIRE(std::isfinite(r.hb_error));
        estimates.push_back(r.hb_error);
        // The same estimate again, to read which Jacobian it took.
        const detail::HbErrorSummary again = detail::estimate_hb_error(hb, settings, settings.outputs, r);
        CHECK(again.structured == (form == JacobianForm::automatic));
        CHECK(again.failed == 0);
        CHECK(again.largest == Approx(r.hb_error).epsilon(1e-12));
    }
    INFO("automatic " << estimates[0] << ", dense " << estimates[1]);
    CHECK(estimates[0] > 1e-8);  // a real difference between H and 2H, not a copy
    CHECK(estimates[0] == Approx(estimates[1]).epsilon(1e-6));
}
