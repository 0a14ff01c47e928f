// hbfriction — time integration of models with massless DOFs (massless.hpp).
#include "time_integration/massless.hpp"

#include "hbf/contact_law.hpp"

#include <cmath>
#include <complex>
#include <vector>

namespace hbf::detail {

namespace {
constexpr double pi = 3.14159265358979323846;
}  // namespace

TimeIntegrationOptions reduced_options(const MasslessCondensation& condensation, const TimeIntegrationOptions& options) {
    TimeIntegrationOptions out = options;
    out.outputs.clear();
    for (const Output& o : options.outputs) {
        std::vector<Output::Term> terms;
        bool massive = true;
        for (const auto& [i, c] : o.terms()) {
            const int p = condensation.position(i);
            if (condensation.massless(i)) massive = false;
            terms.emplace_back(p, c);
        }
        if (massive) out.outputs.emplace_back(o.name(), terms);
    }
    return out;
}

void expand(const MasslessCondensation& condensation, PeriodicResponse& r, const TimeIntegrationOptions& options) {
    const System &system = condensation.original(), &reduced = condensation.reduced();
    const std::vector<int> &massive_dofs = condensation.massive_dofs(), &massless_dofs = condensation.massless_dofs();
    const int n = system.dofs(), nr = static_cast<int>(massive_dofs.size()), nc = static_cast<int>(system.contacts.size());
    const auto ns = static_cast<Eigen::Index>(massless_dofs.size());
    const double omega = r.omega;
    const Eigen::Index samples = r.time.size();
    // Friction forces of the reduced contacts at a reduced state (the converted ones are
    // Jenkins elements: f = k (w^_R^T y_R + p cos - s)), for the state at t = 0 (cos = 1).
    auto forces_at = [&](const Eigen::VectorXd& reduced_state) {
        Eigen::VectorXd f = Eigen::VectorXd::Zero(nc);
        for (int c = 0; c < nc; ++c) {
            if (!condensation.converted(c)) continue;
            const Contact& k = reduced.contacts[static_cast<std::size_t>(c)];
            f(c) = k.stiffness * (k.direction.dot(reduced_state.head(nr)) + k.base_motion - reduced_state(2 * nr + c));
        }
        return f;
    };
    // Displacement and velocity samples of every DOF.
    Eigen::MatrixXd displacement(samples, n), velocity(samples, n);
    Eigen::MatrixXd massless(samples, ns);
    for (Eigen::Index j = 0; j < samples; ++j) {
        const Eigen::VectorXd y_r = r.displacement.row(j).transpose();
        const Eigen::VectorXd f = r.friction_force.row(j).transpose();
        massless.row(j) = condensation.massless_displacement(y_r, f, std::cos(system.excitation_harmonic * omega * r.time(j)))
                              .transpose();
    }
    for (int k = 0; k < nr; ++k) {
        displacement.col(massive_dofs[static_cast<std::size_t>(k)]) = r.displacement.col(k);
        velocity.col(massive_dofs[static_cast<std::size_t>(k)]) = r.velocity.col(k);
    }
    const double dt = 2.0 * pi / omega / static_cast<double>(std::max<Eigen::Index>(samples, 1));
    for (Eigen::Index k = 0; k < ns; ++k) {
        const int i = massless_dofs[static_cast<std::size_t>(k)];
        displacement.col(i) = massless.col(k);
        for (Eigen::Index j = 0; j < samples; ++j)  // periodic central difference
            velocity(j, i) = (massless((j + 1) % samples, k) - massless((j + samples - 1) % samples, k)) / (2.0 * dt);
    }
    // First harmonics: exact for massive DOFs; massless ones from them and the sampled force.
    Eigen::VectorXcd f1 = Eigen::VectorXcd::Zero(nc);
    for (Eigen::Index j = 0; j < samples; ++j) {
        const std::complex<double> phase(std::cos(omega * r.time(j)), -std::sin(omega * r.time(j)));
        f1 += (2.0 / static_cast<double>(samples)) * phase * r.friction_force.row(j).transpose().cast<std::complex<double>>();
    }
    Eigen::VectorXcd harmonic1(n);
    for (int k = 0; k < nr; ++k) harmonic1(massive_dofs[static_cast<std::size_t>(k)]) = r.harmonic1(k);
    const Eigen::VectorXcd h1_s = condensation.massless_harmonic(r.harmonic1, f1);
    for (Eigen::Index k = 0; k < ns; ++k) harmonic1(massless_dofs[static_cast<std::size_t>(k)]) = h1_s(k);
    std::vector<double> y_max(static_cast<std::size_t>(n)), y_amp1(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const int p = condensation.position(i);
        y_max[static_cast<std::size_t>(i)] = !condensation.massless(i)
                                                 ? r.y_max[static_cast<std::size_t>(p)]
                                                 : displacement.col(i).cwiseAbs().maxCoeff();
        y_amp1[static_cast<std::size_t>(i)] = std::abs(harmonic1(i));
    }
    // Outputs: the reduced integration's own where they involve massive DOFs only.
    std::vector<double> output_max, output_amp1;
    std::size_t mapped = 0;
    for (const Output& o : options.outputs) {
        bool massive = true;
        std::complex<double> h = 0.0;
        for (const auto& [i, c] : o.terms()) {
            if (condensation.massless(i)) massive = false;
            h += c * harmonic1(i);
        }
        output_amp1.push_back(std::abs(h));
        if (massive) {
            output_max.push_back(r.output_max[mapped++]);
        } else {
            output_max.push_back(o.combine(displacement).cwiseAbs().maxCoeff());
        }
    }
    // The state at t = 0 in the original layout.
    const Eigen::VectorXd reduced_state = r.state;
    Eigen::VectorXd state = Eigen::VectorXd::Zero(2 * n + 2 * nc);
    if (reduced_state.size() == 2 * nr + 2 * nc) {
        const Eigen::VectorXd y_s =
            condensation.massless_displacement(reduced_state.head(nr), forces_at(reduced_state), 1.0);
        for (int k = 0; k < nr; ++k) {
            state(massive_dofs[static_cast<std::size_t>(k)]) = reduced_state(k);
            state(n + massive_dofs[static_cast<std::size_t>(k)]) = reduced_state(nr + k);
        }
        for (Eigen::Index k = 0; k < ns; ++k) {
            state(massless_dofs[static_cast<std::size_t>(k)]) = y_s(k);
            state(n + massless_dofs[static_cast<std::size_t>(k)]) = samples > 0 ? velocity(0, massless_dofs[static_cast<std::size_t>(k)]) : 0.0;
        }
        for (int c = 0; c < nc; ++c) {
            const bool coulomb = rigid_slider(system.contacts[static_cast<std::size_t>(c)]);
            state(2 * n + c) = condensation.converted(c) && coulomb ? 0.0 : reduced_state(2 * nr + c);
            state(2 * n + nc + c) = reduced_state(2 * nr + nc + c);
        }
    }
    r.state = state;
    r.y_max = y_max;
    r.y_amp1 = y_amp1;
    r.harmonic1 = harmonic1;
    r.output_max = output_max;
    r.output_amp1 = output_amp1;
    r.displacement = displacement;
    r.velocity = velocity;
}

}  // namespace hbf::detail
