// hbfriction — harmonic balance's first guesses (harmonic_balance.hpp: linear_guess): the
// linear structure with each contact as its law's linear element (contact_law.hpp: linearize,
// stuck) or released, solved per harmonic.
#include "hbf/harmonic_balance.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/error.hpp"
#include "hbf/static_state.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

Eigen::VectorXd HarmonicBalance::linear_guess(double omega, bool sliding) const {
    using Complex = std::complex<double>;
    const int n = coefficients(), dofs = system_.dofs(), ns = signals_;
    // The response to F cos(h w t) sits on harmonic h, at the frequency h w.
    const int h = load_harmonic(), cos_row = 2 * h - 1, sin_row = cos_row + 1;
    // Each direction of each contact as a linear element of complex stiffness k + i omega d
    // (pre-sliding), or held rigid (exact Coulomb: its force is the constraint's multiplier);
    // none when sliding. A preloaded element (StuckElement::offset) also loads harmonic 0.
    std::vector<StuckElement> element(static_cast<std::size_t>(ns));
    bool preload = false;
    const std::vector<std::vector<StuckElement>> elements =
        sliding ? std::vector<std::vector<StuckElement>>() : stuck_elements(system_);  // about the static state
    for (std::size_t c = 0; c < system_.contacts.size() && !sliding; ++c) {
        const std::vector<StuckElement>& along = elements[c];
        for (int j = 0; j < signal_count_[c]; ++j) {
            element[static_cast<std::size_t>(signal_first_[c] + j)] = along[static_cast<std::size_t>(j)];
            preload = preload || along[static_cast<std::size_t>(j)].offset != 0.0;
        }
    }
    Eigen::VectorXd x = Eigen::VectorXd::Zero(all_unknowns_);
    Eigen::VectorXcd force = Eigen::VectorXcd::Zero(ns);  // harmonic h's element forces
    // Harmonic k at the frequency k w (k = h: the force F; k = 0: the preloads): the amplitudes
    // of the signals (condensed) or the DOFs (full), and the elements' forces.
    auto solve = [&](int k, Eigen::VectorXcd& amplitude, Eigen::VectorXcd& forces) {
        const double frequency = k * omega;
        forces = Eigen::VectorXcd::Zero(ns);
        Eigen::VectorXcd offset(ns);
        for (int a = 0; a < ns; ++a) offset(a) = k == 0 ? element[static_cast<std::size_t>(a)].offset : 0.0;
        if (condensed_) {
            // Q = Q0 - G Lambda with Lambda_a = element_a Q_a + offset_a, or Q_a = 0 (rigid).
            const Receptance::Harmonic g = k == 0 ? (*harmonic_)[0] : receptance_->solve(k, omega, k == h);
            if (!g.ok) return false;
            Eigen::MatrixXcd m(ns, ns);
            for (int a = 0; a < ns; ++a)
                for (int b = 0; b < ns; ++b) {
                    const StuckElement& e = element[static_cast<std::size_t>(b)];
                    // Lambda' = Lambda - (kappa + i w delta) Q (the shifted structure's force)
                    const Complex shift(shift_stiffness_(b), frequency * shift_damping_(b));
                    m(a, b) = e.rigid ? g.contact(a, b) : g.contact(a, b) * (e.at(frequency) - shift) + (a == b ? 1.0 : 0.0);
                }
            Eigen::VectorXcd rhs = -(g.contact * offset);
            if (k == h) rhs += g.contact_load;
            if (k == 0 && static_contact_.size() > 0) rhs += static_contact_.cast<Complex>();
            const Eigen::VectorXcd u = m.fullPivLu().solve(rhs);
            amplitude = Eigen::VectorXcd::Zero(ns);
            for (int a = 0; a < ns; ++a) {
                const StuckElement& e = element[static_cast<std::size_t>(a)];
                forces(a) = e.rigid ? u(a) : e.at(frequency) * u(a) + offset(a);
                if (!e.rigid) amplitude(a) = u(a);
            }
            return true;
        }
        // (K - w^2 M + i w C + sum_a element_a w_a w_a^T) Y + W_R Lambda_R = F - sum_a offset_a w_a,
        // W_R^T Y = 0.
        std::vector<int> stuck;
        Eigen::MatrixXcd z = dynamic_stiffness(Eigen::MatrixXd(system_.mass), Eigen::MatrixXd(system_.damping),
                                               Eigen::MatrixXd(system_.stiffness), frequency);
        Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(dofs);
        if (k == h) rhs = system_.excitation.cast<Complex>();
        if (k == 0 && system_.static_load.size() > 0) rhs += system_.static_load.cast<Complex>();
        for (int a = 0; a < ns; ++a) {
            const Eigen::VectorXd& w = directions_[static_cast<std::size_t>(a)];
            const StuckElement& e = element[static_cast<std::size_t>(a)];
            rhs -= offset(a) * w.cast<Complex>();
            if (e.rigid)
                stuck.push_back(a);
            else
                z += e.at(frequency) * (w * w.transpose()).cast<Complex>();
        }
        // A sector (cyclic.hpp): Y = T_k U on its independent DOFs, T_k^H z T_k U = T_k^H rhs, the
        // rigid rows w^T T_k U = 0.
        const Eigen::MatrixXcd t = cyclic_ ? cyclic_transform(system_, k * system_.cyclic.phase())
                                           : Eigen::MatrixXcd();
        const auto free = cyclic_ ? t.cols() : static_cast<Eigen::Index>(dofs);
        const auto m = static_cast<Eigen::Index>(stuck.size());
        Eigen::MatrixXcd a = Eigen::MatrixXcd::Zero(free + m, free + m);
        a.topLeftCorner(free, free) = cyclic_ ? Eigen::MatrixXcd(t.adjoint() * z * t) : z;
        for (Eigen::Index j = 0; j < m; ++j) {
            const Eigen::VectorXd& w = directions_[static_cast<std::size_t>(stuck[static_cast<std::size_t>(j)])];
            const Eigen::VectorXcd row = cyclic_ ? Eigen::VectorXcd(t.transpose() * w.cast<Complex>())
                                                 : Eigen::VectorXcd(w.cast<Complex>());
            a.block(0, free + j, free, 1) = row.conjugate();
            a.block(free + j, 0, 1, free) = row.transpose();
        }
        Eigen::VectorXcd full = Eigen::VectorXcd::Zero(free + m);
        full.head(free) = cyclic_ ? Eigen::VectorXcd(t.adjoint() * rhs) : rhs;
        const Eigen::VectorXcd solution = a.fullPivLu().solve(full);
        amplitude = cyclic_ ? Eigen::VectorXcd(t * solution.head(free)) : Eigen::VectorXcd(solution.head(dofs));
        for (Eigen::Index j = 0; j < m; ++j) forces(stuck[static_cast<std::size_t>(j)]) = solution(dofs + j);
        return true;
    };
    const int signals = condensed_ ? ns : dofs;
    Eigen::VectorXcd amplitude;
    if (solve(h, amplitude, force))
        for (int a = 0; a < signals; ++a) {
            const Complex u = amplitude(a);
            if (!std::isfinite(std::abs(u))) continue;  // exact resonance: start from rest
            x(a * n + cos_row) = u.real();  // y = Re(Y e^{i h theta}) = Re Y cos - Im Y sin
            x(a * n + sin_row) = -u.imag();
        }
    Eigen::VectorXcd mean_forces;
    if (rest_ && rest_->ok && !sliding) {
        // Harmonic 0 from the static state (static_state.hpp): the structure loaded before it vibrates.
        const Eigen::VectorXd& rest = rest_->displacement;
        for (int a = 0; a < signals; ++a)
            x(a * n) = condensed_ ? directions_[static_cast<std::size_t>(a)].dot(rest) : rest(a);
        mean_forces = Eigen::VectorXcd::Zero(ns);  // the contacts' static forces (the multipliers' means)
        for (std::size_t c = 0; c < rest_->contacts.size(); ++c)
            for (Eigen::Index j = 0; j < rest_->contacts[c].force.size() && j < signal_count_[c]; ++j)
                mean_forces(signal_first_[c] + j) = rest_->contacts[c].force(j);
    } else if ((preload || system_.has_static_load()) && !odd_ && solve(0, amplitude, mean_forces))
        for (int a = 0; a < signals; ++a)
            if (std::isfinite(amplitude(a).real())) x(a * n) = amplitude(a).real();
    for (std::size_t c = 0; c < system_.contacts.size(); ++c) {
        if (state_offset_[c] < 0) continue;
        const Contact& k = system_.contacts[c];
        const Eigen::VectorXd q = relative_all(x, static_cast<int>(c));
        const int first = signal_first_[c], count = signal_count_[c];
        Eigen::VectorXd mean = Eigen::VectorXd::Zero(count);
        if (mean_forces.size() == ns) mean = mean_forces.segment(first, count).real();
        // zero so far; sliding: the friction force at its limit in phase with the velocity
        // (harmonic h of F_c sign(v) is (4/pi) F_c v / |v|, v ~ (s_h cos - c_h sin) for v on
        // harmonic h); stuck: the law's state in the linear stuck response
        contact_law(k.law).guess_state(k, sliding, q, cos_row, force.segment(first, count), mean,
                                       x.segment(state_offset_[c], state_count_[c] * n));
    }
    if (!odd_ && !cyclic_) return x;
    Eigen::VectorXd balanced(unknowns_);  // the balanced (odd) or independent (sector) entries
    for (int i = 0; i < unknowns_; ++i) balanced(i) = x(balanced_index_[static_cast<std::size_t>(i)]);
    return balanced;
}

}  // namespace hbf
