// hbfriction — the metrics of an exact orbit from one recorded period (metrics.hpp).
#include "event_exact/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>

#include "hbf/error.hpp"
#include "event_exact/polynomial.hpp"

namespace hbf::detail::exact {

Eigen::VectorXd mean_forces(Engine& e, const Engine::Flow& flow) {
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(e.contacts());
    for (const Step& st : flow.steps) {
        const double length = st.s_end * st.h;
        if (length <= 0.0) continue;
        const ModeData& m = e.mode(st.modes);
        for (const auto& [node, weight] : gauss_legendre())
            mean += weight * length * (m.force * evaluate(st.u, node * st.s_end));
        if (st.fast()) mean += m.force * st.fast_integral(0.0).real();
    }
    return mean / e.period();
}

Eigen::VectorXd slip_work(Engine& e, const Engine::Flow& flow) {
    Eigen::VectorXd work = Eigen::VectorXd::Zero(e.contacts());
    for (const Step& st : flow.steps) {
        if (st.s_end * st.h <= 0.0) continue;
        const Eigen::VectorXd z0 = st.state(0.0), z1 = st.state(st.s_end);
        for (int c = 0; c < e.contacts(); ++c) {
            const int mode = st.modes[static_cast<std::size_t>(c)];
            if (mode != 0) work(c) += mode * e.contact(c).friction_limit * (e.spring_end(c, z1) - e.spring_end(c, z0));
        }
    }
    return work;
}

void Maxima::add(const Step& st, const Signal& y, double& best) {
    best = std::max(best, std::abs(y.value(0.0)));
    const auto polynomial_max = [&st](const Eigen::RowVectorXd& poly, double& at) {
        constexpr int samples = 16;
        Eigen::RowVectorXd d = Eigen::RowVectorXd::Zero(std::max<Eigen::Index>(1, poly.size() - 1));
        for (Eigen::Index k = 1; k < poly.size(); ++k) d(k - 1) = static_cast<double>(k) * poly(k);
        double s_prev = 0.0, v_prev = horner(d, 0.0), top = std::abs(horner(poly, 0.0));
        at = 0.0;
        const auto consider = [&](double s) {
            const double value = std::abs(horner(poly, s));
            if (value > top) {
                top = value;
                at = s;
            }
        };
        for (int j = 1; j <= samples; ++j) {
            const double s = st.s_end * j / samples;
            const double vs = horner(d, s);
            consider(s);
            if ((v_prev <= 0.0 && vs >= 0.0) || (v_prev >= 0.0 && vs <= 0.0)) consider(refine_root(d, s_prev, s));
            s_prev = s;
            v_prev = vs;
        }
        return top;
    };
    double at = 0.0;
    const double top = polynomial_max(y.poly, at);
    if (!y.fast()) {
        best = std::max(best, top);
        return;
    }
    double envelope = 0.0;
    for (Eigen::Index j = 0; j < y.amp.size(); ++j)
        envelope += (std::abs(y.amp(j).real()) + std::abs(y.amp(j).imag())) *
                    std::max(1.0, std::exp(y.rate(j).real() * st.s_end));
    best = std::max({best, std::abs(y.value(at)), std::abs(y.value(st.s_end))});
    const double bound = top * (1.0 + 1e-12) + envelope;
    if (bound > best) deferred_.push_back({y, st.s_end, bound, &best});
}

void Maxima::finish() {
    // The deferred steps with fast exponentials: samples resolving every one above rounding of
    // |y|. An extremum between two samples is refined only where it can exceed the best so far:
    // within one sample (half a radian of the fastest exponential) it lies within the samples'
    // values plus their slopes times the spacing.
    for (const Deferred& d : deferred_) {
        double& best = *d.best;
        if (d.bound <= best) continue;
        const Signal& y = d.y;
        double size = std::abs(horner(y.poly, 0.0));
        for (Eigen::Index j = 0; j < y.amp.size(); ++j) size += std::abs(y.amp(j).real()) + std::abs(y.amp(j).imag());
        double s_prev = 0.0, v_prev = 0.0, y_prev = 0.0;
        y.sample(d.s_end, 1e-15 * size, [&](double s, double value, double slope) {
            best = std::max(best, std::abs(value));
            if (s > 0.0 && ((v_prev <= 0.0 && slope >= 0.0) || (v_prev >= 0.0 && slope <= 0.0)) &&
                std::max(std::abs(y_prev), std::abs(value)) + (s - s_prev) * std::max(std::abs(v_prev), std::abs(slope)) > best)
                best = std::max(best, std::abs(y.value(signal_extremum(y, s_prev, s))));
            s_prev = s;
            v_prev = slope;
            y_prev = value;
            return true;
        });
    }
    deferred_.clear();
}

void period_events(const std::vector<ExactEvent>& events, double period, ExactOrbit& out) {
    out.events.clear();
    for (ExactEvent ev : events) {
        ev.time = std::fmod(ev.time, period);
        if (ev.time < 0) ev.time += period;
        if (ev.time >= period) ev.time -= period;
        out.events.push_back(ev);
    }
    std::sort(out.events.begin(), out.events.end(),
              [](const ExactEvent& a, const ExactEvent& b) { return a.time < b.time; });
    out.switches = static_cast<int>(out.events.size());
}

void fill_metrics(Engine& e, const Engine::Flow& flow, double t_s, const ExactOptions& options, ExactOrbit& out,
                  Probes* probes) {
    const int nd = e.dofs(), nc = e.contacts();
    const double period = e.period();
    const auto& rule = gauss_legendre();
    out.y_max.assign(static_cast<std::size_t>(nd), options.dof_maxima ? 0.0 : std::numeric_limits<double>::quiet_NaN());
    const std::vector<Output>& outputs = options.outputs;
    out.output_max.assign(outputs.size(), 0.0);
    // First harmonics of the whole zhat (cos and sin are states of zhat, so probes on them too).
    Eigen::VectorXd c1z = Eigen::VectorXd::Zero(e.n()), s1z = Eigen::VectorXd::Zero(e.n());
    const Eigen::Index n_probes = probes ? probes->rows.rows() : 0;
    if (probes) {
        probes->max.assign(static_cast<std::size_t>(n_probes), 0.0);
        for (Eigen::Index p = 0; p < probes->first_max; ++p)
            probes->max[static_cast<std::size_t>(p)] = std::numeric_limits<double>::quiet_NaN();
    }
    std::vector<double> stick_time(static_cast<std::size_t>(nc), 0.0);  // per element
    out.energy = 0.0;
    double margin_min = std::numeric_limits<double>::infinity(), margin_max = -margin_min;
    auto margin_of = [&](double force) {
        const double value = std::abs(force) / e.contact(0).friction_limit - 1.0;
        margin_min = std::min(margin_min, value);
        margin_max = std::max(margin_max, value);
    };
    auto margin = [&](const Modes& modes, const Eigen::VectorXd& z) { margin_of(e.mode(modes).force.row(0).dot(z)); };
    for (std::size_t k = 0; k < flow.events.size() && nc > 0; ++k) {
        const ExactEvent& ev = flow.events[k];
        if (ev.contact != 0 || ev.mode_before == 0 || !e.coulomb(0)) continue;
        Modes trial = step_at(flow.steps, ev.time).modes;  // the force that would hold it
        trial[0] = 0;
        margin(trial, flow.event_states[k]);
    }
    Eigen::VectorXd z_node;
    Maxima maxima;
    for (const Step& st : flow.steps) {
        const double length = st.s_end * st.h;
        if (length <= 0.0) continue;
        if (nc > 0 && (st.modes[0] == 0 || !e.coulomb(0)))
            st.signal(Eigen::RowVectorXd(e.mode(st.modes).force.row(0)))  // 17 samples
                .sample(st.s_end, std::numeric_limits<double>::infinity(), [&](double, double force, double) {
                margin_of(force);
                return true;
            });
        if (!probes && options.dof_maxima)  // the probes include the DOFs
            for (int i = 0; i < nd; ++i) maxima.add(st, st.signal(i), out.y_max[static_cast<std::size_t>(i)]);
        for (std::size_t o = 0; o < outputs.size(); ++o) {
            Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(e.n());
            for (const auto& [i, c] : outputs[o].terms()) row(i) += c;
            maxima.add(st, st.signal(row), out.output_max[o]);
        }
        if (n_probes > 0)  // p = L zhat
            for (Eigen::Index p = probes->first_max; p < n_probes; ++p)
                maxima.add(st, st.signal(Eigen::RowVectorXd(probes->rows.row(p))), probes->max[static_cast<std::size_t>(p)]);
        // First harmonics by Gauss-Legendre (cos and sin are states of zhat), the fast part's
        // in closed form.
        for (const auto& [node, weight] : rule) {
            z_node = evaluate(st.u, node * st.s_end);
            c1z += (weight * length * z_node(e.cos_index())) * z_node;
            s1z += (weight * length * z_node(e.sin_index())) * z_node;
        }
        if (st.fast()) {
            const std::complex<double> phase(st.u(e.cos_index(), 0), st.u(e.sin_index(), 0));
            const Eigen::VectorXcd turned = phase * st.fast_integral(std::complex<double>(0.0, e.omega()));
            c1z += turned.real();
            s1z += turned.imag();
        }
        for (int c = 0; c < nc; ++c)
            if (st.modes[static_cast<std::size_t>(c)] == 0) stick_time[static_cast<std::size_t>(c)] += length;
    }
    maxima.finish();
    out.energy = slip_work(e, flow).sum();
    c1z *= 2.0 / period;
    s1z *= 2.0 / period;
    const Eigen::VectorXd c1 = c1z.head(nd), s1 = s1z.head(nd);
    if (probes) {
        probes->c1 = probes->rows * c1z;
        probes->s1 = probes->rows * s1z;
    }
    out.harmonic1 = c1.cast<std::complex<double>>() - std::complex<double>(0.0, 1.0) * s1.cast<std::complex<double>>();
    out.y_amp1.resize(static_cast<std::size_t>(nd));
    for (int i = 0; i < nd; ++i) out.y_amp1[static_cast<std::size_t>(i)] = std::hypot(c1(i), s1(i));
    out.output_amp1.clear();
    for (const Output& o : outputs) out.output_amp1.push_back(std::hypot(o.of(c1), o.of(s1)));
    out.input_energy = pi * e.excitation().dot(s1);
    out.stick_margin_min = std::isfinite(margin_min) ? margin_min : 0.0;
    out.stick_margin_max = std::isfinite(margin_max) ? margin_max : 0.0;
    // Per time-domain element here; exact_periodic_orbit regroups them by contact.
    out.contacts.clear();
    for (double t : stick_time) out.contacts.push_back(contact_regime(t, period));
    out.stick_fraction = nc > 0 ? out.contacts.front().stick_fraction : 0.0;
    out.regime = nc > 0 ? out.contacts.front().regime : "none";
    period_events(flow.events, period, out);
    // The state at t = 0 (= T).
    const double t_zero = t_s > 0.0 ? period : 0.0;
    const Step& at_zero = step_at(flow.steps, t_zero);
    const Eigen::VectorXd z_zero = state_at(flow.steps, t_zero);
    out.state = full_state(e, z_zero, at_zero.modes);
    if (probes) {
        probes->value = probes->rows * z_zero;
        probes->rate = probes->rows * (e.mode(at_zero.modes).a * z_zero);
        probes->samples.resize(options.samples, n_probes);
        probes->sample_rates.resize(options.samples, n_probes);
    }
    if (options.samples > 0) {
        out.time.resize(options.samples);
        out.displacement.resize(options.samples, nd);
        out.velocity.resize(options.samples, nd);
        out.friction_force.resize(options.samples, nc);
        for (int j = 0; j < options.samples; ++j) {
            const double t = period * j / options.samples;
            const double tt = t < t_s ? t + period : t;
            const Step& st = step_at(flow.steps, tt);
            const Eigen::VectorXd z = st.state(std::min(std::max((tt - st.t0) / st.h, 0.0), st.s_end));
            out.time(j) = t;
            out.displacement.row(j) = z.head(nd).transpose();
            out.velocity.row(j) = z.segment(nd, nd).transpose();
            const ModeData& m = e.mode(st.modes);
            for (int c = 0; c < nc; ++c) out.friction_force(j, c) = m.force.row(c).dot(z);
            if (probes) {
                probes->samples.row(j) = (probes->rows * z).transpose();
                probes->sample_rates.row(j) = (probes->rows * (m.a * z)).transpose();
            }
        }
    }
}

void note_unresolved_stability(ExactOrbit& out) {
    if (out.stability_unresolved())
        out.message += "; the largest multiplier " + format_number(out.max_multiplier) +
                       " is within the differences' accuracy (" + format_number(out.multiplier_accuracy) +
                       ") of 1: a neutral direction they cannot place, stability uncertain";
}

}  // namespace hbf::detail::exact

namespace hbf {

std::string ExactOrbit::summary() const {
    std::ostringstream s;
    s << "w = " << format_number(omega) << ": " << (converged ? "converged" : "not converged") << " (" << message
      << "), " << iterations << " Newton iterations, residual " << format_number(residual);
    if (!y_max.empty()) s << ", y1_max = " << format_number(y_max.front());
    s << ", " << regime << ", "
      << (!std::isfinite(max_multiplier) ? "stability unknown"
          : stable                       ? "stable"
          : stability_unresolved()       ? "stability uncertain"
                                         : "unstable")
      << " (max |multiplier| " << format_number(max_multiplier);
    if (stability_unresolved()) s << ", within the multipliers' accuracy " << format_number(multiplier_accuracy) << " of 1";
    s << ")";
    return s.str();
}

}  // namespace hbf
