// Reduction of FE models onto their interface (reduction.hpp): each method against the full
// model's linear response (dense solves), its exact limits (every mode kept; statics), and the
// closed forms of what it leaves out (the massless boundary's mass; MacNeal's residual
// flexibility from the full eigendecomposition).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "cli_support.hpp"
#include "hbf/config.hpp"
#include "hbf/error.hpp"
#include "hbf/model.hpp"
#include "hbf/reduction.hpp"
#include "support.hpp"

using namespace hbf;
using ::test::TempDir;
using ::test::write_file;
namespace fs = std::filesystem;

namespace {

/// A clamped Euler-Bernoulli cantilever (EI = 1, rho A = 1, length 1) of `elements` elements,
/// consistent mass (the retained DOFs' mass couples to the interior) or lumped (`lumped`: half
/// an element's mass on each end's transverse DOF, a small rotary inertia). DOFs of node
/// i = 1..elements: 2 (i - 1) transverse, 2 (i - 1) + 1 rotation.
struct Beam {
    Eigen::MatrixXd mass, stiffness;
};
Beam cantilever(int elements, bool lumped = false) {
    const int n = 2 * elements;
    const double h = 1.0 / elements;
    Eigen::Matrix4d ke, me;
    ke << 12, 6 * h, -12, 6 * h, 6 * h, 4 * h * h, -6 * h, 2 * h * h, -12, -6 * h, 12, -6 * h, 6 * h, 2 * h * h, -6 * h,
        4 * h * h;
    ke /= h * h * h;
    if (lumped) {
        me.setZero();
        me(0, 0) = me(2, 2) = h / 2;
        me(1, 1) = me(3, 3) = h * h * h / 24;
    } else {
        me << 156, 22 * h, 54, -13 * h, 22 * h, 4 * h * h, 13 * h, -3 * h * h, 54, 13 * h, 156, -22 * h, -13 * h,
            -3 * h * h, -22 * h, 4 * h * h;
        me *= h / 420;
    }
    Beam b{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n)};
    for (int e = 0; e < elements; ++e)
        for (int a = 0; a < 4; ++a)
            for (int c = 0; c < 4; ++c) {
                const int ra = 2 * e - 2 + a, rc = 2 * e - 2 + c;  // node e's DOFs, then node e + 1's
                if (ra < 0 || rc < 0) continue;                     // the clamped node
                b.stiffness(ra, rc) += ke(a, c);
                b.mass(ra, rc) += me(a, c);
            }
    return b;
}

/// max over `rows` of |y_full - T y_reduced| / max |y_full| for the force F at omega.
double frf_error(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c, const Eigen::MatrixXd& k, const Eigen::VectorXd& f,
                 const ReducedModel& r, double omega) {
    const Eigen::VectorXcd full = linear_response(m, c, k, f, omega);
    const Eigen::VectorXcd q = linear_response(Eigen::MatrixXd(r.mass), Eigen::MatrixXd(r.damping),
                                               Eigen::MatrixXd(r.stiffness), r.project(f), omega);
    const Eigen::VectorXcd y = r.recovery.cast<std::complex<double>>() * q;
    return (full - y).cwiseAbs().maxCoeff() / full.cwiseAbs().maxCoeff();
}

/// The rounding level of a solve with the dynamic stiffness K - w^2 M + i w C: eps times its
/// condition number (2-norm, from the singular values), times a safety factor of 100.
double rounding_bound(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c, const Eigen::MatrixXd& k, double omega) {
    const Eigen::MatrixXcd z = dynamic_stiffness(m, c, k, omega);
    const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(z);
    const Eigen::VectorXd sigma = svd.singularValues();
    return 100.0 * std::numeric_limits<double>::epsilon() * sigma(0) / sigma(sigma.size() - 1);
}

}  // namespace

TEST_CASE("Craig-Bampton with every fixed-interface mode is the FE model in other coordinates", "[reduction]") {
    const Beam beam = cantilever(20);
    const int n = 40, tip = 38, mid = 18;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    f(tip) = 1.0;
    const Eigen::MatrixXd c = 0.002 * beam.mass + 1e-4 * beam.stiffness;  // Rayleigh
    ReductionOptions o;
    o.interface_dofs = {tip, mid};
    o.modes = n - 2;
    const ReducedModel r = reduce(sparse(beam.mass), sparse(c), sparse(beam.stiffness), o, {tip});
    REQUIRE(r.reduced() == n);
    CHECK(r.coordinate(tip) == 0);
    CHECK(r.coordinate(mid) == 1);
    // Exact at every frequency: below, between and above the modes (w_1 = 3.516).
    // Exact at every frequency, below, at and between the modes (w_1 = 3.516, w_3 = 61.70), to
    // the rounding of the solves (the condition number of Z: 3e5 at w = 0.5, 1e8 at w = 3.5).
    for (double omega : {0.5, 3.5, 22.0, 61.7, 500.0}) {
        INFO("w = " << omega);
        CHECK(frf_error(beam.mass, c, beam.stiffness, f, r, omega) < rounding_bound(beam.mass, c, beam.stiffness, omega));
    }
    // Rayleigh damping given to the reduction equals the FE model's projected (a Galerkin method).
    ReductionOptions ray = o;
    ray.damping = ReductionOptions::Damping::rayleigh;
    ray.rayleigh_mass = 0.002;
    ray.rayleigh_stiffness = 1e-4;
    const ReducedModel rr = reduce(sparse(beam.mass), SparseMatrix(), sparse(beam.stiffness), ray, {tip});
    CHECK(frf_error(beam.mass, c, beam.stiffness, f, rr, 3.5) < rounding_bound(beam.mass, c, beam.stiffness, 3.5));
    // Modal damping ratios of the reduced model's modes: with every mode kept they are the FE
    // model's, C = M Phi diag(2 zeta w) Phi^T M from the full eigendecomposition.
    ReductionOptions modal = o;
    modal.damping = ReductionOptions::Damping::modal;
    modal.modal_ratios = {0.01, 0.02};
    const ReducedModel rm = reduce(sparse(beam.mass), SparseMatrix(), sparse(beam.stiffness), modal, {tip});
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(beam.stiffness, beam.mass);
    Eigen::VectorXd d(n);
    for (int j = 0; j < n; ++j) d(j) = 2.0 * (j == 0 ? 0.01 : 0.02) * std::sqrt(eig.eigenvalues()(j));
    const Eigen::MatrixXd mphi = beam.mass * eig.eigenvectors();
    const Eigen::MatrixXd c_modal = mphi * d.asDiagonal() * mphi.transpose();
    for (double omega : {3.516, 22.03, 100.0})
        CHECK(frf_error(beam.mass, c_modal, beam.stiffness, f, rm, omega) <
              rounding_bound(beam.mass, c_modal, beam.stiffness, omega));
}

TEST_CASE("Every method is exact statically, for the loads on retained DOFs", "[reduction]") {
    const Beam beam = cantilever(30);
    const int n = 60, tip = 58;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    f(tip) = 1.0;
    f(20) = -0.4;  // an interior DOF: retained with the loads
    const Eigen::VectorXd exact = beam.stiffness.ldlt().solve(f);
    for (ReductionMethod method :
         {ReductionMethod::craig_bampton, ReductionMethod::massless_boundary, ReductionMethod::macneal}) {
        for (int modes : {1, 6}) {
            ReductionOptions o;
            o.interface_dofs = {tip, 30};
            o.modes = modes;
            o.method = method;
            const ReducedModel r = reduce(sparse(beam.mass), SparseMatrix(), sparse(beam.stiffness), o, {tip, 20});
            REQUIRE(r.retained == std::vector<int>{tip, 30, 20});
            const Eigen::VectorXd q = Eigen::MatrixXd(r.stiffness).ldlt().solve(r.project(f));
            const Eigen::VectorXd y = r.recovery * q;
            INFO(to_string(method) << ", " << modes << " modes");
            CHECK((y - exact).cwiseAbs().maxCoeff() < 1e-10 * exact.cwiseAbs().maxCoeff());
        }
    }
}

TEST_CASE("Craig-Bampton truncated: Rayleigh-Ritz bounds on the frequencies, and the FRF converges with the modes",
          "[reduction]") {
    // A truncated reduction is an approximation: a mode of the structure below the kept
    // fixed-interface frequencies comes out too high by a relative amount that falls with the
    // modes kept (Rayleigh-Ritz on nested subspaces: each reduced frequency is an upper bound,
    // non-increasing as modes are added), and near a resonance of damping ratio zeta the FRF
    // errs by about that shift / zeta. The FRF over a fixed band that covers the first three
    // resonances converges as modes are added.
    const Beam beam = cantilever(40);
    const int n = 80, tip = 78;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    f(tip) = 1.0;
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(beam.stiffness, beam.mass);
    const Eigen::VectorXd exact = eig.eigenvalues().cwiseSqrt();
    const Eigen::MatrixXd mphi = beam.mass * eig.eigenvectors();
    const Eigen::MatrixXd c = mphi * (0.04 * exact).asDiagonal() * mphi.transpose();  // 2 % modal damping
    const double band = 1.2 * exact(2);
    double previous_error = 1e300;
    Eigen::VectorXd previous_frequencies = Eigen::VectorXd::Constant(5, 1e300);
    for (int modes : {4, 8, 16, 32}) {
        ReductionOptions o;
        o.interface_dofs = {tip, 40};
        o.modes = modes;
        const ReducedModel r = reduce(sparse(beam.mass), sparse(c), sparse(beam.stiffness), o, {tip});
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> red(Eigen::MatrixXd(r.stiffness),
                                                                             Eigen::MatrixXd(r.mass));
        const Eigen::VectorXd frequencies = red.eigenvalues().head(5).cwiseSqrt();
        for (int j = 0; j < 5; ++j) {
            INFO(modes << " modes, mode " << j + 1);
            // the dense reference errs by eps lambda_max absolutely in lambda (half that in w)
            const double reference_rounding = 100.0 * std::numeric_limits<double>::epsilon() *
                                              eig.eigenvalues().maxCoeff() / eig.eigenvalues()(j);
            CHECK(frequencies(j) >= exact(j) * (1.0 - reference_rounding));
            CHECK(frequencies(j) <= previous_frequencies(j) * (1.0 + 1e-12));
        }
        previous_frequencies = frequencies;
        double worst = 0.0;
        for (int k = 1; k <= 300; ++k) worst = std::max(worst, frf_error(beam.mass, c, beam.stiffness, f, r, band * k / 300.0));
        INFO(modes << " modes: worst relative FRF error up to w = " << band << ": " << worst);
        CHECK(worst < 0.5 * previous_error);
        previous_error = worst;
    }
}

TEST_CASE("Massless-boundary Craig-Bampton with every mode: the FE model less the boundary's Schur mass",
          "[reduction]") {
    const Beam beam = cantilever(12);
    const int n = 24, tip = 22, mid = 10;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    f(tip) = 1.0;
    ReductionOptions o;
    o.interface_dofs = {tip, mid};
    o.modes = n - 2;
    o.method = ReductionMethod::massless_boundary;
    const ReducedModel r = reduce(sparse(beam.mass), SparseMatrix(), sparse(beam.stiffness), o, {tip});
    // Theorem (reduction.hpp): M_bb becomes M_bi M_ii^-1 M_ib.
    const std::vector<int> b{tip, mid};
    std::vector<int> in;
    for (int i = 0; i < n; ++i)
        if (i != tip && i != mid) in.push_back(i);
    Eigen::MatrixXd m_bi(2, n - 2), m_ii(n - 2, n - 2);
    for (int a = 0; a < 2; ++a)
        for (int j = 0; j < n - 2; ++j) m_bi(a, j) = beam.mass(b[a], in[j]);
    for (int a = 0; a < n - 2; ++a)
        for (int j = 0; j < n - 2; ++j) m_ii(a, j) = beam.mass(in[a], in[j]);
    const Eigen::MatrixXd schur_part = m_bi * m_ii.ldlt().solve(Eigen::MatrixXd(m_bi.transpose()));
    Eigen::MatrixXd deficient = beam.mass;
    for (int a = 0; a < 2; ++a)
        for (int c2 = 0; c2 < 2; ++c2) deficient(b[a], b[c2]) = schur_part(a, c2);
    const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(n, n);
    for (double omega : {1.0, 3.5, 30.0, 200.0}) CHECK(frf_error(deficient, zero, beam.stiffness, f, r, omega) < 1e-9);
    CHECK(Eigen::MatrixXd(r.mass).topLeftCorner(2, 2).cwiseAbs().maxCoeff() == 0.0);  // massless
    // Lumped mass without rotary inertia at the retained transverse DOFs' neighbours: M_bi = 0,
    // so the massless boundary loses exactly the retained DOFs' own mass; with it removed from
    // the FE model, both Craig-Bampton variants equal the FE model.
    Beam lumped = cantilever(12, true);
    for (int d : b) lumped.mass(d, d) = 0.0;
    ReductionOptions cb = o;
    cb.method = ReductionMethod::craig_bampton;
    const ReducedModel r1 = reduce(sparse(lumped.mass), SparseMatrix(), sparse(lumped.stiffness), o, {tip});
    const ReducedModel r2 = reduce(sparse(lumped.mass), SparseMatrix(), sparse(lumped.stiffness), cb, {tip});
    for (double omega : {1.0, 30.0}) {
        CHECK(frf_error(lumped.mass, zero, lumped.stiffness, f, r1, omega) < 1e-9);
        CHECK(frf_error(lumped.mass, zero, lumped.stiffness, f, r2, omega) < 1e-9);
    }
}

TEST_CASE("retain_loads = false: a load on an interior DOF is projected onto the modes, exact with every mode",
          "[reduction]") {
    const Beam beam = cantilever(12);
    const int n = 24, tip = 22, mid = 10;
    System fe;
    fe.mass = sparse(beam.mass);
    fe.stiffness = sparse(beam.stiffness);
    fe.damping = SparseMatrix(n, n);
    fe.excitation = Eigen::VectorXd::Zero(n);
    fe.excitation(mid) = 1.0;
    ReductionOptions o;
    o.interface_dofs = {tip};
    o.retain_loads = false;
    const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(n, n);
    // The load's static part is carried by the modes alone: the error falls as they are added,
    // and with every interior mode the reduction is exact again.
    double previous = std::numeric_limits<double>::infinity();
    for (int modes : {2, 6, 12, 23}) {
        o.modes = modes;
        const ReducedSystem r = reduce(fe, o);
        CHECK(r.model.retained == std::vector<int>{tip});
        CHECK(r.model.projected_load_dofs == 1);
        CHECK_THAT(r.model.summary(), Catch::Contains("loads on 1 interior DOFs projected onto the modes"));
        for (double omega : {0.5, 3.5}) {
            const double e = frf_error(beam.mass, zero, beam.stiffness, fe.excitation, r.model, omega);
            INFO("modes " << modes << ", w = " << omega << ": " << e);
            if (modes == 23) CHECK(e < 1e-9);
            else CHECK(e > 1e-8);  // not statically exact: the load's DOF is not kept
            if (omega == 0.5) {
                CHECK(e < previous);
                previous = e;
            }
        }
    }
    // Kept (the default), the loaded DOF is statically exact at any mode count; with a massless
    // boundary it is massless too, and the mass it drops is the difference.
    o.modes = 6;
    ReductionOptions keep = o;
    keep.retain_loads = true;
    const ReducedSystem kept = reduce(fe, keep);
    CHECK(kept.model.retained == std::vector<int>{tip, mid});
    CHECK(kept.model.projected_load_dofs == 0);
    CHECK(frf_error(beam.mass, zero, beam.stiffness, fe.excitation, kept.model, 0.0) < 1e-9);
    o.method = keep.method = ReductionMethod::massless_boundary;
    const ReducedSystem light = reduce(fe, o), heavy = reduce(fe, keep);
    CHECK(light.model.dropped_mass.size() == 1);
    CHECK(heavy.model.dropped_mass.size() == 2);
    CHECK(light.model.dropped_mass_fraction < heavy.model.dropped_mass_fraction);
}

TEST_CASE("MacNeal: the retained DOFs' receptance is the kept modes plus the static residual flexibility",
          "[reduction]") {
    const Beam beam = cantilever(15);
    const int n = 30, tip = 28, mid = 14, modes = 5;
    ReductionOptions o;
    o.interface_dofs = {tip, mid};
    o.modes = modes;
    o.method = ReductionMethod::macneal;
    const ReducedModel r = reduce(sparse(beam.mass), SparseMatrix(), sparse(beam.stiffness), o);
    // The reference from the full model: the kept modes' phi_b phi_b^T / (lambda - w^2) plus the
    // residual (K^-1)_bb - sum over the kept modes of phi_b phi_b^T / lambda, in long double (a
    // dense eigensolver errs by eps lambda_max in lambda: 1e-7 of lambda_1 in double here).
    using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    const LongMatrix k_long = beam.stiffness.cast<long double>(), m_long = beam.mass.cast<long double>();
    const Eigen::GeneralizedSelfAdjointEigenSolver<LongMatrix> eig(k_long, m_long);
    const int b[2] = {tip, mid};
    const LongMatrix flexibility = k_long.ldlt().solve(LongMatrix::Identity(n, n));
    for (double omega : {0.7, 5.0, 40.0, 300.0}) {
        Eigen::Matrix<long double, 2, 2> sum;
        for (int a = 0; a < 2; ++a)
            for (int c = 0; c < 2; ++c) sum(a, c) = flexibility(b[a], b[c]);
        const long double w2 = static_cast<long double>(omega) * omega;
        for (int j = 0; j < modes; ++j) {
            const long double lambda = eig.eigenvalues()(j);
            const long double factor = 1.0L / (lambda - w2) - 1.0L / lambda;
            for (int a = 0; a < 2; ++a)
                for (int c = 0; c < 2; ++c) sum(a, c) += factor * eig.eigenvectors()(b[a], j) * eig.eigenvectors()(b[c], j);
        }
        const Eigen::Matrix2d expected = sum.cast<double>();
        const Eigen::MatrixXd z = Eigen::MatrixXd(r.stiffness) - omega * omega * Eigen::MatrixXd(r.mass);
        const Eigen::MatrixXd h = z.inverse().topLeftCorner(2, 2);
        // Rounding: G = R_bb is a difference that cancels to 1e-4 of its terms (K^-1 at the tip is
        // the first mode's 1 / lambda_1), so G^-1 in K_r carries ~1e4 eps times the kept modes'
        // own errors: measured 1.6e-10, and 3.7e-9 at w = 300 beside the first truncated mode
        // (298.6), where the kept and the residual parts cancel as well.
        INFO("w = " << omega << ": " << (h - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff());
        CHECK((h - expected).cwiseAbs().maxCoeff() < 1e-7 * expected.cwiseAbs().maxCoeff());
    }
    CHECK(r.mode_frequencies(0) == Approx(std::sqrt(static_cast<double>(eig.eigenvalues()(0)))).epsilon(1e-12));
}

TEST_CASE("Reduction refuses bad interfaces, too many modes and unconstrained structures", "[reduction]") {
    const Beam beam = cantilever(6);
    const SparseMatrix m = sparse(beam.mass), k = sparse(beam.stiffness);
    auto refuses = [&](const ReductionOptions& o, const SparseMatrix& kk, const std::string& words) {
        try {
            reduce(m, SparseMatrix(), kk, o);
            FAIL("accepted: " << words);
        } catch (const InvalidInput& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(words) != std::string::npos);
        }
    };
    ReductionOptions o;
    o.interface_dofs = {10, 12};
    refuses(o, k, "reduction.interface: DOF 13 (entry 2) is out of range: allowed 1..12");
    o.interface_dofs = {10, 4, 10};
    refuses(o, k, "reduction.interface: DOF 11 is listed twice");
    o.interface_dofs = {10};
    o.modes = 12;
    refuses(o, k, "reduction.modes = 12 is out of range: allowed 0..11");
    o.modes = 0;
    o.method = ReductionMethod::macneal;
    refuses(o, k, "reduction.modes = 0 is out of range: allowed 1..11");
    // A free-free beam held at one transverse DOF turns about it: K_ii is singular.
    Eigen::MatrixXd free_free = Eigen::MatrixXd::Zero(14, 14), free_mass = Eigen::MatrixXd::Zero(14, 14);
    {
        const double h = 1.0 / 6;
        Eigen::Matrix4d ke;
        ke << 12, 6 * h, -12, 6 * h, 6 * h, 4 * h * h, -6 * h, 2 * h * h, -12, -6 * h, 12, -6 * h, 6 * h, 2 * h * h,
            -6 * h, 4 * h * h;
        ke /= h * h * h;
        for (int e = 0; e < 6; ++e) free_free.block(2 * e, 2 * e, 4, 4) += ke;
        free_mass = Eigen::MatrixXd::Identity(14, 14);
    }
    ReductionOptions o2;
    o2.interface_dofs = {0};
    try {
        reduce(sparse(free_mass), SparseMatrix(), sparse(free_free), o2);
        FAIL("an unconstrained structure was reduced");
    } catch (const InvalidInput& e) {
        CHECK(std::string(e.what()).find("reduction.interface: the structure with its retained DOFs held is singular") !=
              std::string::npos);
    }
    CHECK_THROWS_AS(parse_reduction_method("guyan"), InvalidInput);
    CHECK(parse_reduction_method("massless-boundary") == ReductionMethod::massless_boundary);
}

namespace {
/// A system file for the shipped 200-DOF beam (examples/systems/beam: its Matrix Market
/// matrices, 10 N at mid-span DOF 99) with the tip's transverse DOF 199 in contact, and
/// `reduction` as its [reduction] table (1-based DOFs throughout).
std::string beam_file(const std::string& reduction, double friction_limit = 1e9) {
    const std::string dir = std::string(HBF_SOURCE_DIR) + "/examples/systems/beam/";
    std::string excitation = "[";
    for (int i = 1; i <= 200; ++i) excitation += std::string(i > 1 ? ", " : "") + (i == 99 ? "10.0" : "0");
    excitation += "]";
    return "[structure]\nmass = \"" + dir + "beam200_mass.mtx\"\nstiffness = \"" + dir + "beam200_stiffness.mtx\"\n" +
           "damping = \"" + dir + "beam200_damping.mtx\"\nexcitation = " + excitation + "\n" +
           "[[contact]]\ndof = 199\nlaw = \"coulomb\"\nfriction_limit = " + std::to_string(friction_limit) + "\n" +
           "[output]\nreport = [99, 199, 150]\n" + reduction;
}
/// Checks `outputs`' first harmonics (their coefficients `y`, columns DOFs of the model solved),
/// outputs of the FE DOFs `dofs` (0-based), against the FE model `fe`'s linear response at w with the DOFs `held` (0-based) held: their
/// rows and columns removed, solved in long double as in test_condensed; to 1e-8 of the largest
/// amplitude (the corrector's 1e-10 amplified by the response).
void check_held_response(const std::vector<Output>& outputs, const Eigen::MatrixXd& y, const hbf::io::SystemConfig& fe,
                         const std::vector<int>& dofs, const std::vector<int>& held, double w) {
    using Long = std::complex<long double>;
    using LongMatrix = Eigen::Matrix<Long, Eigen::Dynamic, Eigen::Dynamic>;
    const System& s = fe.system;
    const long double w2 = static_cast<long double>(w) * w;
    LongMatrix z = Eigen::MatrixXd(s.stiffness).cast<long double>().cast<Long>() -
                   (w2 * Eigen::MatrixXd(s.mass).cast<long double>()).cast<Long>() +
                   Long(0.0L, static_cast<long double>(w)) * Eigen::MatrixXd(s.damping).cast<long double>().cast<Long>();
    Eigen::Matrix<Long, Eigen::Dynamic, 1> f = s.excitation.cast<long double>().cast<Long>();
    for (int d : held) {
        z.row(d).setZero();
        z.col(d).setZero();
        z(d, d) = 1.0L;
        f(d) = 0.0L;
    }
    const Eigen::Matrix<Long, Eigen::Dynamic, 1> solved = z.partialPivLu().solve(f);
    const double scale = std::abs(solved.cast<std::complex<long double>>().cwiseAbs().maxCoeff());
    for (std::size_t o = 0; o < outputs.size(); ++o) {
        const Eigen::VectorXd c = outputs[o].combine(y);
        const int dof = dofs[o];
        const std::complex<double> expected(static_cast<double>(solved(dof).real()), static_cast<double>(solved(dof).imag()));
        INFO("w = " << w << ", " << outputs[o].name());
        // y = Re(Y e^{i w t}) = c1 cos + s1 sin: c1 = Re Y, s1 = -Im Y
        CHECK(std::abs(c(1) - expected.real()) < 1e-8 * scale);
        CHECK(std::abs(c(2) + expected.imag()) < 1e-8 * scale);
    }
}
}  // namespace

TEST_CASE("[reduction] in a system file: the stuck nonlinear FRF of the reduced beam is the tied FE model's linear FRF",
          "[reduction][config]") {
    TempDir dir;
    const fs::path file = dir.path / "beam.toml";
    // Every fixed-interface mode kept (198 = 200 - the contact DOF - the excited DOF): the
    // reduction is exact, so harmonic balance on it with the tip stuck (a friction limit of
    // 1e9 N) must give the FE model's linear response with the tip held (its row and column
    // removed), solved in long double as in test_condensed.
    write_file(file, beam_file("[reduction]\nmodes = 198\n"));
    const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
    REQUIRE(config.reduction);
    CHECK(config.reduction->retained == std::vector<int>{198, 98});  // the contact's DOF, then the loaded one
    REQUIRE(config.outputs.size() == 3);
    CHECK(config.outputs[0].name() == "y99");
    CHECK(config.outputs[2].name() == "y150");
    const hbf::io::SystemConfig fe = [&] {
        write_file(file, beam_file(""));
        return hbf::io::read_system_config(file.string());
    }();
    const std::vector<double> omegas = {35.0, 70.0};
    const auto y = hbf::test::sampled_dofs(config.system, {3, 0, Formulation::condensed}, omegas, 30.0, 80.0, 1e-10);
    for (std::size_t k = 0; k < omegas.size(); ++k)
        check_held_response(config.outputs, y[k], fe, {98, 198, 149}, {198}, omegas[k]);
    // retain_loads = false: the loaded DOF is not kept, its load projected onto the modes (every
    // one of the 199 kept again: exact), and the same response.
    write_file(file, beam_file("[reduction]\nmodes = 199\nretain_loads = false\n"));
    const hbf::io::SystemConfig projected = hbf::io::read_system_config(file.string());
    REQUIRE(projected.reduction);
    CHECK(projected.reduction->retained == std::vector<int>{198});
    CHECK_THAT(projected.reduction->summary(), Catch::Contains("loads on 1 interior DOFs projected onto the modes"));
    const auto yp = hbf::test::sampled_dofs(projected.system, {3, 0, Formulation::condensed}, omegas, 30.0, 80.0, 1e-10);
    for (std::size_t k = 0; k < omegas.size(); ++k)
        check_held_response(projected.outputs, yp[k], fe, {98, 198, 149}, {198}, omegas[k]);
}

TEST_CASE("Clamped DOFs (structure.fixed): the beam clamped at its tip by the file, with and without a reduction, against the "
          "FE model's response with the tip held",
          "[reduction][config]") {
    TempDir dir;
    const fs::path file = dir.path / "beam.toml";
    const hbf::io::SystemConfig fe = [&] {
        write_file(file, beam_file(""));
        return hbf::io::read_system_config(file.string());
    }();
    // beam_file's text with its contact replaced and its outputs off the clamped DOFs.
    const auto text = [](const std::string& contact, const std::string& rest) {
        std::string t = beam_file(rest);
        const std::size_t from = t.find("[[contact]]"), to = t.find("[output]");
        t.replace(from, to - from, contact);
        const std::size_t report = t.find("report = [99, 199, 150]");
        t.replace(report, 23, "report = [99, 150]");
        return t;
    };
    struct Case {
        std::string name, contact, fixed, reduction;
        std::vector<int> held;  // the FE DOFs (0-based) held in the reference
    };
    const std::string stuck = "law = \"coulomb\"\nfriction_limit = 1e9\n";
    const std::vector<Case> cases = {
        // the transverse tip DOF clamped, no contact: 199 DOFs, directly and reduced (every mode)
        {"tip clamped", "", "fixed = [199]\n", "", {198}},
        {"tip clamped, reduced", "", "fixed = [199]\n", "[reduction]\nmodes = 198\n", {198}},
        // the tip's rotation clamped: a contact between the tip and it is one against the
        // ground (stuck: the tip held too), in either order of its DOFs
        {"contact onto a clamped DOF", "[[contact]]\ndof = 199\nother_dof = 200\n" + stuck, "fixed = [200]\n", "", {198, 199}},
        {"contact from a clamped DOF", "[[contact]]\ndof = 200\nother_dof = 199\n" + stuck, "fixed = [200]\n", "", {198, 199}},
        {"contact onto a clamped DOF, reduced", "[[contact]]\ndof = 199\nother_dof = 200\n" + stuck, "fixed = [200]\n",
         "[reduction]\nmodes = 197\n", {198, 199}},
    };
    const std::vector<double> omegas = {35.0, 70.0};
    for (const Case& c : cases) {
        INFO(c.name);
        std::string t = text(c.contact, c.reduction);
        t.replace(t.find("excitation = "), 0, c.fixed);
        write_file(file, t);
        const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
        REQUIRE(config.outputs.size() == 2);
        CHECK(config.outputs[0].name() == "y99");  // the file's numbering
        CHECK(config.outputs[1].name() == "y150");
        if (config.reduction) {
            // the reduced model in the file's numbering: the clamped DOFs' rows of T are zero
            CHECK(config.reduction->dofs() == 200);
            CHECK(config.reduction->clamped_dofs == 1);
            CHECK(config.reduction->recovery.row(c.held.back()).cwiseAbs().maxCoeff() == 0.0);
            CHECK(config.reduction->coordinate(98) >= 0);  // the loaded DOF
            CHECK(config.reduction->summary().find("199 FE DOFs (1 more clamped)") != std::string::npos);
        } else {
            CHECK(config.system.dofs() == 199);
        }
        // Without contacts the model is linear: its response solved directly (rows 1, 2 the
        // cosine and sine coefficients, as harmonic balance's).
        const auto y = config.system.contacts.empty() ? [&] {
            std::vector<Eigen::MatrixXd> linear;
            const System& m = config.system;
            for (double w : omegas) {
                const Eigen::VectorXcd z = linear_response(Eigen::MatrixXd(m.mass), Eigen::MatrixXd(m.damping),
                                                           Eigen::MatrixXd(m.stiffness), m.excitation, w);
                Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(3, m.dofs());
                rows.row(1) = z.real().transpose();
                rows.row(2) = -z.imag().transpose();
                linear.push_back(rows);
            }
            return linear;
        }() : hbf::test::sampled_dofs(config.system, {3, 0, Formulation::condensed}, omegas, 30.0, 80.0, 1e-10);
        for (std::size_t k = 0; k < omegas.size(); ++k)
            check_held_response(config.outputs, y[k], fe, {98, 149}, c.held, omegas[k]);
    }
}

TEST_CASE("Clamped DOFs (structure.fixed): bad lists and what a clamped DOF cannot carry are refused, naming the key",
          "[reduction][config]") {
    TempDir dir;
    const fs::path file = dir.path / "beam.toml";
    const auto with = [](const std::string& fixed, const std::string& rest = "") {
        std::string t = beam_file(rest);
        t.replace(t.find("excitation = "), 0, fixed);
        return t;
    };
    struct Case {
        std::string text;
        std::vector<std::string> expected;
    };
    const std::vector<Case> cases = {
        {with("fixed = [201]\n"), {"structure.fixed", "DOF 201", "allowed 1..200"}},
        {with("fixed = [0]\n"), {"structure.fixed", "DOF 0", "allowed 1..200"}},
        {with("fixed = [3, 3]\n"), {"structure.fixed", "DOF 3 is listed twice"}},
        {with("fixed = [2.5]\n"), {"structure.fixed", "not a DOF"}},
        {with("fixed = []\n"), {"structure.fixed", "empty"}},
        {with("fixed = [99]\n"), {"structure.fixed", "DOF 99 carries the excitation", "support"}},
        {with("fixed = [199]\n"), {"contact[1]", "clamped DOFs only"}},
        {with("fixed = [150]\n"), {"output", "y150", "clamped"}},
        {with("fixed = [5]\n", "[reduction]\nmodes = 4\ninterface = [199, 5]\n"), {"reduction.interface", "DOF 5 is clamped"}},
    };
    for (const Case& c : cases) hbf::test::check_refused_config(file, c.text, c.expected);
    // every DOF clamped
    std::string all = "fixed = [";
    for (int i = 1; i <= 200; ++i) all += std::to_string(i) + (i < 200 ? ", " : "]\n");
    hbf::test::check_refused_config(file, with(all), {"structure.fixed", "every DOF"});
    // an interface node on a clamped DOF; a sector model
    const std::string two_dofs = "[structure]\nmass = [1.0, 0.0]\nstiffness = [[2.0, -1.0], [-1.0, 1.0]]\n"
                                 "excitation = [1.0, 0.0]\nfixed = [2]\n";
    hbf::test::check_refused_config(file, two_dofs + "[[interface]]\nnodes = [[1, 2]]\nnormal = [0.0, 1.0]\nlaw = \"unilateral\"\n"
                                               "friction_coefficient = 0.3\n",
                                    {"interface[1].nodes", "node 1's DOF 2 is clamped"});
    hbf::test::check_refused_config(file, two_dofs + "[cyclic]\nsectors = 4\nengine_order = 1\n", {"structure.fixed", "sector"});
    // Through hbf: exit 2, the key named, no output.
    ::test::check_bad_config(with("fixed = [99]\n"), {"structure.fixed", "DOF 99 carries the excitation"}, dir);
}

TEST_CASE("[reduction] in a system file: bad keys and impossible reductions name the key", "[reduction][config]") {
    TempDir dir;
    const fs::path file = dir.path / "beam.toml";
    struct Case {
        std::string table;
        std::vector<std::string> expected;
    };
    const std::vector<Case> cases = {
        {"[reduction]\nmodes = 10\ninterface = [199, 300]\n", {"reduction.interface", "DOF 300", "allowed 1..200"}},
        {"[reduction]\nmodes = 10\ninterface = [199, 5, 199]\n", {"reduction.interface", "listed twice"}},
        {"[reduction]\nmodes = 10\ninterface = [199, 5.5]\n", {"reduction.interface", "not a DOF"}},
        {"[reduction]\nmodes = 199\n", {"reduction.modes = 199 is out of range: allowed 0..198"}},
        {"[reduction]\ninterface = [199]\n", {"reduction.modes", "missing"}},
        {"[reduction]\nmodes = 4\nmethod = \"guyan\"\n", {"reduction.method", "craig-bampton, massless-boundary, macneal"}},
        {"[reduction]\nmodes = 4\nrayleigh = [0.1, 0.0]\n", {"reduction", "damping matrix", "rayleigh"}},
        {"[reduction]\nmodes = 4\ninterface = [5]\n", {"contact[1]", "FE DOF 199", "reduction.interface"}},
        {"[reduction]\nmodes = 4\nshape = 1\n", {"reduction", "shape"}},
        {"[reduction]\nmodes = 4\nretain_loads = 1\n", {"reduction.retain_loads", "expected true or false"}},
    };
    for (const Case& c : cases) hbf::test::check_refused_config(file, beam_file(c.table), c.expected);
    // Through hbf: exit 2, the key named, no output (an unconstrained structure: the beam's
    // clamp removed is not possible with its file; the library test covers it).
    ::test::check_bad_config(beam_file("[reduction]\nmodes = 199\n"), {"reduction.modes = 199 is out of range"}, dir);
    ::test::check_bad_config(beam_file("[reduction]\nmodes = 4\ninterface = [199, 199]\n"),
                             {"reduction.interface", "listed twice"}, dir);
}
