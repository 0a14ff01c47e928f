// hbfriction — nonlinear modes by the extended periodic motion concept (modes.hpp).
#include "hbf/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/static_state.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {

Eigen::MatrixXd dense_or_zero(const SparseMatrix& matrix, int n) {
    if (matrix.rows() != n || matrix.cols() != n) return Eigen::MatrixXd::Zero(n, n);
    return Eigen::MatrixXd(matrix);
}

double infinity_norm(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

std::vector<LinearMode> stuck_modes(const System& system) {
    system.validate();
    const int n = system.dofs();
    const Eigen::MatrixXd mass = dense_or_zero(system.mass, n);
    Eigen::MatrixXd stiffness = dense_or_zero(system.stiffness, n), damping = dense_or_zero(system.damping, n);
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);
    std::vector<Eigen::VectorXd> rigid;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Eigen::MatrixXd directions = system.contact_directions(system.contacts[c]);
        for (Eigen::Index j = 0; j < directions.cols() && j < static_cast<Eigen::Index>(elements[c].size()); ++j) {
            const StuckElement& e = elements[c][static_cast<std::size_t>(j)];
            const Eigen::VectorXd w = directions.col(j);
            if (e.rigid) {
                rigid.push_back(w);
            } else {
                stiffness += e.stiffness * w * w.transpose();
                damping += e.damping * w * w.transpose();
            }
        }
    }
    // The motions the rigid contacts allow: an orthonormal basis T of {y : w^T y = 0}.
    Eigen::MatrixXd basis = Eigen::MatrixXd::Identity(n, n);
    if (!rigid.empty()) {
        Eigen::MatrixXd w(n, static_cast<Eigen::Index>(rigid.size()));
        for (std::size_t j = 0; j < rigid.size(); ++j) w.col(static_cast<Eigen::Index>(j)) = rigid[j];
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(w, Eigen::ComputeFullU);
        const auto rank = svd.rank();
        if (rank >= n) throw InvalidInput("the stuck structure has no motion: its rigid (exact Coulomb) contacts constrain every DOF");
        basis = svd.matrixU().rightCols(n - rank);
    }
    Eigen::MatrixXd mr = basis.transpose() * mass * basis, kr = basis.transpose() * stiffness * basis;
    mr = 0.5 * (mr + mr.transpose()).eval();
    kr = 0.5 * (kr + kr.transpose()).eval();
    std::vector<LinearMode> modes;
    if (Eigen::LLT<Eigen::MatrixXd>(mr).info() == Eigen::Success) {
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(kr, mr);  // K v = lambda M v, v^T M v = 1
        if (solver.info() != Eigen::Success) throw InvalidInput("the stuck structure's eigenproblem did not converge");
        const double largest = std::max(solver.eigenvalues().cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
        for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j) {
            LinearMode m;
            const double lambda = solver.eigenvalues()(j);
            // Rigid where lambda is at the eigensolver's rounding of the largest (64 eps): a stiff
            // penalty contact (k_n / k = 1e12, common in FE practice) leaves the structure's own
            // modes 1e-12 of the largest, and they are not rigid.
            m.omega = lambda > 64.0 * std::numeric_limits<double>::epsilon() * largest ? std::sqrt(lambda) : 0.0;
            m.shape = basis * solver.eigenvectors().col(j);
            modes.push_back(m);
        }
    } else if (Eigen::LLT<Eigen::MatrixXd>(kr).info() == Eigen::Success) {
        // Massless DOFs: M v = mu K v (mu = 1 / lambda); mu = 0 are the massless directions.
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(mr, kr);
        if (solver.info() != Eigen::Success) throw InvalidInput("the stuck structure's eigenproblem did not converge");
        const double largest = solver.eigenvalues().maxCoeff();
        for (Eigen::Index j = solver.eigenvalues().size() - 1; j >= 0; --j) {
            const double mu = solver.eigenvalues()(j);
            if (!(mu > 1e-14 * largest)) continue;
            LinearMode m;
            m.omega = std::sqrt(1.0 / mu);
            m.shape = basis * solver.eigenvectors().col(j) / std::sqrt(mu);  // v^T K v = 1 -> phi^T M phi = 1
            modes.push_back(m);
        }
    } else {
        throw InvalidInput("the stuck structure's mass and stiffness matrices are both singular (a rigid-body "
                           "mode and massless DOFs): nonlinear modes need one of them positive definite");
    }
    for (std::size_t j = 0; j < modes.size(); ++j) {
        LinearMode& m = modes[j];
        m.index = static_cast<int>(j) + 1;
        // The Rayleigh quotient of the eigenvector: its error is the vector's squared. A dense
        // eigensolver on a finite-element K (entries to 1e10, condition ~N^4) gives the 200-DOF
        // beam's stuck frequency 3e-9 off; the quotient, 1e-11 (inverse iteration as reference).
        if (m.omega > 0.0) {
            const double quotient = m.shape.dot(stiffness * m.shape) / m.shape.dot(mass * m.shape);
            if (quotient > 0.0) m.omega = std::sqrt(quotient);
        }
        Eigen::Index largest = 0;
        m.shape.cwiseAbs().maxCoeff(&largest);
        if (m.shape(largest) < 0.0) m.shape = -m.shape;  // reproducible sign: the largest entry positive
        m.zeta = m.omega > 0.0 ? m.shape.dot(damping * m.shape) / (2.0 * m.omega) : 0.0;
    }
    return modes;
}

std::string to_string(ModeStatus status) {
    switch (status) {
        case ModeStatus::completed: return "completed";
        case ModeStatus::left_range: return "left_range";
        case ModeStatus::min_step: return "min_step";
        case ModeStatus::point_budget: return "point_budget";
        case ModeStatus::start_failed: return "start_failed";
    }
    return "unknown";
}

void ModeOptions::validate() const {
    if (near_frequency != 0.0 && !(near_frequency > 0.0 && std::isfinite(near_frequency)))
        throw InvalidInput("near_frequency = " + format_number(near_frequency) +
                           " is out of range: allowed > 0 (or 0: the mode by its index)");
    if (near_frequency == 0.0 && mode < 1) throw InvalidInput("mode = " + std::to_string(mode) + " is out of range: allowed >= 1");
    if (!(amplitude_min > 0.0 && std::isfinite(amplitude_min)))
        throw InvalidInput("amplitude_min = " + format_number(amplitude_min) + " is out of range: allowed > 0");
    if (!(amplitude_max > amplitude_min && std::isfinite(amplitude_max)))
        throw InvalidInput("amplitude_max = " + format_number(amplitude_max) + " is out of range: allowed > amplitude_min = " +
                           format_number(amplitude_min));
    if (!(max_step > 0.0 && max_step <= 1.0))
        throw InvalidInput("max_step = " + format_number(max_step) + " is out of range: allowed (0, 1] decades");
    if (!(initial_step > 0.0 && initial_step <= max_step))
        throw InvalidInput("initial_step = " + format_number(initial_step) + " is out of range: allowed (0, max_step = " +
                           format_number(max_step) + "] decades");
    if (!(min_step > 0.0 && min_step <= initial_step))
        throw InvalidInput("min_step = " + format_number(min_step) + " is out of range: allowed (0, initial_step]");
    if (!(max_omega_change > 0.0 && max_omega_change <= 1.0))
        throw InvalidInput("max_omega_change = " + format_number(max_omega_change) + " is out of range: allowed (0, 1]");
    if (max_points < 2 || max_points > 1000000)
        throw InvalidInput("max_points = " + std::to_string(max_points) + " is out of range: allowed 2..1000000");
    if (max_iterations < 1 || max_iterations > 1000)
        throw InvalidInput("max_iterations = " + std::to_string(max_iterations) + " is out of range: allowed 1..1000");
    if (!(tolerance >= CorrectorOptions::smallest_tolerance && tolerance <= CorrectorOptions::largest_tolerance))
        throw InvalidInput("tolerance = " + format_number(tolerance) + " is out of range: allowed " +
                           format_number(CorrectorOptions::smallest_tolerance) + ".." +
                           format_number(CorrectorOptions::largest_tolerance));
}

NonlinearModes::NonlinearModes(System system, const HarmonicBalanceOptions& hbo, const ModeOptions& options)
    : system_(std::move(system)), options_(options) {
    options_.validate();
    hbo.validate();
    if (hbo.odd_harmonics)
        throw InvalidInput("odd harmonics only is not available for nonlinear modes (the modal motion may have a mean "
                           "and even harmonics): allowed every harmonic");
    const std::vector<LinearMode> modes = stuck_modes(system_);
    const int count = static_cast<int>(modes.size());
    if (count == 0) throw InvalidInput("the stuck structure has no mode with mass");
    if (options_.near_frequency > 0.0) {
        int best = -1;
        for (int j = 0; j < count; ++j)
            if (modes[static_cast<std::size_t>(j)].omega > 0.0 &&
                (best < 0 || std::abs(modes[static_cast<std::size_t>(j)].omega - options_.near_frequency) <
                                 std::abs(modes[static_cast<std::size_t>(best)].omega - options_.near_frequency)))
                best = j;
        if (best < 0) throw InvalidInput("the stuck structure has only rigid-body modes (omega = 0)");
        linear_ = modes[static_cast<std::size_t>(best)];
        // A frequency far from every mode names none of them (it used to follow the nearest).
        if (std::abs(linear_.omega - options_.near_frequency) > 0.1 * options_.near_frequency) {
            std::string found;
            for (const LinearMode& m : modes)
                if (m.omega > 0.0 && found.size() < 200) found += (found.empty() ? "" : ", ") + format_number(m.omega);
            throw InvalidInput("near_frequency = " + format_number(options_.near_frequency) +
                               ": no mode of the stuck structure within 10 % of it (its modes at w = " + found +
                               (found.size() >= 200 ? ", ..." : "") + ")");
        }
    } else {
        if (options_.mode > count)
            throw InvalidInput("mode = " + std::to_string(options_.mode) + " is out of range: allowed 1.." +
                               std::to_string(count) + " (the stuck structure's modes)");
        linear_ = modes[static_cast<std::size_t>(options_.mode - 1)];
    }
    if (!(linear_.omega > 0.0))
        throw InvalidInput("mode " + std::to_string(linear_.index) +
                           " is a rigid-body mode of the stuck structure (omega = 0): a nonlinear mode needs an "
                           "oscillating linear mode; choose another mode");
    // The residual's own excitation is removed (residual): a unit force on DOF 1 at harmonic 1
    // only keeps HarmonicBalance's checks of a forced problem satisfied.
    System unforced = system_;
    unforced.excitation = Eigen::VectorXd::Zero(system_.dofs());
    unforced.excitation(0) = 1.0;
    unforced.excitation_harmonic = 1;
    hb_ = std::make_unique<HarmonicBalance>(unforced, mode_harmonic_balance(hbo, system_));
    condensed_ = hb_->formulation() == Formulation::condensed;
    guess_shape_ = linear_.shape;
    if (condensed_) {
        hb_->set_free_motion(0.0);  // the placeholder load dropped; xi set per evaluation
        std::vector<Eigen::VectorXd> directions;
        for (const Contact& c : system_.contacts) {
            const Eigen::MatrixXd w = system_.contact_directions(c);
            for (Eigen::Index j = 0; j < w.cols(); ++j) directions.push_back(w.col(j));
        }
        guess_shape_.resize(static_cast<Eigen::Index>(directions.size()));
        for (std::size_t a = 0; a < directions.size(); ++a)
            guess_shape_(static_cast<Eigen::Index>(a)) = directions[a].dot(linear_.shape);
    }
    m_phi_ = system_.mass * linear_.shape;
    force_unit_ = linear_.omega * linear_.omega * infinity_norm(m_phi_);
    phi_max_ = infinity_norm(linear_.shape);
    static_force_ = system_.static_load.size() ? infinity_norm(system_.static_load) : 0.0;
    for (const std::vector<StuckElement>& along : stuck_elements(system_))
        for (const StuckElement& e : along) static_force_ = std::max(static_force_, std::abs(e.offset));
}

void NonlinearModes::residual(const Eigen::VectorXd& x, double omega, double xi, double amplitude, Eigen::VectorXd& r,
                              Eigen::MatrixXd* jacobian) {
    if (condensed_) return residual_condensed(x, omega, xi, amplitude, r, jacobian);
    const int n = hb_->coefficients(), dofs = system_.dofs(), u = hb_->unknowns();
    Eigen::VectorXd structure, structure_omega;
    Eigen::MatrixXd structure_x;
    hb_->evaluate(x, omega, structure, jacobian ? &structure_x : nullptr, jacobian ? &structure_omega : nullptr);
    ++evaluations_;
    structure(1) += 1.0;  // the placeholder force on DOF 1's cos 1 row (constructor), removed
    const Eigen::Map<const Eigen::MatrixXd> y(x.data(), n, dofs);
    const Eigen::MatrixXd& d1 = hb_->fourier().derivative();
    const Eigen::MatrixXd d1ym = (d1 * y) * system_.mass;  // (D1 Y) M
    Eigen::Map<Eigen::MatrixXd>(structure.data(), n, dofs) -= xi * omega * d1ym;
    // Rows of the structure relative to the mode's inertial force (floored by the static loads'
    // rounding), the constraints relative to the amplitude.
    const double scale = std::max(amplitude * force_unit_, 1e-5 * static_force_);
    r.resize(u + 2);
    r.head(u) = structure / scale;
    // Amplitude: the M-norm of the first harmonic, sqrt(c1^T M c1 + s1^T M s1) = a; phase: the
    // modal coordinate's sine coefficient phi^T M s1 = 0.
    const Eigen::VectorXd m_cos1 = system_.mass * y.row(1).transpose(), m_sin1 = system_.mass * y.row(2).transpose();
    const double norm1 = std::sqrt(y.row(1).dot(m_cos1) + y.row(2).dot(m_sin1)), sin1 = y.row(2).dot(m_phi_);
    r(u) = (norm1 - amplitude) / amplitude;
    r(u + 1) = sin1 / amplitude;
    if (!jacobian) return;
    Eigen::MatrixXd& j = *jacobian;
    j.setZero(u + 2, u + 2);
    j.topLeftCorner(u, u) = structure_x;
    for (int k = 0; k < system_.mass.outerSize(); ++k)
        for (SparseMatrix::InnerIterator it(system_.mass, k); it; ++it)
            j.block(it.row() * n, it.col() * n, n, n) -= xi * omega * it.value() * d1;
    Eigen::VectorXd flat = Eigen::Map<const Eigen::VectorXd>(d1ym.data(), d1ym.size());
    j.col(u).head(u) = structure_omega;
    j.col(u).head(n * dofs) -= xi * flat;
    j.col(u + 1).head(n * dofs) = -omega * flat;
    j.topRows(u) /= scale;
    for (int i = 0; i < dofs; ++i) {
        if (norm1 > 0.0) {
            j(u, i * n + 1) = m_cos1(i) / (norm1 * amplitude);
            j(u, i * n + 2) = m_sin1(i) / (norm1 * amplitude);
        }
        j(u + 1, i * n + 2) = m_phi_(i) / amplitude;
    }
}

void NonlinearModes::residual_condensed(const Eigen::VectorXd& x, double omega, double xi, double amplitude,
                                        Eigen::VectorXd& r, Eigen::MatrixXd* jacobian) {
    const int u = hb_->unknowns();
    using Complex = std::complex<double>;
    const Eigen::VectorXcd m_phi = m_phi_.cast<Complex>();
    // The amplitude row's |Y_1|_M and the phase row's phi^T M s1 of y's first harmonic Y_1 =
    // -Z'_1^-1 W Lambda'_1 (the contacts' shifted forces: dofs()'s recovery; not through the
    // contacts' motion Q_1, which vanishes while an exact Coulomb contact sticks); with
    // `gradients` their derivatives in x (dY_1 = -Z'_1^-1 W dLambda'_1).
    struct Rows {
        double norm = std::numeric_limits<double>::quiet_NaN(), sine = std::numeric_limits<double>::quiet_NaN();
        Eigen::RowVectorXd norm_x, sine_x;
    };
    // The forces at omega once (they do not depend on xi); at omega -+ h again (velocity laws).
    Eigen::MatrixXcd d_lambda;
    const Eigen::VectorXcd lambda_here = hb_->shifted_force_harmonic(x, omega, 1, jacobian ? &d_lambda : nullptr);
    auto rows = [&](double at_omega, bool gradients) {  // gradients: at omega only
        Rows out;
        const Eigen::VectorXcd lambda =
            at_omega == omega ? lambda_here : hb_->shifted_force_harmonic(x, at_omega, 1, nullptr);
        const Eigen::MatrixXcd response = hb_->contact_response(1, at_omega);
        if (response.size() == 0) return out;
        const Eigen::VectorXcd y1 = -(response * lambda);
        Eigen::VectorXcd my(y1.size());
        my.real() = system_.mass * y1.real();
        my.imag() = system_.mass * y1.imag();
        out.norm = std::sqrt(std::max(0.0, y1.dot(my).real()));  // Y^H M Y
        out.sine = -(m_phi.dot(y1)).imag();                        // s1 = -Im Y_1
        if (gradients) {
            // (M Y)^H dY = v^H dLambda with v = -R^H M Y; phi^T M dY = b^T dLambda with b = -R^T M phi.
            const Eigen::VectorXcd v = -(response.adjoint() * my), b = -(response.transpose() * m_phi);
            out.norm_x = out.norm > 0.0 ? Eigen::RowVectorXd((v.adjoint() * d_lambda).real() / out.norm)
                                        : Eigen::RowVectorXd::Zero(u);
            out.sine_x = -(b.transpose() * d_lambda).imag();
        }
        return out;
    };
    const double scale = std::max(amplitude * force_unit_, 1e-5 * static_force_);
    auto structure = [&](double at_xi, Eigen::VectorXd& out, Eigen::MatrixXd* jx, Eigen::VectorXd* jw) {
        hb_->set_free_motion(at_xi);
        hb_->evaluate(x, omega, out, jx, jw);
        ++evaluations_;
    };
    // Central differences in xi first (they move the receptances' damping), then the point.
    const double h_xi = 1e-6 * std::max(linear_.omega, std::abs(xi)), h_omega = 1e-6 * omega;
    Eigen::VectorXd d_xi;
    Rows xi_up, xi_down;
    if (jacobian) {
        Eigen::VectorXd up, down;
        structure(xi + h_xi, up, nullptr, nullptr);
        xi_up = rows(omega, false);
        structure(xi - h_xi, down, nullptr, nullptr);
        xi_down = rows(omega, false);
        d_xi = (up - down) / (2.0 * h_xi);
    }
    Eigen::VectorXd structure_r, structure_omega;
    Eigen::MatrixXd structure_x;
    structure(xi, structure_r, jacobian ? &structure_x : nullptr, jacobian ? &structure_omega : nullptr);
    const Rows here = rows(omega, jacobian != nullptr);
    r.resize(u + 2);
    r.head(u) = structure_r / scale;
    r(u) = (here.norm - amplitude) / amplitude;
    r(u + 1) = here.sine / amplitude;
    if (!jacobian) return;
    const Rows omega_up = rows(omega + h_omega, false), omega_down = rows(omega - h_omega, false);
    Eigen::MatrixXd& j = *jacobian;
    j.setZero(u + 2, u + 2);
    j.topLeftCorner(u, u) = structure_x / scale;
    j.col(u).head(u) = structure_omega / scale;
    j.col(u + 1).head(u) = d_xi / scale;
    if (here.norm_x.size() != u) return;  // Z'_1 singular: the rows are NaN, Newton stops
    j.row(u).head(u) = here.norm_x / amplitude;
    j.row(u + 1).head(u) = here.sine_x / amplitude;
    j(u, u) = (omega_up.norm - omega_down.norm) / (2.0 * h_omega * amplitude);
    j(u + 1, u) = (omega_up.sine - omega_down.sine) / (2.0 * h_omega * amplitude);
    j(u, u + 1) = (xi_up.norm - xi_down.norm) / (2.0 * h_xi * amplitude);
    j(u + 1, u + 1) = (xi_up.sine - xi_down.sine) / (2.0 * h_xi * amplitude);
}

Eigen::MatrixXd NonlinearModes::motion(const ModePoint& point) {
    if (condensed_) hb_->set_free_motion(point.xi);
    return hb_->dofs(point.x, point.omega);
}

bool NonlinearModes::solve(ModePoint& point) { return correct(point, nullptr, nullptr); }

Eigen::VectorXd NonlinearModes::column_scale(const ModePoint& point) const {
    const int u = hb_->unknowns(), n = hb_->coefficients();
    const double displacement = point.amplitude * phi_max_;
    Eigen::VectorXd scale = Eigen::VectorXd::Constant(u + 3, displacement);
    // Internal states (Dahl's z, exact Coulomb's multiplier: a force) by their own size.
    int offset = n * static_cast<int>(guess_shape_.size());
    for (int c = 0; c < static_cast<int>(system_.contacts.size()); ++c) {
        const auto states = static_cast<int>(hb_->state(point.x, c).size());
        if (states == 0) continue;
        scale.segment(offset, states).setConstant(std::max(displacement, infinity_norm(point.x.segment(offset, states))));
        offset += states;
    }
    scale(u) = scale(u + 1) = linear_.omega;
    scale(u + 2) = 1.0;
    return scale;
}

bool NonlinearModes::correct(ModePoint& point, const Eigen::VectorXd* tangent, const Eigen::VectorXd* predicted) {
    const int u = hb_->unknowns();
    const bool arclength = tangent != nullptr;
    const int size = arclength ? u + 3 : u + 2;
    // Columns scaled to comparable sizes: x by a |phi|_inf, omega and xi by the linear
    // frequency, log10 a by 1 (the arclength's coordinates; the scale of the predictor's point).
    const Eigen::VectorXd scale = column_scale(point).head(size);
    Eigen::VectorXd v(size);
    v.head(u) = point.x;
    v(u) = point.omega;
    v(u + 1) = point.xi;
    if (arclength) v(u + 2) = std::log10(point.amplitude);
    Eigen::VectorXd r, trial_r;
    Eigen::MatrixXd j;
    // The residual of v: G, and along the arclength t . (v - v_predicted) / scale.
    auto evaluate = [&](const Eigen::VectorXd& at, Eigen::VectorXd& out, Eigen::MatrixXd* jacobian) {
        const double amplitude = arclength ? std::pow(10.0, at(u + 2)) : point.amplitude;
        Eigen::MatrixXd jg;
        Eigen::VectorXd g;
        residual(at.head(u), at(u), at(u + 1), amplitude, g, jacobian ? &jg : nullptr);
        out.resize(size);
        out.head(u + 2) = g;
        if (!arclength) {
            if (jacobian) *jacobian = std::move(jg);
            return;
        }
        out(u + 2) = tangent->dot((at - *predicted).cwiseQuotient(scale));
        if (!jacobian) return;
        jacobian->setZero(size, size);
        jacobian->topLeftCorner(u + 2, u + 2) = jg;
        // dG/d(log10 a): the structure's rows are divided by a force_unit (unless floored), the
        // constraints are |Y_1|_M / a - 1 and phi^T M s1 / a.
        const double ln10 = std::log(10.0);
        if (amplitude * force_unit_ >= 1e-5 * static_force_) jacobian->col(u + 2).head(u) = -ln10 * g.head(u);
        (*jacobian)(u, u + 2) = -ln10 * (g(u) + 1.0);
        (*jacobian)(u + 1, u + 2) = -ln10 * g(u + 1);
        jacobian->row(u + 2) = tangent->cwiseQuotient(scale).transpose();
    };
    for (int iteration = 0;; ++iteration) {
        evaluate(v, r, &j);
        const double norm = infinity_norm(r);
        point.iterations = iteration;
        point.residual = infinity_norm(r.head(u + 2));
        if (!std::isfinite(norm)) return false;
        if (norm <= options_.tolerance) break;
        if (iteration >= options_.max_iterations) return false;
        const Eigen::VectorXd step =
            scale.asDiagonal() * Eigen::VectorXd(Eigen::PartialPivLU<Eigen::MatrixXd>(j * scale.asDiagonal()).solve(-r));
        if (!step.allFinite()) return false;
        // Backtracking on max |r| (the laws are not smooth: a full step can overshoot a switch).
        double length = 1.0;
        bool accepted = false;
        for (int halving = 0; halving < 12 && !accepted; ++halving, length *= 0.5) {
            const Eigen::VectorXd trial = v + length * step;
            if (!(trial(u) > 0.0)) continue;
            evaluate(trial, trial_r, nullptr);
            if (infinity_norm(trial_r) < norm) {
                v = trial;
                accepted = true;
            }
        }
        if (!accepted) return false;
    }
    point.x = v.head(u);
    point.omega = v(u);
    point.xi = v(u + 1);
    if (arclength) point.amplitude = std::pow(10.0, v(u + 2));
    return true;
}

Eigen::VectorXd NonlinearModes::tangent(const ModePoint& point, const Eigen::VectorXd& previous) {
    // The null vector of [dG/d(x, omega, xi), dG/d(log10 a)] in the scaled coordinates, from the
    // bordered system [J D; previous^T] t = e_last, oriented along `previous`.
    const int u = hb_->unknowns();
    Eigen::VectorXd g;
    Eigen::MatrixXd jg;
    residual(point.x, point.omega, point.xi, point.amplitude, g, &jg);
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(u + 3, u + 3);
    j.topLeftCorner(u + 2, u + 2) = jg;
    const double ln10 = std::log(10.0);
    if (point.amplitude * force_unit_ >= 1e-5 * static_force_) j.col(u + 2).head(u) = -ln10 * g.head(u);
    j(u, u + 2) = -ln10 * (g(u) + 1.0);
    j(u + 1, u + 2) = -ln10 * g(u + 1);
    const Eigen::VectorXd scale = column_scale(point);
    j.topRows(u + 2) = j.topRows(u + 2) * scale.asDiagonal();
    j.row(u + 2) = previous.transpose();
    Eigen::VectorXd e = Eigen::VectorXd::Zero(u + 3);
    e(u + 2) = 1.0;
    Eigen::VectorXd t = Eigen::PartialPivLU<Eigen::MatrixXd>(j).solve(e);
    if (!t.allFinite() || t.norm() == 0.0) return previous;
    t.normalize();
    if (t.dot(previous) < 0.0) t = -t;
    return t;
}

ModePoint NonlinearModes::linear_guess(double amplitude) {
    ModePoint p;
    p.amplitude = amplitude;
    p.omega = linear_.omega;
    p.xi = 2.0 * linear_.omega * linear_.zeta;
    const int n = hb_->coefficients(), coordinates = static_cast<int>(guess_shape_.size());
    p.x = hb_->linear_guess(linear_.omega);  // harmonic 0: the static state; the rest replaced
    for (int i = 0; i < coordinates; ++i) {  // every DOF, or (condensed) every contact direction
        p.x.segment(i * n + 1, n - 1).setZero();
        p.x(i * n + 1) = amplitude * guess_shape_(i);
    }
    // Internal states (Dahl, LuGre) follow q while pre-sliding: z = q on the harmonics >= 1.
    int offset = n * coordinates;
    for (int c = 0; c < static_cast<int>(system_.contacts.size()); ++c) {
        const Eigen::VectorXd z = hb_->state(p.x, c);
        if (z.size() == 0) continue;
        const Eigen::VectorXd q = hb_->relative(p.x, c);
        for (Eigen::Index s = 0; s < z.size() / n; ++s)
            if ((s + 1) * n <= q.size()) p.x.segment(offset + s * n + 1, n - 1) = q.segment(s * n + 1, n - 1);
        offset += static_cast<int>(z.size());
    }
    if (condensed_) {
        // Condensed, the motion is recovered from the contacts' forces, and a rigid (exact
        // Coulomb) contact carries the stuck mode by its multiplier alone (q = 0): its harmonic 1
        // from the structure's balance Z_1 a phi + W Lambda_1 = 0 (Z_1 = K - w0^2 M + i w0 (C -
        // xi0 M); least squares over the contacts' directions, exact for rigid ones alone).
        const std::vector<std::vector<StuckElement>> elements = stuck_elements(system_);
        const int dofs = system_.dofs(), signals = coordinates;
        Eigen::MatrixXd w(dofs, signals);
        std::vector<int> first_signal;
        bool rigid = false;
        for (std::size_t c = 0, a = 0; c < system_.contacts.size(); ++c) {
            const Eigen::MatrixXd directions = system_.contact_directions(system_.contacts[c]);
            first_signal.push_back(static_cast<int>(a));
            for (Eigen::Index j = 0; j < directions.cols(); ++j, ++a) w.col(static_cast<Eigen::Index>(a)) = directions.col(j);
            for (const StuckElement& e : elements[c]) rigid = rigid || e.rigid;
        }
        if (rigid) {
            const Eigen::VectorXd y = amplitude * linear_.shape;
            const Eigen::VectorXd real = system_.stiffness * y - p.omega * p.omega * (system_.mass * y);
            const Eigen::VectorXd imag = p.omega * (system_.damping * y - p.xi * (system_.mass * y));
            const Eigen::LDLT<Eigen::MatrixXd> normal(w.transpose() * w);
            const Eigen::VectorXd cosine = -normal.solve(w.transpose() * real), sine = normal.solve(w.transpose() * imag);
            offset = n * coordinates;
            for (std::size_t c = 0; c < system_.contacts.size(); ++c) {
                // One multiplier signal per direction (exact Coulomb; law unilateral pressed shut).
                const auto states = hb_->state(p.x, static_cast<int>(c)).size();
                const auto count = static_cast<Eigen::Index>(elements[c].size());
                bool all_rigid = count > 0;
                for (const StuckElement& e : elements[c]) all_rigid = all_rigid && e.rigid;
                if (all_rigid && states == n * count)
                    for (Eigen::Index j = 0; j < count; ++j) {
                        p.x.segment(offset + j * n + 1, n - 1).setZero();
                        p.x(offset + j * n + 1) = cosine(first_signal[c] + j);
                        p.x(offset + j * n + 2) = sine(first_signal[c] + j);
                    }
                offset += static_cast<int>(states);
            }
        }
    }
    return p;
}

Backbone NonlinearModes::follow() {
    detail::Stopwatch watch;
    Backbone b;
    b.linear = linear_;
    const long long evaluations = evaluations_;
    const int u = hb_->unknowns();
    const double first = std::log10(options_.amplitude_min), last = std::log10(options_.amplitude_max);
    ModePoint start = linear_guess(options_.amplitude_min);
    if (!solve(start)) {
        b.status = ModeStatus::start_failed;
        b.message = "the first point (a = " + format_number(options_.amplitude_min) +
                    ") did not converge from the linear mode: residual " + format_number(start.residual) +
                    (start.iterations == 0 ? std::string(" at the linear mode, which no Newton step (halved 12 times) reduced")
                                           : " after " + std::to_string(start.iterations) + " Newton iterations");
        const PenaltyDiagnostics penalties = penalty_diagnostics(system_, hb_->rest_state());
        for (const std::string& line : penalties.relieved) b.message += "; " + line;
        for (const std::string& line : penalties.stiff) b.message += "; " + line;
        b.evaluations = evaluations_ - evaluations;
        b.seconds = watch.lap();
        return b;
    }
    b.points.push_back(start);
    if (options_.progress) options_.progress(start.amplitude, 1);
    // Pseudo-arclength in the scaled coordinates (x / (a |phi|), omega / w0, xi / w0, log10 a):
    // the backbone may turn back in a (a modal interaction, a contact releasing a second mode).
    Eigen::VectorXd direction = Eigen::VectorXd::Zero(u + 3);
    direction(u + 2) = 1.0;
    Eigen::VectorXd t = tangent(start, direction);
    double h = options_.initial_step;
    const double corner_step = std::max(1e-4, 16.0 * options_.min_step);
    while (true) {
        const ModePoint& previous = b.points.back();
        const double s = std::log10(previous.amplitude);
        if (s >= last - 1e-12) break;
        if (static_cast<int>(b.points.size()) >= options_.max_points) {
            b.status = ModeStatus::point_budget;
            b.message = "point budget " + std::to_string(options_.max_points) + " reached at a = " +
                        format_number(previous.amplitude);
            break;
        }
        const Eigen::VectorXd scale = column_scale(previous);
        Eigen::VectorXd v(u + 3);
        v.head(u) = previous.x;
        v(u) = previous.omega;
        v(u + 1) = previous.xi;
        v(u + 2) = s;
        const Eigen::VectorXd predicted = v + h * scale.cwiseProduct(t);
        ModePoint trial;
        trial.x = predicted.head(u);
        trial.omega = predicted(u);
        trial.xi = predicted(u + 1);
        trial.amplitude = std::pow(10.0, predicted(u + 2));
        bool ok = trial.omega > 0.0 && correct(trial, &t, &predicted) &&
                  std::abs(trial.omega - previous.omega) <= options_.max_omega_change * previous.omega;
        Eigen::VectorXd next;
        bool corner = false;
        if (ok) {
            next = tangent(trial, t);
            // A sharper turn than 0.3 rad: a smaller step; still at a short step, a corner of
            // the backbone (a stick/slip switch: its tangent jumps), crossed.
            corner = next.dot(t) < std::cos(0.3);
            ok = !corner || h <= corner_step;
        }
        if (!ok) {
            ++b.failed_steps;
            h *= 0.5;
            if (h < options_.min_step) {
                b.status = ModeStatus::min_step;
                b.message = "no point beyond a = " + format_number(previous.amplitude) + " (omega = " +
                            format_number(previous.omega) + "): the corrector failed down to the step " +
                            format_number(2.0 * h) + " (residual " + format_number(trial.residual) + ")";
                break;
            }
            continue;
        }
        if (std::log10(trial.amplitude) > last) {
            // Past a_max: the point at a_max itself, from the chord's interpolation.
            const double f = (last - s) / (std::log10(trial.amplitude) - s);
            ModePoint end;
            end.amplitude = options_.amplitude_max;
            end.x = previous.x + f * (trial.x - previous.x);
            end.omega = previous.omega + f * (trial.omega - previous.omega);
            end.xi = previous.xi + f * (trial.xi - previous.xi);
            if (solve(end)) trial = end;
            else {
                ++b.failed_steps;
                h *= 0.5;
                if (h >= options_.min_step) continue;
                b.status = ModeStatus::min_step;
                b.message = "the point at a_max = " + format_number(options_.amplitude_max) + " did not converge";
                break;
            }
        }
        if (std::log10(trial.amplitude) < first) {
            b.status = ModeStatus::left_range;
            b.message = "the backbone turned back below a_min = " + format_number(options_.amplitude_min) +
                        " at omega = " + format_number(trial.omega);
            break;
        }
        trial.step = h;
        if (corner) ++b.corners;
        b.points.push_back(trial);
        t = next;
        if (options_.progress) options_.progress(trial.amplitude, static_cast<int>(b.points.size()));
        if (trial.iterations <= 4) h = std::min(1.5 * h, options_.max_step);
    }
    b.evaluations = evaluations_ - evaluations;
    b.seconds = watch.lap();
    return b;
}

ExactModeCheck NonlinearModes::exact_check(const ModePoint& point) {
    ExactModeCheck out;
    const int dofs = system_.dofs(), contacts = static_cast<int>(system_.contacts.size());
    for (const Contact& c : system_.contacts)
        if ((c.law != FrictionLaw::coulomb && c.law != FrictionLaw::jenkins) || system_.contact_directions(c).cols() != 1) {
            out.message = "the event-exact solver covers exact Coulomb and Jenkins contacts along one direction only";
            return out;
        }
    if (contacts == 0 || dofs > exact_solver_max_dofs ||
        Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd(system_.mass)).info() != Eigen::Success) {
        out.message = "the event-exact flow needs contacts, M positive definite and at most " +
                      std::to_string(exact_solver_max_dofs) + " DOFs";
        return out;
    }
    // The section: the middle of the longest stretch of samples where every contact slips.
    const int nt = hb_->time_samples();
    const Eigen::MatrixXd y = motion(point);
    std::vector<bool> slipping(static_cast<std::size_t>(nt), true);
    for (int c = 0; c < contacts; ++c) {
        const Eigen::VectorXd stick = hb_->stick_indicator(point.x, point.omega, c);
        for (int j = 0; j < nt; ++j) slipping[static_cast<std::size_t>(j)] = slipping[static_cast<std::size_t>(j)] && stick(j) >= 0.0;
    }
    int best = 0, best_end = -1;
    for (int j = 0, run = 0; j < 2 * nt; ++j) {  // twice round: a stretch across theta = 0
        run = slipping[static_cast<std::size_t>(j % nt)] ? std::min(run + 1, nt) : 0;
        if (run > best) {
            best = run;
            best_end = j;
        }
    }
    if (best < 4) {
        out.message = "no contact slips over the period (permanent stick: the linear mode of the stuck structure)";
        return out;
    }
    const double theta0 = 2.0 * M_PI * ((best_end - best / 2) % nt) / nt;
    // The harmonic-balance orbit at theta0: y and y' = omega dy/dtheta.
    Eigen::VectorXd y0 = y.row(0).transpose(), v0 = Eigen::VectorXd::Zero(dofs);
    for (int k = 1; k <= hb_->harmonics(); ++k) {
        const double c = std::cos(k * theta0), s = std::sin(k * theta0);
        y0 += c * y.row(2 * k - 1).transpose() + s * y.row(2 * k).transpose();
        v0 += point.omega * k * (-s * y.row(2 * k - 1).transpose() + c * y.row(2 * k).transpose());
    }
    const double modal_position = m_phi_.dot(y0), modal_velocity = m_phi_.dot(v0);
    std::vector<Eigen::VectorXd> w;
    for (const Contact& c : system_.contacts) w.push_back(system_.contact_directions(c).col(0));
    // The exact flow's state [y, y', internal, mode] from (y, y'): every contact slips at t = 0
    // with the sign of its velocity, a Jenkins slider at q - mode F_c / k_t.
    auto state_of = [&](const Eigen::VectorXd& yy, const Eigen::VectorXd& vv, bool& ok) {
        Eigen::VectorXd z(2 * dofs + 2 * contacts);
        z << yy, vv, Eigen::VectorXd::Zero(2 * contacts);
        ok = true;
        for (int c = 0; c < contacts; ++c) {
            const double v = w[static_cast<std::size_t>(c)].dot(vv);
            const Contact& contact = system_.contacts[static_cast<std::size_t>(c)];
            const double mode = v > 0.0 ? 1.0 : -1.0;
            ok = ok && v != 0.0;
            if (contact.law == FrictionLaw::jenkins)
                z(2 * dofs + c) = w[static_cast<std::size_t>(c)].dot(yy) - mode * contact.friction_limit / contact.stiffness;
            z(2 * dofs + contacts + c) = mode;
        }
        return z;
    };
    System free = system_;
    free.excitation = Eigen::VectorXd::Zero(dofs);
    const SparseMatrix damping = system_.damping.rows() == dofs ? system_.damping : SparseMatrix(dofs, dofs);
    auto flow = [&](const Eigen::VectorXd& z, double omega, double xi) {
        free.damping = damping - xi * system_.mass;
        return exact_flow(free, omega, z, 1);
    };
    const int size = 2 * dofs;
    Eigen::VectorXd u(size + 2);
    u << y0, v0, point.omega, point.xi;
    const double scale = std::max({y0.cwiseAbs().maxCoeff(), v0.cwiseAbs().maxCoeff() / point.omega, 1e-300});
    auto residual = [&](const Eigen::VectorXd& at, Eigen::VectorXd& r, Eigen::MatrixXd* jacobian) {
        bool ok = false;
        const Eigen::VectorXd z = state_of(at.head(dofs), at.segment(dofs, dofs), ok);
        if (!ok || !(at(size) > 0.0)) return false;
        const ExactFlow f = flow(z, at(size), at(size + 1));
        if (!f.ok) return false;
        r.resize(size + 2);
        r.head(size) = f.state.head(size) - at.head(size);
        r.segment(dofs, dofs) /= at(size);  // velocities by omega
        r(size) = m_phi_.dot(at.head(dofs)) - modal_position;
        r(size + 1) = (m_phi_.dot(at.segment(dofs, dofs)) - modal_velocity) / at(size);
        r /= scale;
        if (!jacobian) return true;
        // d z(T) / d(y, y'): the monodromy, a Jenkins slider's column carried by its q = w^T y.
        Eigen::MatrixXd& j = *jacobian;
        j.setZero(size + 2, size + 2);
        j.topLeftCorner(size, size) = f.monodromy.topLeftCorner(size, size);
        for (int c = 0; c < contacts; ++c)
            if (system_.contacts[static_cast<std::size_t>(c)].law == FrictionLaw::jenkins)
                j.topLeftCorner(size, dofs) += f.monodromy.block(0, size + c, size, 1) * w[static_cast<std::size_t>(c)].transpose();
        j.topLeftCorner(size, size) -= Eigen::MatrixXd::Identity(size, size);
        for (int col : {size, size + 1}) {  // omega, xi: central differences of the flow
            const double h = 1e-7 * std::max(point.omega, std::abs(at(col)));
            Eigen::VectorXd up = at, down = at;
            up(col) += h;
            down(col) -= h;
            const ExactFlow fu = flow(z, up(size), up(size + 1)), fd = flow(z, down(size), down(size + 1));
            if (!fu.ok || !fd.ok) return false;
            j.col(col).head(size) = (fu.state.head(size) - fd.state.head(size)) / (2.0 * h);
        }
        j.block(dofs, 0, dofs, size + 2) /= at(size);
        j.block(size, 0, 1, dofs) = m_phi_.transpose();
        j.block(size + 1, dofs, 1, dofs) = m_phi_.transpose() / at(size);
        j /= scale;
        return true;
    };
    Eigen::VectorXd r, trial_r;
    Eigen::MatrixXd j;
    for (int iteration = 0;; ++iteration) {
        if (!residual(u, r, &j)) {
            out.message = "the exact flow failed (an event at the section, or chattering)";
            return out;
        }
        out.iterations = iteration;
        out.residual = r.cwiseAbs().maxCoeff();
        if (out.residual <= 1e-12) break;
        if (iteration >= 30) {
            out.message = "the exact shooting did not converge: residual " + format_number(out.residual);
            return out;
        }
        const Eigen::VectorXd step = Eigen::FullPivLU<Eigen::MatrixXd>(j).solve(-r);
        double length = 1.0;
        bool accepted = false;
        for (int halving = 0; halving < 12 && !accepted; ++halving, length *= 0.5) {
            const Eigen::VectorXd trial = u + length * step;
            if (residual(trial, trial_r, nullptr) && trial_r.cwiseAbs().maxCoeff() < out.residual) {
                u = trial;
                accepted = true;
            }
        }
        if (!accepted) {
            out.message = "the exact shooting stalled: residual " + format_number(out.residual);
            return out;
        }
    }
    out.checked = true;
    out.omega = u(size);
    out.xi = u(size + 1);
    out.gap = std::max(std::abs(out.omega - point.omega), std::abs(out.xi - point.xi)) / out.omega;
    return out;
}

std::vector<double> NonlinearModes::metrics_of(const ModePoint& point, const std::vector<Output>& outputs) {
    return metrics(point, outputs).output_amp1;
}

ModeMetrics NonlinearModes::metrics(const ModePoint& point, const std::vector<Output>& outputs) {
    ModeMetrics m;
    // xi is a Newton unknown, accurate to about the corrector's tolerance (1e-10 of w): a
    // |zeta| below 1e-12 (an undamped stuck structure's rounding, of either sign) is 0.
    m.zeta = std::abs(point.zeta()) < 1e-12 ? 0.0 : point.zeta();
    const Eigen::MatrixXd y = motion(point);  // condensed: the free structure at the point's xi (for the Analyser too)
    Analyser analyse(*hb_, {}, outputs);
    SolutionPoint sp;
    sp.omega = point.omega;
    sp.x = point.x;
    const PointMetrics pm = analyse(sp);
    m.friction_energy = pm.energy;
    m.viscous_energy = pm.viscous_energy;
    m.contacts = pm.contacts;
    m.output_max = pm.output_max;
    m.output_amp1 = pm.output_amp1;
    const int harmonics = hb_->harmonics();
    double kinetic = 0.0;  // sum_k k^2 (c_k^T M c_k + s_k^T M s_k)
    m.harmonic_content.assign(static_cast<std::size_t>(harmonics + 1), 0.0);
    Eigen::VectorXd mean = y.row(0).transpose();
    if (hb_->rest_state() && hb_->rest_state()->ok) mean -= hb_->rest_state()->displacement;  // the static deflection left out
    m.harmonic_content[0] = mean.dot(system_.mass * mean);
    for (int k = 1; k <= harmonics; ++k)
        for (int row : {2 * k - 1, 2 * k}) {
            const Eigen::VectorXd c = y.row(row).transpose();
            const double e = c.dot(system_.mass * c);
            m.harmonic_content[static_cast<std::size_t>(k)] += e;
            kinetic += k * k * e;
        }
    double total = 0.0;
    for (double e : m.harmonic_content) total += e;
    for (double& e : m.harmonic_content) e = total > 0.0 ? std::sqrt(e / total) : 0.0;
    m.injected_energy = point.xi * M_PI * point.omega * kinetic;
    const double dissipated = m.friction_energy + m.viscous_energy;
    const double modal = 2.0 * M_PI * point.omega * point.omega * point.amplitude * point.amplitude;
    const double reference = std::max({std::abs(m.injected_energy), m.viscous_energy + std::abs(m.friction_energy),
                                       1e-8 * modal});
    // The normal forces' work on the AFT grid closes the discrete balance: zero in continuous
    // time, a residue where a contact separates (the corner in N; as in hbf frf's balance).
    double normal_work = 0.0;
    Fourier& aft = hb_->fourier();
    const int n = aft.size(), nt = aft.time_samples();
    Eigen::VectorXd v(nt);
    for (int c = 0; c < static_cast<int>(system_.contacts.size()); ++c) {
        const Eigen::VectorXd q = hb_->relative(point.x, c);
        if (q.size() <= n) continue;  // no normal direction
        const Eigen::VectorXd f = hb_->force_samples(point.x, point.omega, c);
        aft.to_time(point.omega * (aft.derivative() * q.tail(n)), v);
        normal_work += 2.0 * M_PI / point.omega * f.tail(nt).dot(v) / nt;
    }
    m.energy_error = std::abs(m.injected_energy - dissipated - normal_work) / reference;
    m.zeta_energy = dissipated / modal;
    return m;
}

std::vector<SynthesisPoint> NonlinearModes::synthesize(const Backbone& backbone, const std::vector<ModeMetrics>& metrics,
                                                      const Eigen::VectorXd& force, const std::vector<Output>& outputs) {
    if (force.size() != system_.dofs())
        throw InvalidInput("force has " + std::to_string(force.size()) + " entries: allowed " +
                           std::to_string(system_.dofs()) + " (one per DOF)");
    // The discriminant of (w^2 - Omega^2)^2 + Omega^2 xi^2 = |psi^H F|^2 / a^2 in Omega^2, and
    // b = 2 w^2 - xi^2 (Omega^2 = (b -+ sqrt(discriminant)) / 2).
    auto quadratic = [&](const ModePoint& p, double& b) {
        const Eigen::MatrixXd y = motion(p);  // psi^H F = (c1 + i s1)^T F / a (each DOF's cos 1 and sin 1 rows)
        const double c = y.row(1).dot(force), s = y.row(2).dot(force);
        const double load = std::hypot(c, s) / p.amplitude, w2 = p.omega * p.omega;
        b = 2.0 * w2 - p.xi * p.xi;
        return b * b - 4.0 * (w2 * w2 - load * load / (p.amplitude * p.amplitude));
    };
    std::vector<SynthesisPoint> lower, upper;
    auto add = [&](const ModePoint& p, const std::vector<double>& amp1) {
        double b = 0.0;
        const double discriminant = quadratic(p, b);
        if (!(discriminant >= 0.0)) return;  // F cannot sustain this amplitude
        const double root = std::sqrt(discriminant);
        for (int flank : {-1, 1}) {
            const double x = 0.5 * (b + flank * root);  // Omega^2
            if (!(x > 0.0)) continue;
            SynthesisPoint q;
            q.omega = std::sqrt(x);
            q.amplitude = p.amplitude;
            q.mode_omega = p.omega;
            q.flank = flank;
            q.output_amp1 = amp1;
            (flank < 0 ? lower : upper).push_back(q);
        }
    };
    for (std::size_t k = 0; k < backbone.points.size() && k < metrics.size(); ++k) {
        const ModePoint& p = backbone.points[k];
        double b = 0.0;
        if (k > 0) {
            // Where F's largest sustainable amplitude (the synthesised peak: discriminant 0) lies
            // between two backbone points, it is found by bisection in a, the mode solved at each
            // trial amplitude (the peak would otherwise be cut at the sampling).
            const ModePoint& q = backbone.points[k - 1];
            const bool inside = quadratic(q, b) >= 0.0, here = quadratic(p, b) >= 0.0;
            if (inside != here) {
                ModePoint in = inside ? q : p, out = inside ? p : q;
                bool ok = true;
                for (int it = 0; it < 60 && ok && std::abs(out.amplitude - in.amplitude) > 1e-12 * in.amplitude; ++it) {
                    ModePoint mid = in;
                    mid.amplitude = std::sqrt(in.amplitude * out.amplitude);
                    ok = solve(mid);
                    if (ok) (quadratic(mid, b) >= 0.0 ? in : out) = mid;
                }
                add(in, metrics_of(in, outputs));
            }
        }
        add(p, metrics[k].output_amp1);
    }
    std::vector<SynthesisPoint> all(lower.begin(), lower.end());
    all.insert(all.end(), upper.rbegin(), upper.rend());
    return all;
}

Verdict judge_backbone(const Backbone& backbone, const std::vector<ModeMetrics>& metrics, double tolerance) {
    Verdict verdict;
    // The stuck mode is the undamped one; where its damping estimate is not small the damped
    // modes differ from it (an overdamped contact damper, regularised Coulomb's F_c / eps), and
    // Newton from it may reach another EPMC solution than its continuation.
    if (backbone.linear.zeta > 0.3 && !backbone.points.empty())
        verdict.warning("the stuck mode's damping estimate zeta = " + format_number(backbone.linear.zeta) +
                        " is not small: the stuck structure's damped modes differ from its undamped mode (w0 = " +
                        format_number(backbone.linear.omega) + "), and the backbone's first point (w = " +
                        format_number(backbone.points.front().omega) + ", zeta = " +
                        format_number(backbone.points.front().zeta()) + ") may belong to another of them");
    if (backbone.status == ModeStatus::start_failed)
        verdict.error(backbone.message);
    else if (backbone.status != ModeStatus::completed)
        verdict.warning("the backbone is incomplete (" + to_string(backbone.status) + "): " + backbone.message);
    double worst = 0.0;
    std::size_t where = 0;
    for (std::size_t k = 0; k < metrics.size(); ++k)
        if (metrics[k].energy_error > worst) {
            worst = metrics[k].energy_error;
            where = k;
        }
    const double limit = energy_balance_limit(tolerance);
    if (worst > limit && where < backbone.points.size())
        verdict.warning("points fail the energy balance (largest relative error " + format_number(worst) + " at a = " +
                        format_number(backbone.points[where].amplitude) + ", allowed " + format_number(limit) +
                        "; energy_error)");
    return verdict;
}

HarmonicBalanceOptions mode_harmonic_balance(HarmonicBalanceOptions hbo, const System& system) {
    if (hbo.formulation == Formulation::automatic && hbo.modes == 0 &&
        static_cast<long long>(system.dofs()) * (2LL * hbo.harmonics + 1) <= mode_full_limit)
        hbo.formulation = Formulation::full;
    if (hbo.formulation == Formulation::full) hbo.modes = 0;
    hbo.jacobian = JacobianForm::dense;
    return hbo;
}

ModeRun compute_mode(const System& system, HarmonicBalanceOptions hbo, const ModeOptions& options,
                     std::vector<Output> outputs, bool synthesis, bool exact_check) {
    if (outputs.empty())
        for (int i = 0; i < system.dofs(); ++i) outputs.push_back(Output::dof(i));
    for (const Output& o : outputs) o.validate(system.dofs());
    if (synthesis && system.excitation_harmonic != 1)
        throw InvalidInput("synthesis: the response to F cos(w t) is synthesised: the system's excitation harmonic is " +
                           std::to_string(system.excitation_harmonic) + " (allowed 1)");
    NonlinearModes nm(system, hbo, options);
    ModeRun run;
    run.backbone = nm.follow();
    for (const ModePoint& p : run.backbone.points) run.metrics.push_back(nm.metrics(p, outputs));
    std::vector<bool> normal;  // the contacts with a normal direction: a separated_fraction column
    for (std::size_t c = 0; c < system.contacts.size(); ++c)
        normal.push_back(!run.metrics.empty() && !std::isnan(run.metrics.front().contacts.at(c).separated_fraction));
    run.harmonics = nm.harmonic_balance().harmonics();
    run.time_samples = nm.harmonic_balance().time_samples();
    run.formulation = nm.formulation();
    run.modes = nm.harmonic_balance().modes();
    run.table = io::backbone_table(run.backbone, run.metrics, outputs, normal, run.harmonics);
    if (synthesis) run.synthesis = nm.synthesize(run.backbone, run.metrics, system.excitation, outputs);
    run.verdict = judge_backbone(run.backbone, run.metrics, options.tolerance);
    if (run.backbone.status != ModeStatus::start_failed) {  // a failed start says them in its message
        const PenaltyDiagnostics penalties = penalty_diagnostics(system, nm.harmonic_balance().rest_state());
        for (const std::string& line : penalties.relieved) run.verdict.warning(line);
        for (const std::string& line : penalties.stiff) run.verdict.note(line);
    }
    if (exact_check) {
        std::vector<io::Column> columns = io::exact_columns();
        std::vector<std::vector<io::Cell>> cells(columns.size());
        double largest = 0.0;
        std::size_t checked = 0, where = 0;
        std::string reason;
        for (std::size_t k = 0; k < run.backbone.points.size(); ++k) {
            const ExactModeCheck c = nm.exact_check(run.backbone.points[k]);
            run.exact.push_back(c);
            cells[0].push_back(c.checked ? io::Cell(c.omega) : io::Cell());
            cells[1].push_back(c.checked ? io::Cell(c.xi) : io::Cell());
            cells[2].push_back(c.checked ? io::Cell(c.gap) : io::Cell());
            if (c.checked) {
                ++checked;
                if (c.gap >= largest) {
                    largest = c.gap;
                    where = k;
                }
            } else if (reason.empty()) {
                reason = c.message + " (first at a = " + format_number(run.backbone.points[k].amplitude) + ")";
            }
        }
        for (std::size_t c = 0; c < columns.size(); ++c) {
            run.table.columns.push_back(columns[c]);
            run.table.cells.push_back(std::move(cells[c]));
        }
        std::string note = "exact check: " + std::to_string(checked) + " of " + std::to_string(run.backbone.points.size()) +
                           " points checked by the event-exact solver";
        if (checked > 0)
            note += ", largest exact_gap " + format_number(largest) + " at a = " +
                    format_number(run.backbone.points[where].amplitude);
        if (checked < run.backbone.points.size()) note += "; not checked: " + reason;
        run.verdict.note(note);
    }
    if (synthesis && !run.backbone.points.empty()) {
        // The synthesis covers the backbone's amplitudes only: a response that reaches its last
        // point has its peak beyond it (the curve is cut, not a peak); none at all means the
        // force sustains no computed amplitude (the response lies below the first point).
        const double last = run.backbone.points.back().amplitude;
        const bool cut = std::any_of(run.synthesis.begin(), run.synthesis.end(),
                                     [&](const SynthesisPoint& q) { return q.amplitude == last; });
        if (cut)
            run.verdict.warning("the synthesised response is cut at the backbone's last point a = " + format_number(last) +
                                ": the excitation sustains that amplitude, so its peak lies beyond the backbone "
                                "(raise the amplitude range's upper end)");
        else if (run.synthesis.empty())
            run.verdict.warning("the synthesised response is empty: the excitation sustains no amplitude of the backbone "
                                "(its response lies below a = " + format_number(run.backbone.points.front().amplitude) +
                                ": lower the amplitude range's lower end)");
    }
    return run;
}

namespace io {

std::vector<Column> backbone_columns(const std::vector<Output>& outputs, const std::vector<bool>& normal, int harmonics) {
    std::vector<Column> c = {
        {"a", "modal amplitude: M-norm of the first harmonic c1 cos + s1 sin of y, sqrt(c1^T M c1 + s1^T M s1) "
              "(units sqrt(mass) x length); in the linear limit the amplitude of q = phi^T M y, phi the stuck "
              "mode with phi^T M phi = 1"},
        {"w", "frequency omega of the nonlinear mode (the periodic motion's fundamental)"},
        {"xi", "artificial damping xi: the term -xi M y' that makes the free motion periodic (feeds in what is dissipated)"},
        {"zeta", "modal damping ratio xi / (2 w) (0 where below 1e-12, the corrector's resolution)"},
        {"zeta_energy", "energy damping ratio (friction_energy + viscous_energy) / (2 pi w^2 a^2); equals zeta when the "
                        "motion is a single harmonic (xi's energy balance), differs with higher harmonics"},
        {"energy", "energy dissipated per cycle by the contacts and the viscous damping C"},
        {"friction_energy", "energy the contacts dissipate per cycle (integral of f q' on the AFT grid)"},
        {"viscous_energy", "energy C dissipates per cycle"},
        {"energy_error", "energy balance |xi-injected - energy - normal forces' work on the AFT grid| relative to the "
                         "larger of xi-injected and energy (floor: 1e-8 2 pi w^2 a^2)"}};
    for (const Output& o : outputs) {
        c.push_back({o.name() + "_max", "max over one period of |" + o.name() + "(t)|"});
        c.push_back({o.name() + "_amp1", "first-harmonic amplitude of " + o.name() + "(t)"});
    }
    for (std::size_t k = 0; k < normal.size(); ++k) {
        const std::string n = std::to_string(k + 1);
        c.push_back({"stick_fraction_c" + n, "share of the period contact " + n + " sticks (its law's definition, as hbf frf)"});
        c.push_back({"regime_c" + n, "stick, slip or stick-slip (contact " + n + ")", ColumnType::text});
        if (normal[k])
            c.push_back({"separated_fraction_c" + n, "share of the period contact " + n + " is open (N = 0)"});
    }
    for (int k = 0; k <= harmonics; ++k)
        c.push_back({"h" + std::to_string(k), "harmonic content: sqrt(Y_k^T M Y_k) over the M-norm of every harmonic (k = " +
                                                  std::to_string(k) + (k == 0 ? ": the mean minus the static deflection)" : ")")});
    c.push_back({"iterations", "Newton iterations of the point", ColumnType::integer});
    c.push_back({"residual", "max |scaled residual| of the point (structure rows relative to a w0^2 |M phi|, "
                             "constraints relative to a)"});
    return c;
}

std::vector<Column> exact_columns() {
    return {{"exact_w", "frequency of the event-exact free orbit with C - xi M (exact Coulomb, Jenkins) at the same "
                        "modal displacement and velocity at a section where every contact slips; empty where not "
                        "checked (permanent stick: the linear mode; laws it does not cover; its shooting failed)"},
            {"exact_xi", "that orbit's artificial damping xi"},
            {"exact_gap", "max(|w - exact_w|, |xi - exact_xi|) / exact_w: harmonic balance's truncation error here"}};
}

std::vector<Column> synthesis_columns(const std::vector<Output>& outputs) {
    std::vector<Column> c = {
        {"w", "excitation frequency of the synthesised forced response (the system's excitation F cos(w t))"},
        {"a", "modal amplitude of the backbone point it comes from"},
        {"w_mode", "that point's frequency w(a) (w = w_mode: phase resonance, where the synthesis is exact for a "
                   "single mode)"},
        {"flank", "-1 the lower root of (w_mode^2 - w^2)^2 + w^2 xi^2 = |psi^H F|^2 / a^2, +1 the upper",
         ColumnType::integer}};
    for (const Output& o : outputs)
        c.push_back({o.name() + "_amp1", "first-harmonic amplitude of " + o.name() + "(t) (the mode's at a)"});
    return c;
}

Table synthesis_table(const std::vector<SynthesisPoint>& curve, const std::vector<Output>& outputs) {
    Table table{synthesis_columns(outputs)};
    for (const SynthesisPoint& q : curve) {
        std::vector<Cell> row = {q.omega, q.amplitude, q.mode_omega, static_cast<long long>(q.flank)};
        for (double v : q.output_amp1) row.emplace_back(v);
        table.add_row(std::move(row));
    }
    return table;
}

Table backbone_table(const Backbone& backbone, const std::vector<ModeMetrics>& metrics,
                     const std::vector<Output>& outputs, const std::vector<bool>& normal, int harmonics) {
    Table table{backbone_columns(outputs, normal, harmonics)};
    for (std::size_t k = 0; k < backbone.points.size() && k < metrics.size(); ++k) {
        const ModePoint& p = backbone.points[k];
        const ModeMetrics& m = metrics[k];
        std::vector<Cell> row = {p.amplitude,       p.omega,           p.xi,
                                 m.zeta,            m.zeta_energy,     m.friction_energy + m.viscous_energy,
                                 m.friction_energy, m.viscous_energy,  m.energy_error};
        for (std::size_t o = 0; o < outputs.size(); ++o) {
            row.emplace_back(m.output_max.at(o));
            row.emplace_back(m.output_amp1.at(o));
        }
        for (std::size_t c = 0; c < normal.size(); ++c) {
            const ContactRegime& r = m.contacts.at(c);
            row.emplace_back(r.stick_fraction);
            row.emplace_back(r.regime);
            if (normal[c]) row.emplace_back(r.separated_fraction);
        }
        for (int h = 0; h <= harmonics; ++h) row.emplace_back(m.harmonic_content.at(static_cast<std::size_t>(h)));
        row.emplace_back(static_cast<long long>(p.iterations));
        row.emplace_back(p.residual);
        table.add_row(std::move(row));
    }
    return table;
}

}  // namespace io

}  // namespace hbf
