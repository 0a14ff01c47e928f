// hbfriction — the forced response synthesised from a nonlinear mode (single-nonlinear-mode
// synthesis, Krack et al. 2014; modes.hpp: NonlinearModes::synthesize) and its table.
#include "hbf/modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "hbf/error.hpp"

namespace hbf {

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


namespace io {

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
