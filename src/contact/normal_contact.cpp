// hbfriction — the 2D elastic friction element with a varying normal load (normal_contact.hpp).
#include "hbf/normal_contact.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "hbf/error.hpp"

namespace hbf {

namespace {

void validate(const ElasticContact2D& e) {
    auto require = [](bool ok, const char* key, const char* allowed, double value) {
        if (!ok)
            throw InvalidInput(std::string(key) + " = " + format_number(value) + " is out of range: allowed " + allowed);
    };
    require(e.normal_stiffness > 0.0 && std::isfinite(e.normal_stiffness), "normal_stiffness", "finite and > 0",
            e.normal_stiffness);
    require(e.tangential_stiffness > 0.0 && std::isfinite(e.tangential_stiffness), "tangential_stiffness",
            "finite and > 0", e.tangential_stiffness);
    require(e.friction_coefficient >= 0.0 && std::isfinite(e.friction_coefficient), "friction_coefficient",
            "finite and >= 0", e.friction_coefficient);
    require(std::isfinite(e.normal_offset), "normal_offset", "finite", e.normal_offset);
}

}  // namespace

NormalContactCycle march(const ElasticContact2D& e, const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
    validate(e);
    if (u.size() != v.size() || u.size() == 0)
        throw InvalidInput("normal contact: " + std::to_string(u.size()) + " tangential and " +
                           std::to_string(v.size()) + " normal samples: allowed equal, nonzero counts");
    const int nt = static_cast<int>(u.size());
    const double kt = e.tangential_stiffness, kn = e.normal_stiffness, mu = e.friction_coefficient;
    using Slider = NormalContactCycle::Slider;
    NormalContactCycle c;
    c.normal = (e.normal_offset + kn * v.array()).cwiseMax(0.0).matrix();
    c.tangential.resize(nt);
    c.state.assign(static_cast<std::size_t>(nt), ContactState::stuck);
    c.slider_before.assign(static_cast<std::size_t>(nt), Slider{});
    // The permanent-stick interval of the slider, max_j (u_j - mu N_j / k_t) ..
    // min_j (u_j + mu N_j / k_t), from samples a and b; its midpoint starts the march.
    Eigen::Index a = 0, b = 0;
    const Eigen::ArrayXd travel = mu * c.normal.array() / kt;
    const double lower = (u.array() - travel).maxCoeff(&a), upper = (u.array() + travel).minCoeff(&b);
    const bool separates = (c.normal.array() <= 0.0).any();
    double slider = 0.0;
    Slider dependence;
    if (lower <= upper && !separates) {
        slider = 0.5 * (lower + upper);
        // d travel_j / d v_j = mu k_n / k_t on closed samples (all of them here).
        dependence.anchor[0] = static_cast<int>(a);
        dependence.u_weight[0] = 0.5;
        dependence.v_weight[0] = -0.5 * mu * kn / kt;
        dependence.anchor[1] = static_cast<int>(b);
        dependence.u_weight[1] = 0.5;
        dependence.v_weight[1] = 0.5 * mu * kn / kt;
    } else {
        slider = 0.5 * (u.maxCoeff() + u.minCoeff());  // forgotten at the first event
    }
    // Two periods settle the cycle when it slips or separates (the first event forgets the
    // start); more only while the slider at the period's end still changes. The samples of the
    // last period before its first event hang on the previous period's last event, which is
    // the same sample once the cycle repeats.
    constexpr int max_periods = 8;
    for (int period = 0; period < max_periods; ++period) {
        const double start = slider;
        bool event = false;
        for (int j = 0; j < nt; ++j) {
            const auto index = static_cast<std::size_t>(j);
            c.slider_before[index] = dependence;
            if (c.normal(j) <= 0.0) {
                c.state[index] = ContactState::separated;
                c.tangential(j) = 0.0;
                slider = u(j);
                dependence = Slider{};
                dependence.anchor[0] = j;
                dependence.u_weight[0] = 1.0;
                event = true;
                continue;
            }
            const double trial = kt * (u(j) - slider), limit = mu * c.normal(j);
            if (std::abs(trial) <= limit) {
                c.state[index] = ContactState::stuck;
                c.tangential(j) = trial;
                continue;
            }
            const double sign = trial > 0.0 ? 1.0 : -1.0;
            c.state[index] = ContactState::slipping;
            c.tangential(j) = sign * limit;
            slider = u(j) - sign * limit / kt;
            dependence = Slider{};
            dependence.anchor[0] = j;
            dependence.u_weight[0] = 1.0;
            dependence.v_weight[0] = -sign * mu * kn / kt;
            event = true;
        }
        if (!event) {
            c.permanent_stick = true;
            break;
        }
        if (period > 0 && slider == start) break;
    }
    return c;
}

void evaluate(const ElasticContact2D& e, Fourier& fourier, const Eigen::VectorXd& u, const Eigen::VectorXd& v,
              NormalContactEvaluation& out, bool jacobian) {
    const int nt = fourier.time_samples(), n = fourier.size();
    Eigen::VectorXd ut(nt), vt(nt);
    fourier.to_time(u, ut);
    fourier.to_time(v, vt);
    const NormalContactCycle cycle = march(e, ut, vt);
    out.tangential.resize(n);
    out.normal.resize(n);
    fourier.to_coefficients(cycle.tangential, out.tangential);
    fourier.to_coefficients(cycle.normal, out.normal);
    if (!jacobian) return;
    const double kt = e.tangential_stiffness, kn = e.normal_stiffness, mu = e.friction_coefficient;
    // Own samples: stuck T_j = k_t u_j - k_t s_{j-1}; slipping T_j = sign mu (n_0 + k_n v_j);
    // closed N_j = n_0 + k_n v_j.
    Eigen::VectorXd own_u = Eigen::VectorXd::Zero(nt), own_v = Eigen::VectorXd::Zero(nt), closed(nt);
    const Eigen::MatrixXd& P = fourier.analysis();
    Eigen::MatrixXd slider_u = Eigen::MatrixXd::Zero(n, nt), slider_v = Eigen::MatrixXd::Zero(n, nt);
    for (int j = 0; j < nt; ++j) {
        const auto index = static_cast<std::size_t>(j);
        closed(j) = cycle.normal(j) > 0.0 ? kn : 0.0;
        if (cycle.state[index] == ContactState::slipping) {
            own_v(j) = (cycle.tangential(j) > 0.0 ? 1.0 : -1.0) * mu * kn;
        } else if (cycle.state[index] == ContactState::stuck) {
            own_u(j) = kt;
            const NormalContactCycle::Slider& s = cycle.slider_before[index];
            for (int m = 0; m < 2; ++m) {
                if (s.anchor[m] < 0) continue;
                slider_u.col(s.anchor[m]) -= kt * s.u_weight[m] * P.col(j);
                slider_v.col(s.anchor[m]) -= kt * s.v_weight[m] * P.col(j);
            }
        }
    }
    const Eigen::MatrixXd& E = fourier.synthesis();
    out.tangential_u.resize(n, n);
    out.tangential_v.resize(n, n);
    out.normal_v.resize(n, n);
    fourier.multiplication_matrix(own_u, out.tangential_u);
    fourier.multiplication_matrix(own_v, out.tangential_v);
    fourier.multiplication_matrix(closed, out.normal_v);
    out.tangential_u.noalias() += slider_u * E;
    out.tangential_v.noalias() += slider_v * E;
}

}  // namespace hbf
