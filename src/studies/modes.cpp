// hbfriction — nonlinear modes by the extended periodic motion concept (modes.hpp).
#include "hbf/modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/error.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/static_state.hpp"
#include "base/stopwatch.hpp"
#include "base/enum_table.hpp"
#include "continuation/switch_hold.hpp"

namespace hbf {

namespace {
double infinity_norm(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

// A sector's stuck modes at the engine order's phase (cyclic.hpp: sector_modes) as linear
// modes: the travelling wave phi = shape + i shape_imag on every DOF of the sector; omega = 0
// for a rigid-body mode (lambda at the eigensolver's rounding of the largest, as stuck_modes).
std::vector<LinearMode> travelling_modes(const System& system) {
    const std::vector<SectorMode> sector = sector_modes(system, system.cyclic.phase(), true);
    double largest = 0.0;
    for (const SectorMode& m : sector) largest = std::max(largest, m.omega * m.omega);
    std::vector<LinearMode> modes;
    for (const SectorMode& m : sector) {
        LinearMode mode;
        mode.index = m.index;
        mode.omega = m.omega * m.omega > 64.0 * std::numeric_limits<double>::epsilon() * largest ? m.omega : 0.0;
        mode.zeta = mode.omega > 0.0 ? m.zeta : 0.0;
        mode.shape = m.shape.real();
        mode.shape_imag = m.shape.imag();
        modes.push_back(std::move(mode));
    }
    return modes;
}
}  // namespace
constexpr detail::EnumName<ModeStatus> mode_status_names[] = {
    {ModeStatus::completed, "completed"}, {ModeStatus::left_range, "left_range"}, {ModeStatus::min_step, "min_step"},
    {ModeStatus::point_budget, "point_budget"}, {ModeStatus::start_failed, "start_failed"},
    {ModeStatus::stopped, "stopped"}};

std::string to_string(ModeStatus status) { return detail::enum_name(mode_status_names, status, "mode status"); }

void ModeOptions::validate() const {
    if (near_frequency != 0.0 && !(near_frequency > 0.0 && std::isfinite(near_frequency)))
        throw InvalidInput("near_frequency = " + format_number(near_frequency) +
                           " is out of range: allowed > 0 (or 0: the mode by its index)");
    if (near_frequency == 0.0 && mode < 1) throw InvalidInput("mode = " + std::to_string(mode) + " is out of range: allowed >= 1");
    if (start_frequency != 0.0 && !(start_frequency > 0.0 && std::isfinite(start_frequency)))
        throw InvalidInput("start_frequency = " + format_number(start_frequency) +
                           " is out of range: allowed > 0 (or 0: the automatic start)");
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
    {
        // Newton on the modes' unknowns is dense (no structured Jacobian here): refused before
        // the structure is factorised and solved, by the smaller of the two formulations' counts.
        int signals = 0;
        for (const Contact& c : system_.contacts) signals += static_cast<int>(system_.contact_directions(c).cols());
        const long n = 2L * hbo.harmonics + 1;
        const long smallest = std::min<long>(signals, system_.dofs()) * n;
        if (smallest > HarmonicBalance::max_unknowns) {
            const long fits = (HarmonicBalance::max_unknowns / std::min<long>(signals, system_.dofs()) - 1) / 2;
            throw InvalidInput("harmonics = " + std::to_string(hbo.harmonics) + " with " + std::to_string(signals) +
                               " contact directions makes at least " + std::to_string(smallest) +
                               " unknowns for nonlinear modes, whose Newton system is dense (" +
                               format_number(std::round(8.0 * smallest * static_cast<double>(smallest) / 1048576.0)) +
                               " MB per copy): allowed at most " + std::to_string(HarmonicBalance::max_unknowns) + " (" +
                               (fits >= 1 ? "at most H = " + std::to_string(fits) + " fits; " : std::string()) +
                               "fewer contact nodes)");
        }
    }
    // A sector's modes are the travelling waves of the engine order's harmonic index (cyclic.hpp).
    const bool sector = system_.cyclic.active();
    const std::vector<LinearMode> modes = sector ? travelling_modes(system_) : stuck_modes(system_);
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
                               std::to_string(count) +
                               (sector ? " (the stuck sector's modes of nodal diameter " +
                                             std::to_string(nodal_diameter(system_.cyclic, 1)) + ")"
                                       : std::string(" (the stuck structure's modes)")));
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
    unforced.excitation(independent_dofs(system_).front()) = 1.0;  // the first unknowns' DOF (a sector's first own DOF)
    unforced.excitation_harmonic = 1;
    hb_ = std::make_unique<HarmonicBalance>(unforced, mode_harmonic_balance(hbo, system_));
    condensed_ = hb_->formulation() == Formulation::condensed;
    if (sector && condensed_)
        throw InvalidInput("formulation = condensed: a sector model's nonlinear modes are solved in the full "
                           "formulation (allowed: full or automatic)");
    // Where the stuck structure is damped (a contact's damper, C), its damped mode is the
    // linear limit: the undamped mode is not an EPMC solution, and Newton from it can reach
    // another one.
    if (linear_.zeta != 0.0) damped_ = damped_linear_mode(system_, linear_);
    guess_shape_ = linear_.shape;
    if (sector) {
        // The unknowns are the own DOFs': phi's entries there (Y_1 = a phi: c1 = a Re phi, s1 = -a Im phi).
        const std::vector<int> own = independent_dofs(system_);
        guess_shape_.resize(static_cast<Eigen::Index>(own.size()));
        guess_sine_.resize(guess_shape_.size());
        for (std::size_t j = 0; j < own.size(); ++j) {
            guess_shape_(static_cast<Eigen::Index>(j)) = linear_.shape(own[j]);
            guess_sine_(static_cast<Eigen::Index>(j)) = -linear_.shape_imag(own[j]);
        }
    }
    if (damped_.ok) {
        guess_shape_ = damped_.shape.real();
        guess_sine_ = -damped_.shape.imag();
    }
    if (condensed_) {
        hb_->set_free_motion(0.0);  // the placeholder load dropped; xi set per evaluation
        std::vector<Eigen::VectorXd> directions;
        for (const Contact& c : system_.contacts) {
            const Eigen::MatrixXd w = system_.contact_directions(c);
            for (Eigen::Index j = 0; j < w.cols(); ++j) directions.push_back(w.col(j));
        }
        const Eigen::VectorXd cosine = guess_shape_, sine = guess_sine_;
        guess_shape_.resize(static_cast<Eigen::Index>(directions.size()));
        if (sine.size() > 0) guess_sine_.resize(guess_shape_.size());
        for (std::size_t a = 0; a < directions.size(); ++a) {
            guess_shape_(static_cast<Eigen::Index>(a)) = directions[a].dot(cosine);
            if (sine.size() > 0) guess_sine_(static_cast<Eigen::Index>(a)) = directions[a].dot(sine);
        }
    }
    m_phi_ = system_.mass * linear_.shape;
    if (linear_.shape_imag.size()) m_phi_imag_ = system_.mass * linear_.shape_imag;
    const auto modulus = [](const Eigen::VectorXd& re, const Eigen::VectorXd& im) {
        return im.size() ? Eigen::VectorXd(re.cwiseAbs2() + im.cwiseAbs2()).cwiseSqrt().maxCoeff() : infinity_norm(re);
    };
    force_unit_ = linear_.omega * linear_.omega * modulus(m_phi_, m_phi_imag_);
    phi_max_ = modulus(linear_.shape, linear_.shape_imag);
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
    // A sector: the terms below on every DOF's harmonics X = P U (its own DOFs' unknowns U, the
    // dependent DOFs turned), the rows folded by P^T (harmonic_balance.hpp); else P = I.
    const bool sector = system_.cyclic.active();
    const SparseMatrix& p = hb_->cyclic_map();
    const Eigen::VectorXd all = sector ? Eigen::VectorXd(p * x) : Eigen::VectorXd();
    const Eigen::VectorXd& xa = sector ? all : x;
    const auto fold = [&](const Eigen::VectorXd& v) { return sector ? Eigen::VectorXd(p.transpose() * v) : v; };
    structure(1) += 1.0;  // the placeholder force on DOF 1's cos 1 row (constructor), removed
    const Eigen::Map<const Eigen::MatrixXd> y(xa.data(), n, dofs);
    const Eigen::MatrixXd& d1 = hb_->fourier().derivative();
    const Eigen::MatrixXd d1ym = (d1 * y) * system_.mass;  // (D1 Y) M
    Eigen::VectorXd flat = Eigen::VectorXd::Zero(xa.size());
    flat.head(n * dofs) = Eigen::Map<const Eigen::VectorXd>(d1ym.data(), d1ym.size());
    const Eigen::VectorXd folded = fold(flat);
    structure -= xi * omega * folded;
    // Rows of the structure relative to the mode's inertial force (floored by the static loads'
    // rounding), the constraints relative to the amplitude.
    const double scale = std::max(amplitude * force_unit_, 1e-5 * static_force_);
    r.resize(u + 2);
    r.head(u) = structure / scale;
    // Amplitude: the M-norm of the first harmonic, sqrt(c1^T M c1 + s1^T M s1) = a; phase: the
    // modal coordinate's Im(phi^H M Y_1) = 0, Y_1 = c1 - i s1: phi^T M s1 for a real phi,
    // (Re phi)^T M s1 + (Im phi)^T M c1 for a sector's travelling wave.
    const bool complex_phi = m_phi_imag_.size() > 0;
    const Eigen::VectorXd m_cos1 = system_.mass * y.row(1).transpose(), m_sin1 = system_.mass * y.row(2).transpose();
    const double norm1 = std::sqrt(y.row(1).dot(m_cos1) + y.row(2).dot(m_sin1));
    const double sin1 = y.row(2).dot(m_phi_) + (complex_phi ? y.row(1).dot(m_phi_imag_) : 0.0);
    r(u) = (norm1 - amplitude) / amplitude;
    r(u + 1) = sin1 / amplitude;
    if (!jacobian) return;
    Eigen::MatrixXd& j = *jacobian;
    j.setZero(u + 2, u + 2);
    j.topLeftCorner(u, u) = structure_x;
    if (sector) {
        if (sector_mass_d1_.rows() != u) {  // P^T (M (x) D1) P: constant, formed at the first Jacobian
            std::vector<Eigen::Triplet<double>> entries;
            for (int k = 0; k < system_.mass.outerSize(); ++k)
                for (SparseMatrix::InnerIterator it(system_.mass, k); it; ++it)
                    for (int a = 0; a < n; ++a)
                        for (int b = 0; b < n; ++b)
                            if (d1(a, b) != 0.0)
                                entries.emplace_back(static_cast<int>(it.row()) * n + a,
                                                     static_cast<int>(it.col()) * n + b, it.value() * d1(a, b));
            SparseMatrix m_d1(xa.size(), xa.size());
            m_d1.setFromTriplets(entries.begin(), entries.end());
            sector_mass_d1_ = Eigen::MatrixXd(p.transpose() * m_d1 * p);
        }
        j.topLeftCorner(u, u) -= xi * omega * sector_mass_d1_;
    } else {
        for (int k = 0; k < system_.mass.outerSize(); ++k)
            for (SparseMatrix::InnerIterator it(system_.mass, k); it; ++it)
                j.block(it.row() * n, it.col() * n, n, n) -= xi * omega * it.value() * d1;
    }
    j.col(u).head(u) = structure_omega - xi * folded;
    j.col(u + 1).head(u) = -omega * folded;
    j.topRows(u) /= scale;
    Eigen::VectorXd norm_row = Eigen::VectorXd::Zero(xa.size()), phase_row = Eigen::VectorXd::Zero(xa.size());
    for (int i = 0; i < dofs; ++i) {
        if (norm1 > 0.0) {
            norm_row(i * n + 1) = m_cos1(i) / (norm1 * amplitude);
            norm_row(i * n + 2) = m_sin1(i) / (norm1 * amplitude);
        }
        phase_row(i * n + 2) = m_phi_(i) / amplitude;
        if (complex_phi) phase_row(i * n + 1) = m_phi_imag_(i) / amplitude;
    }
    j.row(u).head(u) = fold(norm_row).transpose();
    j.row(u + 1).head(u) = fold(phase_row).transpose();
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
        // The N x signals response only where the gradients need it (its transpose applied).
        Eigen::MatrixXcd response;
        Eigen::VectorXcd y1;
        if (gradients) {
            response = hb_->contact_response(1, at_omega);
            if (response.size() == 0) return out;
            y1 = -(response * lambda);
        } else {
            y1 = hb_->free_response(1, at_omega, lambda);
            if (y1.size() == 0) return out;
        }
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
    const double h_xi = 1e-6 * std::max(linear_.omega, std::abs(xi)), h_omega = 1e-6 * omega;
    Eigen::VectorXd structure_r, structure_omega;
    Eigen::MatrixXd structure_x;
    structure(xi, structure_r, jacobian ? &structure_x : nullptr, jacobian ? &structure_omega : nullptr);
    const Rows here = rows(omega, jacobian != nullptr);
    // The structure's rows in xi exactly (the receptances' derivative applied to the forces);
    // central differences where the receptance cannot give it, and for the two constraint rows
    // (cheap: one response vector each). Both move the receptances' damping: xi restored after.
    Eigen::VectorXd d_xi;
    Rows xi_up, xi_down;
    if (jacobian) {
        if (!hb_->free_motion_xi_derivative(x, omega, d_xi)) {
            Eigen::VectorXd up, down;
            structure(xi + h_xi, up, nullptr, nullptr);
            structure(xi - h_xi, down, nullptr, nullptr);
            d_xi = (up - down) / (2.0 * h_xi);
        }
        hb_->set_free_motion(xi + h_xi);
        xi_up = rows(omega, false);
        hb_->set_free_motion(xi - h_xi);
        xi_down = rows(omega, false);
        hb_->set_free_motion(xi);
    }
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
    if (!hb_->hold_switches(false)) return correct_once(point, tangent, predicted);
    // The residual jumps at a switch away from a solution: Newton with the switches free can
    // cycle across it. Each solve holds the forms decided at its start.
    int iterations = 0;
    ModePoint decided;
    for (int attempt = 0; attempt < 3; ++attempt) {
        ModePoint trial = point;
        bool solved = false;
        {
            const detail::SwitchHold hold(*hb_);
            if (attempt > 0) {  // the first evaluation decides: at the last solution
                Eigen::VectorXd g;
                residual(decided.x, decided.omega, decided.xi, decided.amplitude, g, nullptr);
            }
            solved = correct_once(trial, tangent, predicted);
        }
        iterations += trial.iterations;
        if (!solved) {
            point.iterations = iterations;
            point.residual = trial.residual;
            return false;
        }
        Eigen::VectorXd g;
        residual(trial.x, trial.omega, trial.xi, trial.amplitude, g, nullptr);
        const double free = infinity_norm(g);
        if (free <= options_.tolerance) {
            point = trial;
            point.iterations = iterations;
            point.residual = free;
            return true;
        }
        decided = trial;
    }
    point.iterations = iterations;
    return false;
}

bool NonlinearModes::correct_once(ModePoint& point, const Eigen::VectorXd* tangent, const Eigen::VectorXd* predicted) {
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
    p.omega = damped_.ok ? damped_.omega : linear_.omega;
    p.xi = damped_.ok ? damped_.xi : 2.0 * linear_.omega * linear_.zeta;
    const int n = hb_->coefficients(), coordinates = static_cast<int>(guess_shape_.size());
    p.x = hb_->linear_guess(linear_.omega);  // harmonic 0: the static state; the rest replaced
    for (int i = 0; i < coordinates; ++i) {  // every DOF, or (condensed) every contact direction
        p.x.segment(i * n + 1, n - 1).setZero();
        p.x(i * n + 1) = amplitude * guess_shape_(i);
        if (guess_sine_.size() > 0) p.x(i * n + 2) = amplitude * guess_sine_(i);
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
    b.damped_linear = damped_.ok;
    b.linear_omega = damped_.ok ? damped_.omega : linear_.omega;
    b.linear_xi = damped_.ok ? damped_.xi : 2.0 * linear_.omega * linear_.zeta;
    const long long evaluations = evaluations_;
    ModePoint start;
    if (first_point(start, b)) continue_from(start, options_.amplitude_min, options_.amplitude_max, b);
    b.evaluations = evaluations_ - evaluations;
    b.seconds = watch.lap();
    return b;
}

bool NonlinearModes::first_point(ModePoint& start, Backbone& b) {
    const double a_min = options_.amplitude_min;
    const auto fail = [&](const ModePoint& at, const std::string& from) {
        b.status = ModeStatus::start_failed;
        b.message = "the first point (a = " + format_number(a_min) + ") did not converge from " + from + ": residual " +
                    format_number(at.residual) +
                    (at.iterations == 0 ? std::string(" at the guess, which no Newton step (halved 12 times) reduced")
                                        : " after " + std::to_string(at.iterations) + " Newton iterations");
        const PenaltyDiagnostics penalties = penalty_diagnostics(system_, hb_->rest_state());
        for (const std::string& line : penalties.relieved) b.message += "; " + line;
        for (const std::string& line : penalties.stiff) b.message += "; " + line;
        return false;
    };
    start = linear_guess(a_min);
    if (options_.start_frequency > 0.0) {
        start.omega = options_.start_frequency;
        b.start = "given";
        return solve(start) || fail(start, "the given start frequency " + format_number(options_.start_frequency));
    }
    const bool direct = solve(start);
    // Is a_min in the linear regime, and is the point found there the continuation of the linear
    // limit? Probes far below a_min (where the motion is the linear limit's) answer both: the
    // first one on the linear limit is followed up to a_min unless a_min's point equals it.
    const double omega0 = b.linear_omega, xi0 = b.linear_xi;
    const double xi_slack = damped_.ok || linear_.zeta == 0.0 ? 0.0 : 0.05 * std::abs(xi0);  // a first-order estimate
    const auto near = [](const ModePoint& u, double omega, double xi, double tolerance, double slack) {
        return std::abs(u.omega - omega) <= tolerance * omega && std::abs(u.xi - xi) <= tolerance * omega + slack;
    };
    std::string probes;
    for (int decades = 3; decades <= 12; decades += 3) {
        ModePoint probe = linear_guess(a_min * std::pow(10.0, -decades));
        if (!solve(probe)) {
            probes += (probes.empty() ? "" : "; ") + ("a = " + format_number(probe.amplitude) + " did not converge");
            continue;
        }
        if (!near(probe, omega0, xi0, 1e-4, xi_slack)) {
            probes += (probes.empty() ? "" : "; ") + ("a = " + format_number(probe.amplitude) + ": w = " +
                                                       format_number(probe.omega) + ", xi = " + format_number(probe.xi));
            continue;
        }
        if (direct && near(start, probe.omega, probe.xi, 1e-6, 0.0)) {
            b.start = "linear";
            return true;
        }
        Backbone run;
        const ModeOptions kept = options_;
        options_.progress = nullptr;
        // The run-up only has to reach a_min: at least the default steps, whatever the
        // backbone's own (a short max_step resolves the backbone, not the way to it).
        const ModeOptions defaults;
        options_.max_step = std::max(options_.max_step, defaults.max_step);
        options_.initial_step = std::max(options_.initial_step, defaults.initial_step);
        continue_from(probe, probe.amplitude, a_min, run);
        options_ = kept;
        b.failed_steps += run.failed_steps;
        if (run.status == ModeStatus::stopped) {
            b.status = ModeStatus::stopped;
            b.message = "stopped before the first point, in the run-up from the linear regime (a = " +
                        format_number(probe.amplitude) + ") to a_min: " + run.message;
            return false;
        }
        const bool reached = run.status == ModeStatus::completed && !run.points.empty() &&
                             std::abs(run.points.back().amplitude - a_min) <= 1e-12 * a_min;
        if (reached) {
            const ModePoint& up = run.points.back();
            if (direct && !near(start, up.omega, up.xi, 1e-6, 0.0))
                b.start_note = "the first point solved at a_min from the linear limit converged to another solution "
                               "(w = " + format_number(start.omega) + ", xi = " + format_number(start.xi) +
                               ") than the backbone that continues the linear limit (w = " + format_number(up.omega) +
                               ", xi = " + format_number(up.xi) + " at a_min, followed up from a = " +
                               format_number(probe.amplitude) + "): the backbone starts from the latter";
            start = up;
            b.start = "run-up";
            return true;
        }
        if (!direct) return fail(start, "the linear limit, nor was it reached from the linear regime (" + run.message + ")");
        b.start = "unchecked";
        b.start_note = "the backbone could not be followed from the linear regime (a = " + format_number(probe.amplitude) +
                       ") up to a_min (" + (run.message.empty() ? to_string(run.status) : run.message) +
                       "): its first point (w = " + format_number(start.omega) + ", xi = " + format_number(start.xi) +
                       ") may belong to another solution than the linear limit's continuation";
        return true;
    }
    if (!direct) return fail(start, "the linear limit");
    b.start = "unchecked";
    b.start_note = "no point down to a = " + format_number(a_min * 1e-12) + " matched the linear limit (w = " +
                   format_number(omega0) + ", xi = " + format_number(xi0) + "; " + probes +
                   "): the first point (w = " + format_number(start.omega) + ", xi = " + format_number(start.xi) +
                   ") may belong to another solution than the linear limit's continuation";
    return true;
}

void NonlinearModes::continue_from(const ModePoint& start, double a_first, double a_last, Backbone& b) {
    const int u = hb_->unknowns();
    const double first = std::log10(a_first), last = std::log10(a_last);
    b.points.push_back(start);
    if (options_.progress) options_.progress(start.amplitude, 1);
    // Pseudo-arclength in the scaled coordinates (x / (a |phi|), omega / w0, xi / w0, log10 a):
    // the backbone may turn back in a (a modal interaction, a contact releasing a second mode).
    Eigen::VectorXd direction = Eigen::VectorXd::Zero(u + 3);
    direction(u + 2) = 1.0;
    Eigen::VectorXd t = tangent(start, direction);
    double h = options_.initial_step;
    const double corner_step = std::max(1e-4, 16.0 * options_.min_step);
    double rejected_turn = -1.0;  // turn of the last step rejected for turning too sharply
    int leaps = 0;                // steps over a spot the corrector cannot land on (below)
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
        if (options_.stop) {
            const std::string why = options_.stop();
            if (!why.empty()) {
                b.status = ModeStatus::stopped;
                b.message = "stopped at a = " + format_number(previous.amplitude) + " after " +
                            std::to_string(b.points.size()) + " points: " + why;
                break;
            }
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
        if (ok && h > 2.0 * options_.min_step) {
            // The corrector moves on the hyperplane through the predicted point; a correction
            // longer than twice the step landed elsewhere on the solution set: a jump, retried
            // with a shorter step, as the FRF's continuation does.
            Eigen::VectorXd landed(u + 3);
            landed.head(u) = trial.x;
            landed(u) = trial.omega;
            landed(u + 1) = trial.xi;
            landed(u + 2) = std::log10(trial.amplitude);
            ok = (landed - predicted).cwiseQuotient(scale).norm() <= 2.0 * h;
        }
        Eigen::VectorXd next;
        bool corner = false;
        bool turned = false;
        if (ok) {
            next = tangent(trial, t);
            // A sharper turn than 0.3 rad: a smaller step; a corner of the backbone (a
            // stick/slip switch of a time sample: its tangent jumps) is crossed where the turn
            // does not shrink with the step (at least 3/4 of the turn the longer step made),
            // or at a short step.
            const double turn = std::acos(std::clamp(next.dot(t), -1.0, 1.0));
            corner = turn > 0.3;
            const bool kink = rejected_turn > 0.0 && turn > 0.75 * rejected_turn;
            ok = !corner || h <= corner_step || kink;
            if (!ok) {
                rejected_turn = turn;
                turned = true;
            }
        }
        if (!turned) rejected_turn = -1.0;
        if (!ok) {
            ++b.failed_steps;
            h *= 0.5;
            if (h < options_.min_step && leaps < 3) {
                // The corrector cannot land near here (the residual of a nonsmooth law is
                // piecewise smooth: at a pattern boundary Newton may cycle): step over the spot
                // with 16, 64, 256 times the corner step, each leap corrected and checked like
                // any step (the FRF's continuation does the same).
                h = std::min(options_.max_step, 16.0 * corner_step * std::pow(4.0, leaps++));
                continue;
            }
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
            end.amplitude = a_last;
            end.x = previous.x + f * (trial.x - previous.x);
            end.omega = previous.omega + f * (trial.omega - previous.omega);
            end.xi = previous.xi + f * (trial.xi - previous.xi);
            if (solve(end)) trial = end;
            else {
                ++b.failed_steps;
                h *= 0.5;
                if (h >= options_.min_step) continue;
                b.status = ModeStatus::min_step;
                b.message = "the point at a = " + format_number(a_last) + " did not converge";
                break;
            }
        }
        if (std::log10(trial.amplitude) < first) {
            b.status = ModeStatus::left_range;
            b.message = "the backbone turned back below a = " + format_number(a_first) +
                        " at omega = " + format_number(trial.omega);
            break;
        }
        trial.step = h;
        leaps = 0;
        if (corner) ++b.corners;
        b.points.push_back(trial);
        t = next;
        if (options_.progress) options_.progress(trial.amplitude, static_cast<int>(b.points.size()));
        if (trial.iterations <= 4) h = std::min(1.5 * h, options_.max_step);
    }
}
SlipOnset slip_onset(const System& system, const HarmonicBalanceOptions& hbo, const ModeOptions& options) {
    ModeOptions chosen = options;  // the mode as chosen; any valid range (not followed)
    chosen.amplitude_min = 1e-4;
    chosen.amplitude_max = 1.0;
    const NonlinearModes probe(system, hbo, chosen);
    return slip_onset(system, probe.linear());
}

}  // namespace hbf
