// hbfriction — harmonic balance's first guesses (harmonic_balance.hpp: linear_guess): the
// linear structure with each contact as its law's linear element (contact.hpp: linearize,
// stuck) or released, solved per harmonic.
#include "hbf/harmonic_balance.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact.hpp"
#include "hbf/error.hpp"
#include "stopwatch.hpp"

namespace hbf {

Eigen::VectorXd HarmonicBalance::linear_guess(double omega, bool sliding) const {
    using Complex = std::complex<double>;
    const int n = coefficients(), dofs = system_.dofs(), nc = static_cast<int>(system_.contacts.size());
    // The response to F cos(h w t) sits on harmonic h, at the frequency h w.
    const int h = load_harmonic(), cos_row = 2 * h - 1, sin_row = cos_row + 1;
    const double drive = h * omega;
    // Each contact as a linear element of complex stiffness k + i omega d (pre-sliding), or held
    // rigid (exact Coulomb: its force is the constraint's multiplier); none when sliding.
    std::vector<Complex> element(static_cast<std::size_t>(nc), Complex(0.0, 0.0));
    std::vector<bool> rigid(static_cast<std::size_t>(nc), false);
    for (std::size_t c = 0; c < system_.contacts.size() && !sliding; ++c) {
        const Contact& k = system_.contacts[c];
        const StuckElement stuck = contact_law(k.law).stuck(k);
        if (stuck.rigid)
            rigid[c] = true;
        else
            element[c] = stuck.at(drive);
    }
    // Harmonic h: Q = Q0 - G Lambda with Lambda_c = element_c Q_c, or Q_c = 0 (rigid).
    Eigen::VectorXd x = Eigen::VectorXd::Zero(all_unknowns_);
    Eigen::VectorXcd force = Eigen::VectorXcd::Zero(nc);
    auto put = [&](Eigen::Index offset, Complex a) {
        if (!std::isfinite(std::abs(a))) return;  // exact resonance: start from rest
        x(offset + cos_row) = a.real();  // y = Re(Y e^{i h theta}) = Re Y cos - Im Y sin
        x(offset + sin_row) = -a.imag();
    };
    if (condensed_) {
        const Receptance::Harmonic g = receptance_->solve(h, omega, true);
        if (g.ok) {
            // Unknown u_c: Q_c, or Lambda_c for a rigid contact.
            Eigen::MatrixXcd a(nc, nc);
            for (int c = 0; c < nc; ++c)
                for (int d = 0; d < nc; ++d) {
                    const auto dd = static_cast<std::size_t>(d);
                    // Lambda' = Lambda - (kappa + i w delta) Q (the shifted structure's force)
                    const Complex shift(shift_stiffness_(d), drive * shift_damping_(d));
                    a(c, d) = rigid[dd] ? g.contact(c, d) : g.contact(c, d) * (element[dd] - shift) + (c == d ? 1.0 : 0.0);
                }
            const Eigen::VectorXcd u = a.fullPivLu().solve(g.contact_load);
            for (int c = 0; c < nc; ++c) {
                const auto cc = static_cast<std::size_t>(c);
                force(c) = rigid[cc] ? u(c) : element[cc] * u(c);
                if (!rigid[cc]) put(c * n, u(c));
            }
        }
    } else {
        // (K - w^2 M + i w C + sum_c element_c w_c w_c^T) Y + W_R Lambda_R = F, W_R^T Y = 0.
        std::vector<int> stuck;
        Eigen::MatrixXcd z = dynamic_stiffness(Eigen::MatrixXd(system_.mass), Eigen::MatrixXd(system_.damping),
                                               Eigen::MatrixXd(system_.stiffness), drive);
        for (int c = 0; c < nc; ++c) {
            const Eigen::VectorXd& w = directions_[static_cast<std::size_t>(c)];
            if (rigid[static_cast<std::size_t>(c)])
                stuck.push_back(c);
            else
                z += element[static_cast<std::size_t>(c)] * (w * w.transpose()).cast<Complex>();
        }
        const auto m = static_cast<Eigen::Index>(stuck.size());
        Eigen::MatrixXcd a = Eigen::MatrixXcd::Zero(dofs + m, dofs + m);
        a.topLeftCorner(dofs, dofs) = z;
        for (Eigen::Index j = 0; j < m; ++j) {
            const Eigen::VectorXd& w = directions_[static_cast<std::size_t>(stuck[static_cast<std::size_t>(j)])];
            a.block(0, dofs + j, dofs, 1) = w.cast<Complex>();
            a.block(dofs + j, 0, 1, dofs) = w.cast<Complex>().transpose();
        }
        Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(dofs + m);
        rhs.head(dofs) = system_.excitation.cast<Complex>();
        const Eigen::VectorXcd amplitude = a.fullPivLu().solve(rhs);
        for (int d = 0; d < dofs; ++d) put(d * n, amplitude(d));
        for (Eigen::Index j = 0; j < m; ++j) force(stuck[static_cast<std::size_t>(j)]) = amplitude(dofs + j);
    }
    for (std::size_t c = 0; c < system_.contacts.size(); ++c) {
        if (state_offset_[c] < 0) continue;
        const Contact& k = system_.contacts[c];
        const Eigen::VectorXd q = relative_all(x, static_cast<int>(c));
        // zero so far; sliding: the friction force at its limit in phase with the velocity
        // (harmonic h of F_c sign(v) is (4/pi) F_c v / |v|, v ~ (s_h cos - c_h sin) for v on
        // harmonic h); stuck: the law's state in the linear stuck response
        contact_law(k.law).guess_state(k, sliding, q, cos_row, force(static_cast<Eigen::Index>(c)),
                                       x.segment(state_offset_[c], n));
    }
    if (!odd_) return x;
    Eigen::VectorXd balanced(unknowns_);
    for (int i = 0; i < unknowns_; ++i) balanced(i) = x(balanced_index_[static_cast<std::size_t>(i)]);
    return balanced;
}

}  // namespace hbf
