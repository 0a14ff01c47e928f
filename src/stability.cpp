#include "hbf/stability.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "hbf/contact.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/friction.hpp"

namespace hbf {

std::string to_string(Stability stability) {
    switch (stability) {
        case Stability::not_computed: return "";
        case Stability::stable: return "true";
        case Stability::unstable: return "false";
        case Stability::uncertain: return "uncertain";
    }
    return "?";
}

std::string to_string(StabilityMethod method) {
    switch (method) {
        case StabilityMethod::hill: return "hill";
        case StabilityMethod::monodromy: return "monodromy";
        case StabilityMethod::both: return "both";
    }
    return "?";
}

StabilityMethod parse_stability_method(const std::string& name) {
    for (StabilityMethod m : {StabilityMethod::hill, StabilityMethod::monodromy, StabilityMethod::both})
        if (to_string(m) == name) return m;
    throw InvalidInput("stability method = '" + name + "' is not known: allowed hill, monodromy, both");
}

void StabilityOptions::validate() const {
    if (!(tolerance >= 0.0 && tolerance <= 1.0))
        throw InvalidInput("stability tolerance = " + format_number(tolerance) + " is out of range: allowed 0..1");
    if (!(confidence > 0.0 && confidence <= 1.0))
        throw InvalidInput("stability confidence = " + format_number(confidence) + " is out of range: allowed (0, 1]");
    if (!(integration_tolerance >= 1e-13 && integration_tolerance <= 1e-4))
        throw InvalidInput("stability integration_tolerance = " + format_number(integration_tolerance) +
                           " is out of range: allowed 1e-13..1e-4");
    if (max_hill_size < 10 || max_hill_size > 20000)
        throw InvalidInput("stability max_hill_size = " + std::to_string(max_hill_size) +
                           " is out of range: allowed 10..20000");
    if (!(exact_gap > 0.0 && std::isfinite(exact_gap)))
        throw InvalidInput("stability exact_gap = " + format_number(exact_gap) + " is out of range: allowed > 0");
}

namespace {

bool smooth(FrictionLaw law) {
    return contact_law(law).smooth();
}

/// Value and tau-derivative (d/dtheta) of a coefficient vector at phase theta.
void at_phase(const Eigen::VectorXd& c, double theta, double& value, double& rate) {
    value = c(0);
    rate = 0.0;
    for (int k = 1; 2 * k < c.size(); ++k) {
        const double ck = std::cos(k * theta), sk = std::sin(k * theta);
        value += c(2 * k - 1) * ck + c(2 * k) * sk;
        rate += k * (c(2 * k) * ck - c(2 * k - 1) * sk);
    }
}

Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& a) {
    Eigen::EigenSolver<Eigen::MatrixXd> solver(a, false);
    if (solver.info() != Eigen::Success) return {};
    return solver.eigenvalues();
}

double largest_modulus(const Eigen::VectorXcd& mu) {
    return mu.size() == 0 ? std::numeric_limits<double>::quiet_NaN() : mu.cwiseAbs().maxCoeff();
}

/// The variational equation ds' = A(t) ds of one HB solution (see stability.hpp).
class Variational {
public:
    Variational(HarmonicBalance& hb, const Eigen::MatrixXd& minv, const Eigen::MatrixXd& w, const SolutionPoint& p)
        : system_(hb.system()), omega_(p.omega), n_(hb.system().dofs()) {
        const int nc = static_cast<int>(system_.contacts.size());
        state_index_.assign(static_cast<std::size_t>(nc), -1);
        int s = 0;
        for (int c = 0; c < nc; ++c) {
            q_.push_back(hb.relative(p.x, c));
            z_.push_back(hb.state(p.x, c));
            if (z_.back().size() > 0) state_index_[static_cast<std::size_t>(c)] = 2 * n_ + s++;
        }
        d_ = 2 * n_ + s;
        base_ = Eigen::MatrixXd::Zero(d_, d_);
        base_.block(0, n_, n_, n_).setIdentity();
        const Eigen::MatrixXd K = Eigen::MatrixXd(system_.stiffness);
        const Eigen::MatrixXd C = system_.damping.size() > 0 && system_.damping.rows() == n_
                                      ? Eigen::MatrixXd(system_.damping)
                                      : Eigen::MatrixXd::Zero(n_, n_);
        base_.block(n_, 0, n_, n_) = -minv * K;
        base_.block(n_, n_, n_, n_) = -minv * C;
        w_ = w;
        mw_ = minv * w;
    }
    int size() const { return d_; }
    double omega() const { return omega_; }
    /// Slopes of every contact at phase theta.
    void slopes(double theta, std::vector<LocalLinearization>& out) const {
        out.resize(q_.size());
        for (std::size_t c = 0; c < q_.size(); ++c) {
            double q, dq, z = 0.0, dz;
            at_phase(q_[c], theta, q, dq);
            if (z_[c].size() > 0) at_phase(z_[c], theta, z, dz);
            out[c] = linearize(system_.contacts[c], omega_ * dq, z);
        }
    }
    /// A(t) at phase theta = omega t.
    void matrix(double theta, Eigen::MatrixXd& a) const {
        slopes(theta, scratch_);
        a = base_;
        for (std::size_t c = 0; c < q_.size(); ++c) add_contact(static_cast<int>(c), scratch_[c], a);
    }
    /// Adds contact c's part of A for the given slopes (entries of one instant).
    void add_contact(int c, const LocalLinearization& l, Eigen::MatrixXd& a) const {
        const auto col = static_cast<Eigen::Index>(c);
        a.block(n_, n_, n_, n_).noalias() -= l.f_v * mw_.col(col) * w_.col(col).transpose();
        const int s = state_index_[static_cast<std::size_t>(c)];
        if (s < 0) return;
        a.block(n_, s, n_, 1) -= l.f_z * mw_.col(col);
        a.block(s, n_, 1, n_) += l.g_v * w_.col(col).transpose();
        a(s, s) += l.g_z;
    }
    /// Hill's matrix on the samples of `fourier` (all harmonics 0..H).
    Eigen::MatrixXd hill(Fourier& fourier) const {
        const int m = fourier.size(), nt = fourier.time_samples();
        Eigen::MatrixXd h = Eigen::MatrixXd::Zero(d_ * m, d_ * m);
        // The constant part: a_ij I per block.
        for (int i = 0; i < d_; ++i)
            for (int j = 0; j < d_; ++j)
                if (base_(i, j) != 0.0) h.block(i * m, j * m, m, m).diagonal().setConstant(base_(i, j));
        // The contacts' parts: each entry of A is a combination of the slopes' samples.
        const int nc = static_cast<int>(q_.size());
        std::vector<Eigen::VectorXd> fv(static_cast<std::size_t>(nc), Eigen::VectorXd(nt)),
            fz = fv, gv = fv, gz = fv;
        // v_c and z_c on the AFT grid by the FFT (Fourier::to_time), then the slopes pointwise.
        Eigen::VectorXd v(nt), z(nt);
        for (int c = 0; c < nc; ++c) {
            const auto cc = static_cast<std::size_t>(c);
            fourier.to_time(omega_ * (fourier.derivative() * q_[cc]), v);
            if (z_[cc].size() > 0)
                fourier.to_time(z_[cc], z);
            else
                z.setZero();
            for (int j = 0; j < nt; ++j) {
                const LocalLinearization l = linearize(system_.contacts[cc], v(j), z(j));
                fv[cc](j) = l.f_v;
                fz[cc](j) = l.f_z;
                gv[cc](j) = l.g_v;
                gz[cc](j) = l.g_z;
            }
        }
        Eigen::MatrixXd p(m, m);
        for (int c = 0; c < nc; ++c) {
            const auto cc = static_cast<std::size_t>(c);
            const auto col = static_cast<Eigen::Index>(c);
            const Eigen::MatrixXd outer = -mw_.col(col) * w_.col(col).transpose();
            fourier.multiplication_matrix(fv[cc], p);
            for (int i = 0; i < n_; ++i)
                for (int j = 0; j < n_; ++j)
                    if (outer(i, j) != 0.0) h.block((n_ + i) * m, (n_ + j) * m, m, m) += outer(i, j) * p;
            const int s = state_index_[cc];
            if (s < 0) continue;
            fourier.multiplication_matrix(fz[cc], p);
            for (int i = 0; i < n_; ++i)
                if (mw_(i, col) != 0.0) h.block((n_ + i) * m, s * m, m, m) -= mw_(i, col) * p;
            fourier.multiplication_matrix(gv[cc], p);
            for (int j = 0; j < n_; ++j)
                if (w_(j, col) != 0.0) h.block(s * m, (n_ + j) * m, m, m) += w_(j, col) * p;
            fourier.multiplication_matrix(gz[cc], p);
            h.block(s * m, s * m, m, m) += p;
        }
        // - d/dt on every signal.
        const Eigen::MatrixXd d = omega_ * fourier.derivative();
        for (int i = 0; i < d_; ++i) h.block(i * m, i * m, m, m) -= d;
        return h;
    }

private:
    const System& system_;
    double omega_;
    int n_, d_ = 0;
    std::vector<Eigen::VectorXd> q_, z_;
    std::vector<int> state_index_;
    Eigen::MatrixXd base_, w_, mw_;
    mutable std::vector<LocalLinearization> scratch_;
};

void quiet_handler(int, const char*, const char*, char*, void*) {}

/// Phi(T) of ds' = A(t) ds by CVODE (BDF, dense, exact Jacobian). Small systems (d <= 12)
/// integrate Phi' = A Phi as one system of d^2 states (one step sequence; Jacobian I (x) A),
/// larger ones one column at a time (d LU factorisations of d x d instead of one of d^2).
class MonodromyIntegrator {
public:
    MonodromyIntegrator(const Variational& v, double tolerance)
        : v_(v), d_(v.size()), columns_(v.size() <= 12 ? v.size() : 1), length_(d_ * columns_) {
        if (SUNContext_Create(nullptr, &context_) != 0) throw std::runtime_error("SUNContext_Create failed");
        x_ = N_VNew_Serial(length_, context_);
        matrix_ = SUNDenseMatrix(length_, length_, context_);
        linear_ = SUNLinSol_Dense(x_, matrix_, context_);
        cvode_ = CVodeCreate(CV_BDF, context_);
        if (!x_ || !matrix_ || !linear_ || !cvode_) throw std::runtime_error("CVODE allocation failed");
        N_VConst(0.0, x_);
        check(CVodeInit(cvode_, rhs, 0.0, x_), "CVodeInit");
        check(CVodeSetErrHandlerFn(cvode_, quiet_handler, nullptr), "CVodeSetErrHandlerFn");
        check(CVodeSetUserData(cvode_, this), "CVodeSetUserData");
        check(CVodeSStolerances(cvode_, tolerance, tolerance * 1e-2), "CVodeSStolerances");
        check(CVodeSetLinearSolver(cvode_, linear_, matrix_), "CVodeSetLinearSolver");
        check(CVodeSetJacFn(cvode_, jacobian), "CVodeSetJacFn");
        check(CVodeSetMaxNumSteps(cvode_, 200000), "CVodeSetMaxNumSteps");
    }
    ~MonodromyIntegrator() {
        if (cvode_) CVodeFree(&cvode_);
        if (linear_) SUNLinSolFree(linear_);
        if (matrix_) SUNMatDestroy(matrix_);
        if (x_) N_VDestroy(x_);
        if (context_) SUNContext_Free(&context_);
    }
    MonodromyIntegrator(const MonodromyIntegrator&) = delete;
    MonodromyIntegrator& operator=(const MonodromyIntegrator&) = delete;

    /// False (and `failure`) when CVODE failed.
    bool run(Eigen::MatrixXd& phi, std::string& failure) {
        const double period = 2.0 * M_PI / v_.omega();
        phi.resize(d_, d_);
        for (int first = 0; first < d_; first += columns_) {
            N_VConst(0.0, x_);
            Eigen::Map<Eigen::MatrixXd> start(N_VGetArrayPointer(x_), d_, columns_);
            for (int j = 0; j < columns_; ++j) start(first + j, j) = 1.0;
            check(CVodeReInit(cvode_, 0.0, x_), "CVodeReInit");
            check(CVodeSetStopTime(cvode_, period), "CVodeSetStopTime");
            sunrealtype t = 0.0;
            const int flag = CVode(cvode_, period, x_, &t, CV_NORMAL);
            if (flag < 0) {
                failure = "CVODE failed on the variational equation (flag " + std::to_string(flag) + ") at t = " +
                          format_number(t) + " of T = " + format_number(period);
                return false;
            }
            phi.middleCols(first, columns_) = Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(x_), d_, columns_);
        }
        return true;
    }

private:
    static int rhs(sunrealtype t, N_Vector x, N_Vector dx, void* data) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_);
        Eigen::Map<Eigen::MatrixXd>(N_VGetArrayPointer(dx), self->d_, self->columns_).noalias() =
            self->a_ * Eigen::Map<const Eigen::MatrixXd>(N_VGetArrayPointer(x), self->d_, self->columns_);
        return 0;
    }
    static int jacobian(sunrealtype t, N_Vector, N_Vector, SUNMatrix j, void* data, N_Vector, N_Vector, N_Vector) {
        auto* self = static_cast<MonodromyIntegrator*>(data);
        self->v_.matrix(self->v_.omega() * t, self->a_);
        SUNMatZero(j);
        const int d = self->d_;
        for (int b = 0; b < self->columns_; ++b)  // I (x) A: one block of A per column of Phi
            for (int c = 0; c < d; ++c)
                Eigen::Map<Eigen::VectorXd>(SUNDenseMatrix_Column(j, b * d + c) + b * d, d) = self->a_.col(c);
        return 0;
    }
    void check(int flag, const char* what) const {
        if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed (flag " + std::to_string(flag) + ")");
    }

    const Variational& v_;
    int d_, columns_, length_;
    Eigen::MatrixXd a_;
    SUNContext context_ = nullptr;
    N_Vector x_ = nullptr;
    SUNMatrix matrix_ = nullptr;
    SUNLinearSolver linear_ = nullptr;
    void* cvode_ = nullptr;
};

/// Hill's classical sorted selection: mu = exp(lambda T) of the d exponents with the smallest
/// |Im lambda|; empty when the matrix would exceed max_size rows or the eigensolver failed.
Eigen::VectorXcd sorted_hill(const Variational& v, Fourier& fourier, int max_size) {
    if (v.size() * fourier.size() > max_size) return {};
    const Eigen::VectorXcd lambda = eigenvalues(v.hill(fourier));
    if (lambda.size() < v.size()) return {};
    std::vector<Eigen::Index> order(static_cast<std::size_t>(lambda.size()));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
        return std::abs(lambda(a).imag()) < std::abs(lambda(b).imag());
    });
    const double period = 2.0 * M_PI / v.omega();
    Eigen::VectorXcd mu(v.size());
    for (int k = 0; k < v.size(); ++k) mu(k) = std::exp(lambda(order[static_cast<std::size_t>(k)]) * period);
    return mu;
}

Stability verdict(double margin, double tolerance) {
    if (!std::isfinite(margin)) return Stability::uncertain;
    return margin > 1.0 + tolerance ? Stability::unstable : Stability::stable;
}

}  // namespace

std::string stability_refusal(const System& system) {
    if (system.contacts.empty()) {
        if (!system.has_positive_definite_mass())
            return "the mass matrix is singular (massless DOFs): the stability analysis needs M positive definite";
        return "";
    }
    bool all_smooth = true, all_exact = true;
    for (const Contact& c : system.contacts) {
        all_smooth = all_smooth && smooth(c.law);
        all_exact = all_exact && !smooth(c.law);
    }
    if (all_exact) {
        const std::string why = exact_solver_refusal(system);
        return why.empty() ? "" : "coulomb/jenkins stability comes from the event-exact solver, which refuses: " + why;
    }
    if (!all_smooth)
        return "the contacts mix smooth laws (dahl, lugre, coulomb-reg) with coulomb/jenkins: no stability analysis "
               "covers both";
    if (!system.has_positive_definite_mass())
        return "the mass matrix is singular (massless DOFs): the variational equations need M positive definite";
    return "";
}

StabilityAnalyser::StabilityAnalyser(HarmonicBalance& hb, StabilityOptions options)
    : hb_(hb), options_(options) {
    options_.validate();
    const System& s = hb.system();
    refusal_ = stability_refusal(s);
    smooth_ = std::all_of(s.contacts.begin(), s.contacts.end(), [](const Contact& c) { return smooth(c.law); });
    if (!refusal_.empty() || !smooth_) return;
    const Eigen::MatrixXd m = Eigen::MatrixXd(s.mass);
    minv_ = m.llt().solve(Eigen::MatrixXd::Identity(m.rows(), m.cols()));
    w_.resize(s.dofs(), static_cast<Eigen::Index>(s.contacts.size()));
    for (std::size_t c = 0; c < s.contacts.size(); ++c)
        w_.col(static_cast<Eigen::Index>(c)) = s.contact_direction(s.contacts[c]);
}

Eigen::VectorXd StabilityAnalyser::start_state(const SolutionPoint& point) {
    Eigen::VectorXd state = exact_start_state(hb_, point);
    const System& s = hb_.system();
    const int n = s.dofs(), nc = static_cast<int>(s.contacts.size());
    for (int c = 0; c < nc; ++c) {
        const FrictionLaw law = s.contacts[static_cast<std::size_t>(c)].law;
        if (contact_law(law).time_state() != TimeState::bristle) continue;
        double z, rate;
        at_phase(hb_.state(point.x, c), 0.0, z, rate);
        state(2 * n + c) = z;
        state(2 * n + nc + c) = 0;
    }
    return state;
}

Eigen::VectorXcd StabilityAnalyser::hill(const SolutionPoint& point) {
    if (!refusal_.empty() || !smooth_) return {};
    return sorted_hill(Variational(hb_, minv_, w_, point), hb_.fourier(), options_.max_hill_size);
}

Eigen::MatrixXd StabilityAnalyser::monodromy(const SolutionPoint& point) {
    if (!refusal_.empty() || !smooth_) return {};
    const Variational v(hb_, minv_, w_, point);
    Eigen::MatrixXd phi;
    std::string failure;
    if (!MonodromyIntegrator(v, options_.integration_tolerance).run(phi, failure)) return {};
    return phi;
}

FloquetResult StabilityAnalyser::operator()(const SolutionPoint& point) {
    FloquetResult r;
    if (!refusal_.empty()) {
        r.message = refusal_;
        return r;
    }
    if (!smooth_) {
        // Coulomb / Jenkins: the event-exact orbit from the HB state at t = 0.
        const ExactOrbit orbit = exact_periodic_orbit(hb_.system(), point.omega, start_state(point));
        r.route = "exact";
        r.multipliers = orbit.multipliers;
        r.margin = orbit.max_multiplier;
        if (!orbit.converged) {
            r.stability = Stability::uncertain;
            r.message = "the exact solver did not converge from the HB state: " + orbit.message;
            return r;
        }
        // The HB orbit's y_max on the AFT grid against the exact one (all DOFs).
        const Eigen::MatrixXd y = hb_.dofs(point.x, point.omega);
        double gap = 0.0, scale = 0.0;
        Eigen::VectorXd samples(hb_.time_samples());
        for (int i = 0; i < y.cols(); ++i) {
            hb_.fourier().to_time(y.col(i), samples);
            const double exact = orbit.y_max[static_cast<std::size_t>(i)];
            gap = std::max(gap, std::abs(samples.cwiseAbs().maxCoeff() - exact));
            scale = std::max(scale, exact);
        }
        if (gap > options_.exact_gap * scale) {
            r.stability = Stability::uncertain;
            r.message = "the exact orbit found from the HB state differs from it (y_max gap " +
                        format_number(gap / scale) + ")";
            return r;
        }
        r.stability = orbit.stable ? Stability::stable : Stability::unstable;
        return r;
    }
    const bool use_hill = options_.method != StabilityMethod::monodromy;
    const bool use_monodromy = options_.method != StabilityMethod::hill;
    const Variational v(hb_, minv_, w_, point);  // one linearisation for both routes
    if (use_hill) {
        r.hill_multipliers = sorted_hill(v, hb_.fourier(), options_.max_hill_size);
        r.hill_margin = largest_modulus(r.hill_multipliers);
    }
    std::string failure;
    if (use_monodromy) {
        Eigen::MatrixXd phi;
        if (MonodromyIntegrator(v, options_.integration_tolerance).run(phi, failure)) {
            r.monodromy_multipliers = eigenvalues(phi);
            r.monodromy_margin = largest_modulus(r.monodromy_multipliers);
        }
    }
    const bool has_hill = r.hill_multipliers.size() > 0, has_monodromy = r.monodromy_multipliers.size() > 0;
    r.route = has_hill && has_monodromy ? "hill+monodromy" : has_hill ? "hill" : has_monodromy ? "monodromy" : "";
    if (has_monodromy) {
        r.multipliers = r.monodromy_multipliers;
        r.margin = r.monodromy_margin;
    } else if (has_hill) {
        r.multipliers = r.hill_multipliers;
        r.margin = r.hill_margin;
    }
    if (!has_hill && !has_monodromy) {
        r.stability = failure.empty() ? Stability::not_computed : Stability::uncertain;
        r.message = !failure.empty() ? failure
                                     : "Hill's matrix is larger than stability max_hill_size = " +
                                           std::to_string(options_.max_hill_size) + " rows";
        return r;
    }
    if (use_monodromy && !has_monodromy) {
        r.stability = Stability::uncertain;
        r.message = failure;
        return r;
    }
    const Stability h = has_hill ? verdict(r.hill_margin, options_.tolerance) : Stability::not_computed;
    const Stability m = has_monodromy ? verdict(r.monodromy_margin, options_.tolerance) : Stability::not_computed;
    if (has_hill && has_monodromy && h != m) {
        r.stability = Stability::uncertain;
        r.message = "Hill's sorted multipliers (largest " + format_number(r.hill_margin) +
                    ") and the monodromy's (largest " + format_number(r.monodromy_margin) + ") disagree";
        return r;
    }
    r.stability = has_monodromy ? m : h;
    return r;
}

std::string BranchStability::summary() const {
    std::string s = "stability: " + std::to_string(stable) + " stable, " + std::to_string(unstable_points) +
                    " unstable, " + std::to_string(uncertain) + " uncertain";
    if (not_computed > 0) s += ", " + std::to_string(not_computed) + " not computed";
    s += "; " + std::to_string(unstable.size()) + " unstable interval(s)";
    if (!bifurcations.empty()) s += ", " + std::to_string(bifurcations.size()) + " bifurcation(s)";
    if (both_confident > 0)
        s += "; Hill's sorting disagreed with the monodromy at " + std::to_string(sorting_disagreements) + " of " +
             std::to_string(both_confident) + " confident points";
    s += " (" + format_number(seconds) + " s)";
    return s;
}

namespace {

/// Unstable multipliers of each kind: real > 0, real < 0, complex.
struct Crossings {
    int positive = 0, negative = 0, complex = 0;
    double positive_max = 0, negative_max = 0, complex_max = 0;  // largest modulus of each kind
};
Crossings classify(const Eigen::VectorXcd& mu, double tolerance) {
    Crossings c;
    for (Eigen::Index k = 0; k < mu.size(); ++k) {
        const double m = std::abs(mu(k));
        const bool real = std::abs(mu(k).imag()) <= 1e-9 * std::max(1.0, m);
        double& largest = !real ? c.complex_max : mu(k).real() > 0 ? c.positive_max : c.negative_max;
        largest = std::max(largest, m);
        if (m <= 1.0 + tolerance) continue;
        if (!real)
            ++c.complex;
        else if (mu(k).real() > 0)
            ++c.positive;
        else
            ++c.negative;
    }
    return c;
}

}  // namespace

void find_bifurcations(const std::vector<SolutionPoint>& points, double tolerance, BranchStability& b) {
    if (b.points.size() != points.size())
        throw InvalidInput("stability verdicts = " + std::to_string(b.points.size()) +
                           " do not match the points = " + std::to_string(points.size()) + ": allowed one per point");
    b.unstable.clear();
    b.bifurcations.clear();
    // Unstable intervals and bifurcations along each branch (samples excluded).
    bool open = false;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const SolutionPoint& p = points[k];
        if (p.kind == PointKind::sample) continue;
        const bool unstable = b.points[k].stability == Stability::unstable;
        if (open && (!unstable || p.branch != b.unstable.back().branch)) open = false;
        if (unstable) {
            if (!open) b.unstable.push_back({p.omega, p.omega, p.branch});
            b.unstable.back().omega_to = p.omega;
            open = true;
        }
    }
    // Between consecutive points with a verdict (uncertain ones skipped: their multipliers
    // are in doubt) on one branch.
    auto certain = [&](std::size_t k) {
        const Stability s = b.points[k].stability;
        return points[k].kind != PointKind::sample && b.points[k].multipliers.size() > 0 &&
               (s == Stability::stable || s == Stability::unstable);
    };
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (!certain(k)) continue;
        std::size_t next = k + 1;
        while (next < points.size() && points[next].branch == points[k].branch && !certain(next)) ++next;
        if (next >= points.size() || !certain(next) || points[next].branch != points[k].branch) continue;
        const SolutionPoint &p = points[k], &q = points[next];
        const Eigen::VectorXcd &a = b.points[k].multipliers, &c = b.points[next].multipliers;
        const Crossings x = classify(a, tolerance), y = classify(c, tolerance);
        auto add = [&](const char* kind, double ma, double mc) {
            double omega = p.omega;
            if (std::abs(mc - ma) > 0.0) omega = p.omega + (1.0 - ma) / (mc - ma) * (q.omega - p.omega);
            if (!(std::isfinite(omega))) omega = p.omega;
            b.bifurcations.push_back({k, next, omega, kind, p.branch});
        };
        // Through +1: a fold where the branch turns between the two points (a located fold point
        // among them), else a branch point (symmetry breaking, or a nonsmooth jump of the
        // multipliers at a stick-slip transition).
        bool turns = false;
        for (std::size_t j = k; j <= next; ++j) turns = turns || points[j].kind == PointKind::fold;
        if (x.positive != y.positive) add(turns ? "fold" : "branch-point", x.positive_max, y.positive_max);
        if (x.negative != y.negative) add("period-doubling", x.negative_max, y.negative_max);
        if (x.complex != y.complex) add("neimark-sacker", x.complex_max, y.complex_max);
    }
}

void mark_bifurcations(const BranchStability& b, std::vector<SolutionPoint>& points) {
    for (const BranchStability::Bifurcation& f : b.bifurcations) {
        if (f.at >= points.size() || points[f.at].kind != PointKind::regular) continue;
        if (f.kind == "branch-point") points[f.at].kind = PointKind::branch_point;
        if (f.kind == "period-doubling") points[f.at].kind = PointKind::period_doubling;
        if (f.kind == "neimark-sacker") points[f.at].kind = PointKind::neimark_sacker;
    }
}

BranchStability analyse_branch_stability(HarmonicBalance& hb, const std::vector<SolutionPoint>& points,
                                         const StabilityOptions& options, const std::vector<ExactPoint>* polish) {
    const auto started = std::chrono::steady_clock::now();
    BranchStability b;
    StabilityAnalyser analyse(hb, options);
    b.points.reserve(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (polish && k < polish->size() && (*polish)[k].status != PolishStatus::off) {
            const ExactPoint& e = (*polish)[k];
            FloquetResult r;
            r.route = "exact";
            if (e.status == PolishStatus::exact) {
                r.stability = e.stable ? Stability::stable : Stability::unstable;
                r.margin = e.max_multiplier;
                r.multipliers = e.multipliers;
            } else {
                r.stability = Stability::uncertain;
                r.message = "the exact polish failed here: " + e.message;
            }
            b.points.push_back(r);
        } else {
            b.points.push_back(analyse(points[k]));
        }
        const FloquetResult& r = b.points.back();
        switch (r.stability) {
            case Stability::stable: ++b.stable; break;
            case Stability::unstable: ++b.unstable_points; break;
            case Stability::uncertain: ++b.uncertain; break;
            case Stability::not_computed: ++b.not_computed; break;
        }
        if (points[k].kind != PointKind::fold && r.hill_multipliers.size() > 0 && r.monodromy_multipliers.size() > 0 &&
            std::abs(r.hill_margin - 1.0) > options.confidence && std::abs(r.monodromy_margin - 1.0) > options.confidence) {
            ++b.both_confident;
            if ((r.hill_margin > 1.0) != (r.monodromy_margin > 1.0)) ++b.sorting_disagreements;
        }
    }
    find_bifurcations(points, options.tolerance, b);
    b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return b;
}

}  // namespace hbf
