// hbfriction — the linear limits (linear_limits.hpp): the stuck steady state and the
// resonances of the released, stuck and rigid structure.
#include "hbf/linear_limits.hpp"
#include "hbf/cyclic.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/static_state.hpp"
#include "base/enum_table.hpp"

namespace hbf {

StuckResponse stuck_linear_response(const System& system, double fundamental) {
    using Complex = std::complex<double>;
    const double omega = system.excitation_harmonic * fundamental;  // the force's frequency
    const int n = system.dofs(), nc = static_cast<int>(system.contacts.size());
    Eigen::MatrixXcd a = dynamic_stiffness(Eigen::MatrixXd(system.mass), Eigen::MatrixXd(system.damping),
                                           Eigen::MatrixXd(system.stiffness), omega);
    std::vector<int> rigid;
    std::vector<Complex> element(static_cast<std::size_t>(nc), Complex(0.0, 0.0));
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);  // about the static state
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        const std::vector<StuckElement>& along = elements[static_cast<std::size_t>(c)];
        const StuckElement stuck = along.front();
        if (stuck.rigid) {
            rigid.push_back(c);
            continue;
        }
        element[static_cast<std::size_t>(c)] = stuck.at(omega);
        // every direction's spring and damper (one for the laws along one direction)
        const Eigen::MatrixXd w = system.contact_directions(contact);
        for (Eigen::Index j = 0; j < w.cols(); ++j)
            a += along[static_cast<std::size_t>(j)].at(omega) * (w.col(j) * w.col(j).transpose()).cast<Complex>();
    }
    const int m = static_cast<int>(rigid.size());
    Eigen::MatrixXcd kkt = Eigen::MatrixXcd::Zero(n + m, n + m);
    kkt.topLeftCorner(n, n) = a;
    // The constraint rows and columns scaled to the size of A's entries (a finite-element K
    // has entries ~1e10 against w's ~1: unscaled, the LU judged the KKT matrix singular); the
    // multipliers are scaled back below.
    const double scale = std::max(a.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
    for (int j = 0; j < m; ++j) {
        const Eigen::VectorXd w = system.contact_direction(system.contacts[static_cast<std::size_t>(rigid[static_cast<std::size_t>(j)])]);
        kkt.block(0, n + j, n, 1) = (scale * w).cast<Complex>();
        kkt.block(n + j, 0, 1, n) = (scale * w.transpose()).cast<Complex>();
    }
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(n + m);
    rhs.head(n) = system.excitation.cast<Complex>();
    // An elastic slider whose spring's far end moves (Contact::base_motion p): its stuck force
    // k (w^T Y + p) loads the structure by -k p w.
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        if (contact.base_motion != 0.0)
            rhs.head(n) -= element[static_cast<std::size_t>(c)] * contact.base_motion *
                           system.contact_direction(contact).cast<Complex>();
    }
    StuckResponse out;
    Eigen::FullPivLU<Eigen::MatrixXcd> lu(kkt);
    if (!lu.isInvertible()) return out;
    const Eigen::VectorXcd x = lu.solve(rhs);
    if (!x.allFinite()) return out;
    out.ok = true;
    out.amplitude = x.head(n);
    out.force = Eigen::VectorXcd::Zero(nc);
    for (int j = 0; j < m; ++j) out.force(rigid[static_cast<std::size_t>(j)]) = scale * x(n + j);
    for (int c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[static_cast<std::size_t>(c)];
        if (elements[static_cast<std::size_t>(c)].front().rigid) continue;
        out.force(c) = element[static_cast<std::size_t>(c)] *
                       (system.contact_direction(contact).cast<Complex>().dot(out.amplitude) + contact.base_motion);
    }
    return out;
}

constexpr detail::EnumName<LinearResonance::Limit> linear_resonance_limit_names[] = {
    {LinearResonance::Limit::released, "released"}, {LinearResonance::Limit::stuck, "stuck"},
    {LinearResonance::Limit::rigid, "rigid"}};

std::string to_string(LinearResonance::Limit limit) {
    return detail::enum_name(linear_resonance_limit_names, limit, "limit");
}

namespace {
/// The natural frequencies sqrt(lambda) of K phi = lambda M phi (finite, real, lambda > 0).
std::vector<double> natural_frequencies(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass) {
    std::vector<double> out;
    if (stiffness.rows() == 0) return out;
    Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> qz(stiffness, mass, false);
    if (qz.info() != Eigen::Success) return out;
    const double scale = std::max(stiffness.cwiseAbs().maxCoeff(), mass.cwiseAbs().maxCoeff());
    for (Eigen::Index j = 0; j < qz.alphas().size(); ++j) {
        const std::complex<double> alpha = qz.alphas()(j);
        const double beta = qz.betas()(j);
        // Infinite (a massless direction: beta at rounding) or complex (rounding of a symmetric
        // pencil; a real pair otherwise cannot occur for M >= 0): not a resonance.
        if (!(std::abs(beta) > 1e-13 * scale) || std::abs(alpha.imag()) > 1e-8 * std::abs(alpha)) continue;
        const double lambda = alpha.real() / beta;
        if (lambda > 0.0 && std::isfinite(lambda)) out.push_back(std::sqrt(lambda));
    }
    return out;
}
/// sqrt(lambda) of the Hermitian pencil (K, M), M positive definite; none where M is not (a
/// sector with massless DOFs: no resonance is guarded there).
std::vector<double> hermitian_frequencies(const Eigen::MatrixXcd& k, const Eigen::MatrixXcd& m) {
    const Eigen::MatrixXcd ks = (k + k.adjoint()) / 2.0, ms = (m + m.adjoint()) / 2.0;
    if (ms.rows() == 0 || Eigen::LLT<Eigen::MatrixXcd>(ms).info() != Eigen::Success) return {};
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> solver(ks, ms);
    std::vector<double> out;
    if (solver.info() != Eigen::Success) return out;
    for (Eigen::Index j = 0; j < solver.eigenvalues().size(); ++j)
        if (solver.eigenvalues()(j) > 0.0) out.push_back(std::sqrt(solver.eigenvalues()(j)));
    return out;
}
}  // namespace

std::vector<LinearResonance> linear_resonances(const System& system, double omega_low, double omega_high) {
    std::vector<LinearResonance> out;
    const int n = system.dofs();
    if (n == 0 || n > linear_resonance_dof_limit) return out;
    const Eigen::MatrixXd mass(system.mass), stiffness(system.stiffness);
    const double h = std::max(1, system.excitation_harmonic);
    auto add = [&](const std::vector<double>& natural, LinearResonance::Limit limit) {
        for (const double w : natural) {
            const double fundamental = w / h;
            if (fundamental >= omega_low && fundamental <= omega_high) out.push_back({fundamental, limit});
        }
    };
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);  // about the static state
    // The force elements without friction that act in every state (polynomial springs,
    // dampers: ContactLaw::friction, unilateral) are part of the structure in each limit: their
    // linear spring in K, their direction free.
    Eigen::MatrixXd structure = stiffness;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const ContactLaw& law = contact_law(system.contacts[c].law);
        if (law.friction() || law.unilateral()) continue;
        const Eigen::MatrixXd w = system.contact_directions(system.contacts[c]);
        for (Eigen::Index j = 0; j < w.cols() && j < static_cast<Eigen::Index>(elements[c].size()); ++j)
            structure += elements[c][static_cast<std::size_t>(j)].stiffness * w.col(j) * w.col(j).transpose();
    }
    // A sector (cyclic.hpp): each limit on the independent DOFs at the excitation's harmonic
    // index (T^H A T, Hermitian; the rigid subspace of the turned directions T^T w).
    const bool sector = system.cyclic.active();
    const Eigen::MatrixXcd t = sector ? cyclic_transform(system, system.cyclic.phase()) : Eigen::MatrixXcd();
    auto frequencies = [&](const Eigen::MatrixXd& k, const Eigen::MatrixXd& m) -> std::vector<double> {
        if (!sector) return natural_frequencies(k, m);
        return hermitian_frequencies(t.adjoint() * k.cast<std::complex<double>>() * t,
                                     t.adjoint() * m.cast<std::complex<double>>() * t);
    };
    add(frequencies(structure, mass), LinearResonance::Limit::released);
    Eigen::MatrixXd stuck = structure;
    bool springs = false;
    Eigen::MatrixXd directions(n, 0);  // every direction of every contact
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Contact& contact = system.contacts[c];
        const ContactLaw& law = contact_law(contact.law);
        if (!law.friction() && !law.unilateral()) continue;
        const Eigen::MatrixXd w = system.contact_directions(contact);
        directions.conservativeResize(Eigen::NoChange, directions.cols() + w.cols());
        directions.rightCols(w.cols()) = w;
        const std::vector<StuckElement>& along = elements[c];
        for (Eigen::Index j = 0; j < w.cols(); ++j) {
            const StuckElement& element = along[static_cast<std::size_t>(j)];
            if (!element.rigid && element.stiffness != 0.0) {  // a stuck spring (jenkins, dahl, lugre, elastic)
                stuck += element.stiffness * w.col(j) * w.col(j).transpose();
                springs = springs || element.stiffness > 0.0;
            }
        }
    }
    if (springs) add(frequencies(stuck, mass), LinearResonance::Limit::stuck);
    if (sector && directions.cols() > 0) {
        const Eigen::MatrixXcd rows = (t.transpose() * directions.cast<std::complex<double>>()).transpose();
        Eigen::FullPivLU<Eigen::MatrixXcd> lu(rows);
        if (lu.rank() < t.cols()) {
            const Eigen::MatrixXcd basis = lu.kernel();
            const Eigen::MatrixXcd tb = t * basis;
            add(hermitian_frequencies(tb.adjoint() * structure.cast<std::complex<double>>() * tb,
                                      tb.adjoint() * mass.cast<std::complex<double>>() * tb),
                LinearResonance::Limit::rigid);
        }
    } else if (directions.cols() > 0) {
        // y = B z with B an orthonormal basis of the null space of W^T: the rigid contacts' subspace.
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(directions);
        const Eigen::Index rank = qr.rank();
        if (rank < n) {
            const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
            const Eigen::MatrixXd basis = q.rightCols(n - rank);
            add(natural_frequencies(basis.transpose() * structure * basis, basis.transpose() * mass * basis),
                LinearResonance::Limit::rigid);
        }
    }
    std::sort(out.begin(), out.end(), [](const LinearResonance& a, const LinearResonance& b) { return a.omega < b.omega; });
    return out;
}

}  // namespace hbf
