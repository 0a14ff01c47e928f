// hbfriction — time integration of rigid unilateral contacts on massless coordinates
// (unilateral_contacts.hpp).
#include "time_integration/unilateral_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <vector>

#include "contact/massless_contacts.hpp"
#include "time_integration/elastic_contacts.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"

namespace hbf::detail {

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr int max_dofs = 2000;
constexpr long max_steps_per_period = 1L << 22;

using Eigen::MatrixXd;
using Eigen::VectorXd;

using Block = RigidContact;  // one contact's entries of lambda (normal_contact.hpp)

/// The contacts' state after a step: per contact 0 open, 1 stuck, 2 slipping.
struct Step {
    VectorXd yc, lambda, q, free;  // free: q0, the relative displacements without contact forces
    std::vector<int> state;
};

class UnilateralIntegrator {
public:
    UnilateralIntegrator(const System& system, double omega, long steps)
        : drive_(system.excitation_harmonic * omega),
          dt_(2.0 * pi / omega / static_cast<double>(steps)),
          s_(split_massless_contacts(system, "time integration")) {
        minv_ = s_.Mmm.llt().solve(MatrixXd::Identity(s_.Mmm.rows(), s_.Mmm.cols()));
        velocity_ = (s_.Mmm + 0.5 * dt_ * s_.Cmm).partialPivLu();
    }

    int massive() const { return static_cast<int>(s_.massive.size()); }
    int lambdas() const { return s_.lambdas; }
    double dt() const { return dt_; }

    /// The contacts at time t for the masses at ym, the tangential displacements of the last
    /// step `previous` (its normal entries unused), lambda warm-started from `out.lambda`
    /// (normal_contact.hpp: solve_rigid_contacts).
    bool contacts(double t, const VectorXd& ym, const VectorXd& previous, Step& out, std::string& failure) const {
        const VectorXd yc0 = s_.Kcc_inverse * (s_.Fc * std::cos(drive_ * t) + s_.Sc - s_.Kcm * ym);
        out.free = s_.W.transpose() * yc0;
        RigidContactSolution solution;
        solution.lambda = out.lambda;
        const bool ok = solve_rigid_contacts(s_.blocks, s_.G, out.free, previous, solution);
        out.lambda = solution.lambda;
        out.q = solution.q;
        out.state = solution.state;
        out.yc = yc0 - s_.B * out.lambda;
        if (!ok)
            failure = "the contact problem at t = " + format_number(t) + " did not converge (residual " +
                      format_number(solution.residual) + " of the contact forces)";
        return ok;
    }

    /// The force on the masses at time t (the contact forces act on the massless nodes alone).
    VectorXd force(double t, const VectorXd& ym, const VectorXd& yc) const {
        return s_.Fm * std::cos(drive_ * t) + s_.Sm - s_.Kmm * ym - s_.Kmc * yc;
    }

    /// One Verlet step from t (ym, vm, am, the contacts `step` at t) to t + dt.
    bool advance(double t, VectorXd& ym, VectorXd& vm, VectorXd& am, Step& step, std::string& failure) const {
        const VectorXd previous = step.q;
        const std::vector<int> before = step.state;
        ym += dt_ * vm + 0.5 * dt_ * dt_ * am;
        if (!contacts(t + dt_, ym, previous, step, failure)) return false;
        // A contact that closes within the step holds its tangential node from the closing
        // instant, not from the step's start: the history moves to the free tangential position
        // there, interpolated linearly by the free normal displacement's crossing of g_0
        // (second order in the step, where holding the start would be first order).
        VectorXd history = previous;
        bool closed = false;
        for (std::size_t c = 0; c < s_.blocks.size() && before.size() == s_.blocks.size(); ++c) {
            if (before[c] != 0 || step.state[c] == 0) continue;
            const Block& b = s_.blocks[c];
            const int normal = b.first + b.d;
            const double reach = step.free(normal) - previous(normal);
            const double fraction = reach > 0.0 ? std::clamp((b.gap - previous(normal)) / reach, 0.0, 1.0) : 1.0;
            for (int j = b.first; j < normal; ++j) history(j) = previous(j) + fraction * (step.free(j) - previous(j));
            closed = true;
        }
        if (closed && !contacts(t + dt_, ym, history, step, failure)) return false;
        const VectorXd f = force(t + dt_, ym, step.yc);
        vm = velocity_.solve(s_.Mmm * vm + 0.5 * dt_ * (s_.Mmm * am + f));
        am = acceleration(f, vm);
        return true;
    }

    /// M^-1 (f - C v) on the DOFs with mass.
    VectorXd acceleration(const VectorXd& f, const VectorXd& vm) const { return minv_ * (f - s_.Cmm * vm); }

    const std::vector<int>& massive_dofs() const { return s_.massive; }
    const std::vector<int>& massless_dofs() const { return s_.massless; }
    const std::vector<Block>& blocks() const { return s_.blocks; }
    const MatrixXd& damping() const { return s_.Cmm; }

private:
    double drive_;
    double dt_;
    MasslessContacts s_;
    MatrixXd minv_;
    Eigen::PartialPivLU<MatrixXd> velocity_;
};

/// The steps per period: a multiple of `samples`, at least 16 of them, and at least 20 per
/// period of the stiffest mode of (M_mm, K_mm).
long steps_per_period(const System& system, double omega, int samples) {
    const int n = system.dofs();
    const MatrixXd M(system.mass), K(system.stiffness);
    std::vector<int> massive;
    for (int i = 0; i < n; ++i)
        if (M.col(i).cwiseAbs().maxCoeff() > 0.0) massive.push_back(i);
    const auto m = static_cast<Eigen::Index>(massive.size());
    const MatrixXd Mmm = pick(M, massive, massive), Kmm = pick(K, massive, massive);
    double highest = 0.0;
    if (m > 0) {
        Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> modes(Kmm, Mmm, Eigen::EigenvaluesOnly);
        if (modes.info() == Eigen::Success) highest = std::sqrt(std::max(modes.eigenvalues().maxCoeff(), 0.0));
    }
    const double needed = std::max(16.0 * samples, 20.0 * highest / omega);
    const double multiple = std::ceil(needed / samples);
    if (!(multiple * samples <= static_cast<double>(max_steps_per_period)))
        throw InvalidInput("w = " + format_number(omega) + ": the stiffest mode of the DOFs with mass (" +
                           format_number(highest) + " rad per time unit) needs " + format_number(multiple * samples) +
                           " steps per period for time integration of law unilateral: allowed at most " +
                           std::to_string(max_steps_per_period) + " (a higher w, or a softer model)");
    return static_cast<long>(multiple) * samples;
}

}  // namespace

bool has_unilateral_contacts(const System& system) {
    return std::any_of(system.contacts.begin(), system.contacts.end(), [](const Contact& c) {
        return contact_law(c.law).time_integrator() == TimeIntegrator::unilateral_contacts;
    });
}

PeriodicResponse integrate_unilateral_contacts(const System& system, double omega,
                                               const TimeIntegrationOptions& options,
                                               const Eigen::VectorXd* initial_state) {
    const int n = system.dofs();
    if (n > max_dofs)
        throw InvalidInput("dofs = " + std::to_string(n) + " with law unilateral: time integration of rigid contacts "
                           "allows at most " + std::to_string(max_dofs) + " DOFs");
    if (initial_state && (initial_state->size() != 2 * n || !initial_state->allFinite()))
        throw InvalidInput("initial state has " + std::to_string(initial_state->size()) +
                           " entries or non-finite values: allowed " + std::to_string(2 * n) +
                           " finite values (y and y' of every DOF)");
    const int kept = options.samples_per_period;
    const long steps = steps_per_period(system, omega, kept);
    const UnilateralIntegrator integrator(system, omega, steps);
    const std::vector<int>& massive = integrator.massive_dofs();
    const std::vector<int>& massless = integrator.massless_dofs();
    const int nm = integrator.massive();
    VectorXd ym = VectorXd::Zero(nm), vm = VectorXd::Zero(nm);
    Step step;
    if (initial_state)
        for (int i = 0; i < nm; ++i) {
            ym(i) = (*initial_state)(massive[static_cast<std::size_t>(i)]);
            vm(i) = (*initial_state)(n + massive[static_cast<std::size_t>(i)]);
        }
    std::string failure;
    PeriodicResponse out;
    out.omega = omega;
    out.displacement_scale = options.displacement_scale > 0.0 ? options.displacement_scale : response_scale(system, omega);
    // the history before t = 0: the nodes where the initial state puts them (at rest: free of contact forces)
    {
        step.q = VectorXd::Zero(integrator.lambdas());
        if (initial_state) {
            std::size_t c = 0;
            for (const Contact& k : system.contacts) {
                const MatrixXd w = system.contact_directions(k);
                step.q.segment(integrator.blocks()[c].first, w.cols()) = w.transpose() * initial_state->head(n);
                ++c;
            }
        }
    }
    auto fail = [&](const std::string& where) {
        out.message = failure + " (" + where + ", w = " + format_number(omega) + ")";
        out.state = VectorXd::Zero(2 * n);
        return out;
    };
    if (!integrator.contacts(0.0, ym, step.q, step, failure)) return fail("t = 0");
    VectorXd am = integrator.acceleration(integrator.force(0.0, ym, step.yc), vm);
    const double dt = integrator.dt(), period = 2.0 * pi / omega;
    auto state_of = [&](const VectorXd& y, const VectorXd& v, const Step& s) {
        VectorXd x(2 * nm + s.q.size());
        x << y, v / omega, s.q;
        return x;
    };
    for (int k = 1; k <= options.max_periods + 1; ++k) {
        const bool final = out.converged;
        if (const std::string why = k > 1 && !final ? options.stop_reason() : std::string(); !why.empty()) {
            out.stop_after(k - 1, why);
            out.state = VectorXd::Zero(2 * n);  // as a point that did not converge
            return out;
        }
        const VectorXd start = state_of(ym, vm, step);
        // the final period's records
        MatrixXd Y, V, L;
        std::vector<std::vector<int>> states;
        if (final) {
            Y.resize(steps + 1, n);
            V.resize(steps + 1, nm);
            L.resize(steps + 1, step.lambda.size());
            states.reserve(static_cast<std::size_t>(steps + 1));
        }
        auto record = [&](long j) {
            for (int i = 0; i < nm; ++i) Y(j, massive[static_cast<std::size_t>(i)]) = ym(i);
            for (std::size_t i = 0; i < massless.size(); ++i) Y(j, massless[i]) = step.yc(static_cast<Eigen::Index>(i));
            V.row(j) = vm.transpose();
            L.row(j) = step.lambda.transpose();
            states.push_back(step.state);
        };
        if (final) record(0);
        for (long j = 0; j < steps; ++j) {
            if (!integrator.advance(static_cast<double>(j) * dt, ym, vm, am, step, failure))
                return fail("period " + std::to_string(k));
            if (final) record(j + 1);
        }
        out.periods = k;
        if (!final) {
            const VectorXd end = state_of(ym, vm, step);
            const double size_now = end.cwiseAbs().maxCoeff();
            const double change = (end - start).cwiseAbs().maxCoeff();
            out.poincare_change = size_now > 0.0 ? change / size_now : change;
            if (k >= options.min_periods && out.poincare_change <= options.steady_tolerance) out.converged = true;
            if (!out.converged && k == options.max_periods) break;
            continue;
        }
        // ---- the final period's metrics ----
        out.message = "converged after " + std::to_string(k - 1) + " periods (Poincare change " +
                      format_number(out.poincare_change) + ")";
        const auto S = static_cast<Eigen::Index>(steps);
        out.harmonic1 = Eigen::VectorXcd::Zero(n);
        for (Eigen::Index j = 0; j < S; ++j) {
            const double phase = omega * static_cast<double>(j) * dt;
            out.harmonic1 += (2.0 / static_cast<double>(S)) * Y.row(j).transpose().cast<std::complex<double>>() *
                             std::complex<double>(std::cos(phase), std::sin(phase));
        }
        // (c1 - i s1) from sum y (cos + i sin): c1 = 2/S sum y cos, s1 = 2/S sum y sin
        out.harmonic1 = out.harmonic1.conjugate().eval();
        for (int i = 0; i < n; ++i) {
            out.y_max.push_back(refined_max(Y.col(i).head(S)));
            out.y_amp1.push_back(std::abs(out.harmonic1(i)));
        }
        for (const Output& o : options.outputs) {
            VectorXd series(S);
            for (Eigen::Index j = 0; j < S; ++j) series(j) = o.of(Y.row(j).transpose());
            out.output_max.push_back(refined_max(series));
            std::complex<double> h(0.0, 0.0);
            for (int i = 0; i < n; ++i) h += o.of(VectorXd::Unit(n, i)) * out.harmonic1(i);
            out.output_amp1.push_back(std::abs(h));
        }
        // energies: input sum F cos(t_mid) . dy, viscous trapezoid of v^T C v, friction lambda_mid . dq
        VectorXd F = system.excitation.size() ? VectorXd(system.excitation) : VectorXd::Zero(n);
        out.input_energy = out.viscous_energy = out.energy = 0.0;
        std::vector<double> energy(system.contacts.size(), 0.0), stuck(system.contacts.size(), 0.0),
            open(system.contacts.size(), 0.0);
        std::vector<MatrixXd> w;
        for (const Contact& c : system.contacts) w.push_back(system.contact_directions(c));
        const std::vector<Block>& blocks = integrator.blocks();
        double normal_work = 0.0;
        out.stick_margin_min = std::numeric_limits<double>::infinity();
        out.stick_margin_max = -std::numeric_limits<double>::infinity();
        out.switches = 0;
        std::vector<VectorXd> normal(blocks.size(), VectorXd(S));
        out.friction_force = MatrixXd(kept, static_cast<Eigen::Index>(blocks.size()));
        for (Eigen::Index j = 0; j < S; ++j) {
            const double mid = (static_cast<double>(j) + 0.5) * dt;
            const VectorXd dy = (Y.row(j + 1) - Y.row(j)).transpose();
            out.input_energy += std::cos(system.excitation_harmonic * omega * mid) * F.dot(dy);
            out.viscous_energy += 0.5 * dt * (V.row(j) * integrator.damping() * V.row(j).transpose() +
                                              V.row(j + 1) * integrator.damping() * V.row(j + 1).transpose())(0, 0);
            for (std::size_t c = 0; c < blocks.size(); ++c) {
                const Block& b = blocks[c];
                const VectorXd lambda = 0.5 * (L.row(j) + L.row(j + 1)).segment(b.first, b.d + 1).transpose();
                const VectorXd dq = w[c].transpose() * dy;
                energy[c] += lambda.head(b.d).dot(dq.head(b.d));  // the friction's; the normal one
                normal_work += lambda(b.d) * dq(b.d);           // does none (but at a corner in a step)
                const int now = states[static_cast<std::size_t>(j + 1)][c], before = states[static_cast<std::size_t>(j)][c];
                if (now == 1) stuck[c] += dt;
                if (now == 0) open[c] += dt;
                if (now != before) ++out.switches;
                normal[c](j) = L(j + 1, b.first + b.d);
                if (c == 0) {
                    const double limit = b.mu * normal[c](j);
                    const double margin = now == 0 ? 1.0
                                          : now == 2 ? 0.0
                                          : (limit > 0.0 ? L.row(j + 1).segment(b.first, b.d).norm() / limit - 1.0 : -1.0);
                    out.stick_margin_min = std::min(out.stick_margin_min, margin);
                    out.stick_margin_max = std::max(out.stick_margin_max, margin);
                }
            }
        }
        for (std::size_t c = 0; c < blocks.size(); ++c) {
            ContactRegime regime = contact_regime(stuck[c], period);
            regime.separated_fraction = open[c] / period;
            regime.normal_mean = normal[c].mean();
            regime.normal_amplitude = 0.5 * (normal[c].maxCoeff() - normal[c].minCoeff());
            regime.energy = energy[c];
            out.energy += energy[c];
            out.contacts.push_back(regime);
        }
        summarise_contacts(out);
        if (out.contacts.empty()) out.stick_margin_min = out.stick_margin_max = 0.0;
        const double reach = pi * system.excitation_harmonic * system.excitation.norm() * out.harmonic1.norm();
        out.energy_error = energy_imbalance(out.input_energy, out.viscous_energy, out.energy + normal_work, reach);
        // the samples, every (steps / kept)-th step; massless velocities by central differences
        const long stride = steps / kept;
        out.time.resize(kept);
        out.displacement.resize(kept, n);
        out.velocity.resize(kept, n);
        for (int j = 0; j < kept; ++j) {
            const Eigen::Index at = static_cast<Eigen::Index>(j) * stride;
            out.time(j) = static_cast<double>(at) * dt;
            out.displacement.row(j) = Y.row(at);
            const Eigen::Index before = at == 0 ? S - 1 : at - 1;
            const VectorXd central = (Y.row(at + 1) - Y.row(before)).transpose() / (2.0 * dt);
            for (int i = 0; i < nm; ++i) out.velocity(j, massive[static_cast<std::size_t>(i)]) = V(at, i);
            for (int i : massless) out.velocity(j, i) = central(i);
            for (std::size_t c = 0; c < blocks.size(); ++c)
                out.friction_force(j, static_cast<Eigen::Index>(c)) = L(at, blocks[c].first);
        }
        out.state = VectorXd(2 * n);
        out.state << out.displacement.row(0).transpose(), out.velocity.row(0).transpose();
        out.steps = static_cast<long>(k) * steps;
        if (out.energy_error > options.physics_tolerance()) {
            out.converged = false;
            out.message += "; but the energy balance fails: " + format_number(out.energy_error) + " > " +
                           format_number(options.physics_tolerance());
        }
        return out;
    }
    out.state = VectorXd::Zero(2 * n);
    out.message = "no steady state within " + std::to_string(options.max_periods) + " periods (Poincare change " +
                  format_number(out.poincare_change) + ")";
    out.steps = static_cast<long>(out.periods) * steps;
    return out;
}

}  // namespace hbf::detail
