// Post-processing of branch points: metrics (y_max, first harmonics, stick pattern, energy)
// and refined resonance peaks (declared in continuation.hpp, next to the branch data).
#include "hbf/post_processing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/continuation.hpp"
#include "hbf/error.hpp"
#include "numerics/golden_section.hpp"
#include "numerics/peak_newton.hpp"

namespace hbf {

// ---- post-processing --------------------------------------------------------------------

int fine_time_samples(int harmonics) { return std::max(1024, Fourier::default_time_samples(harmonics) * 4); }

namespace {
/// max over theta of |x(theta)| for the series with coefficients c: the largest of the
/// samples, polished by Newton on x'(theta) = 0 within one grid spacing (exact to rounding,
/// where the grid alone would be off by up to (pi / N)^2 / 2 relative).
double series_max_abs(const Eigen::VectorXd& c, const Eigen::VectorXd& samples) {
    // An infinite coefficient (a DOF unbounded at an undamped resonance, Receptance's limit) is
    // an infinite maximum, not the NaN that inf * cos(pi / 2) would give.
    if (!c.allFinite()) return c.array().isNaN().any() ? std::numeric_limits<double>::quiet_NaN()
                                                       : std::numeric_limits<double>::infinity();
    Eigen::Index j = 0;
    const double grid_max = samples.cwiseAbs().maxCoeff(&j);
    const int harmonics = static_cast<int>(c.size() - 1) / 2;
    const double spacing = 2.0 * M_PI / static_cast<double>(samples.size());
    const double theta0 = spacing * static_cast<double>(j);
    double theta = theta0;
    auto value = [&](double th, double* d1, double* d2) {
        double x = c(0), dx = 0.0, ddx = 0.0;
        for (int k = 1; k <= harmonics; ++k) {
            const double ck = c(2 * k - 1), sk = c(2 * k), co = std::cos(k * th), si = std::sin(k * th);
            x += ck * co + sk * si;
            dx += k * (sk * co - ck * si);
            ddx -= k * k * (ck * co + sk * si);
        }
        if (d1) *d1 = dx;
        if (d2) *d2 = ddx;
        return x;
    };
    for (int iteration = 0; iteration < 8; ++iteration) {
        double d1 = 0.0, d2 = 0.0;
        value(theta, &d1, &d2);
        if (d2 == 0.0) break;
        const double next = theta - d1 / d2;
        if (std::abs(next - theta0) > spacing) break;  // left the sample's neighbourhood
        const bool converged = std::abs(next - theta) <= 1e-14;
        theta = next;
        if (converged) break;
    }
    return std::max(grid_max, std::abs(value(theta, nullptr, nullptr)));
}
}  // namespace

int stick_phase_samples(int harmonics, int time_samples) {
    return (2 * time_samples + 2 * harmonics) / (2 * harmonics + 1);  // ceil(2 N_t / (2H + 1))
}

ContactRegime stick_pattern(const Eigen::VectorXd& phi, int min_run) {
    const Eigen::Index n = phi.size();
    ContactRegime p;
    if (n == 0) return p;
    const Eigen::Index sticking = (phi.array() < 0.0).count();
    if (sticking == n) {
        p.stick_fraction = 1.0;
        p.regime = "stick";
        return p;
    }
    // Runs of sticking samples, starting after a slipping sample (one exists).
    Eigen::Index start = 0;
    while (phi(start) < 0.0) ++start;
    Eigen::Index in_phases = 0, run = 0;
    for (Eigen::Index k = 1; k <= n; ++k) {
        if (phi((start + k) % n) < 0.0) {
            ++run;
            continue;
        }
        if (run >= min_run) in_phases += run;
        run = 0;
    }
    p.stick_fraction = static_cast<double>(in_phases) / static_cast<double>(n);
    p.regime = in_phases == 0 ? "slip" : "stick-slip";
    return p;
}

Analyser::Analyser(HarmonicBalance& hb, std::vector<int> report)
    : hb_(hb), fine_(hb.harmonics(), fine_time_samples(hb.harmonics())), report_(std::move(report)) {
    for (int i : report_)
        if (i < 0 || i >= hb.system().dofs())
            throw InvalidInput("reported DOF " + std::to_string(i + 1) + " is out of range: allowed 1.." +
                               std::to_string(hb.system().dofs()));
    if (report_.empty())
        for (int i = 0; i < hb.system().dofs(); ++i) report_.push_back(i);
}

Analyser::Analyser(HarmonicBalance& hb, std::vector<int> report, std::vector<Output> outputs)
    : hb_(hb), fine_(hb.harmonics(), fine_time_samples(hb.harmonics())), report_(std::move(report)),
      outputs_(std::move(outputs)) {
    for (int i : report_)
        if (i < 0 || i >= hb.system().dofs())
            throw InvalidInput("reported DOF " + std::to_string(i + 1) + " is out of range: allowed 1.." +
                               std::to_string(hb.system().dofs()));
    for (const Output& o : outputs_) o.validate(hb.system().dofs());
}

PointMetrics Analyser::operator()(const SolutionPoint& point) {
    PointMetrics m;
    const System& s = hb_.system();
    const double omega = point.omega;
    Eigen::VectorXd samples(fine_.time_samples());
    const Eigen::MatrixXd y = hb_.dofs(point.x, omega);
    m.y_max.assign(static_cast<std::size_t>(s.dofs()), std::numeric_limits<double>::quiet_NaN());
    // Work of F cos(h w t) per period: pi h F^T s_h (s_h the sine coefficients of harmonic h).
    const int h = s.excitation_harmonic;
    for (int i = 0; i < s.dofs(); ++i) {
        m.y_amp1.push_back(std::hypot(y(1, i), y(2, i)));
        m.input_energy += M_PI * h * s.excitation(i) * y(2 * h, i);
    }
    for (const Output& o : outputs_) {
        const Eigen::VectorXd c = o.combine(y);
        fine_.to_time(c, samples);
        m.output_max.push_back(series_max_abs(c, samples));
        m.output_amp1.push_back(std::hypot(c(1), c(2)));
        if (o.single_dof() >= 0) m.y_max[static_cast<std::size_t>(o.single_dof())] = m.output_max.back();
    }
    for (int i : report_) {
        if (!std::isnan(m.y_max[static_cast<std::size_t>(i)])) continue;  // an output already
        const Eigen::VectorXd c = y.col(i);
        fine_.to_time(c, samples);
        m.y_max[static_cast<std::size_t>(i)] = series_max_abs(c, samples);
    }
    double normal_work = 0.0;  // the normal forces' work on the AFT grid (below)
    if (s.contacts.empty()) {
        m.regime = "none";
    } else {
        // Stick fraction and regime of every contact from its law's own stick samples.
        const int min_run = stick_phase_samples(hb_.harmonics(), hb_.time_samples());
        for (int c = 0; c < static_cast<int>(s.contacts.size()); ++c) {
            const Eigen::VectorXd phi = hb_.stick_indicator(point.x, omega, c);
            m.contacts.push_back(stick_pattern(phi, min_run));
            if (c > 0) continue;
            m.stick_indicator_max = phi.maxCoeff();
            m.stick_indicator_min = phi.minCoeff();
        }
        mark_force_elements(s, m.contacts, m.regime, m.stick_fraction);
        // Dissipated energy: integral over the period 2 pi / omega of f q', on the AFT grid.
        Fourier& aft = hb_.fourier();
        Eigen::VectorXd v(aft.time_samples());
        // A contact with a normal direction: the sum over its tangential directions. The
        // normal force's work N v' vanishes over a period in continuous time (law elastic's
        // normal spring is conservative, law unilateral's rigid contact does no work), but not
        // on the AFT grid, where a separation puts a corner into N: that residue (measured 1.6e-6
        // against a friction energy of 4.3e-6 in lift-off on liftoff3.toml at H = 40) enters the
        // energy balance below, whose discrete identity it is part of, not the dissipation.
        const int n = aft.size(), nt = aft.time_samples();
        for (int c = 0; c < static_cast<int>(s.contacts.size()); ++c) {
            const Eigen::VectorXd q = hb_.relative(point.x, c);
            const Eigen::VectorXd f = hb_.force_samples(point.x, omega, c);
            ContactRegime& r = m.contacts[static_cast<std::size_t>(c)];
            r.energy = 0.0;
            const Eigen::Index signals = q.size() / n;
            const ContactLaw& law = contact_law(s.contacts[static_cast<std::size_t>(c)].law);
            // (an element over several coordinates without friction: the work of all of them)
            const bool normal_direction = signals > 1 && law.friction();
            for (Eigen::Index a = 0; a < signals; ++a) {
                aft.to_time(omega * (aft.derivative() * q.segment(a * n, n)), v);
                const double work = 2.0 * M_PI / omega * f.segment(a * nt, nt).dot(v) / nt;
                (normal_direction && a == signals - 1 ? normal_work : r.energy) += work;
            }
            m.energy += r.energy;
            if (normal_direction || law.unilateral()) {
                // a normal direction (its force is the last signal's), or a unilateral spring
                const Eigen::VectorXd normal = f.tail(nt);
                r.separated_fraction = static_cast<double>((normal.array() <= 0.0).count()) / nt;
                r.normal_mean = normal.mean();
                r.normal_amplitude = 0.5 * (normal.maxCoeff() - normal.minCoeff());
            }
        }
    }
    // Viscous dissipation per period 2 pi / w of y' = sum_k k w (s_k cos - c_k sin):
    // int y'^T C y' dt = pi w sum_k k^2 (c_k^T C c_k + s_k^T C s_k).
    if (s.damping.nonZeros() > 0)
        for (int k = 1; k <= hb_.harmonics(); ++k)
            for (int row : {2 * k - 1, 2 * k}) {
                const Eigen::VectorXd c = y.row(row).transpose();
                m.viscous_energy += M_PI * omega * k * k * c.dot(s.damping * c);
            }
    // Relative to the work the force could do on the response's harmonic h, pi h |F| |(c_h, s_h)|
    // (the input work itself vanishes in permanent stick of an undamped structure).
    const double reach = M_PI * h * s.excitation.norm() *
                         std::max(std::hypot(y.row(2 * h - 1).norm(), y.row(2 * h).norm()), response_floor(s, omega));
    m.energy_error = energy_imbalance(m.input_energy, m.viscous_energy, m.energy + normal_work, reach);
    return m;
}

double response_floor(const System& system, double omega) {
    double stiffness = 0.0, mass = 0.0;
    for (Eigen::Index i = 0; i < system.stiffness.rows(); ++i) {
        stiffness = std::max(stiffness, std::abs(system.stiffness.coeff(i, i)));
        mass = std::max(mass, std::abs(system.mass.coeff(i, i)));
    }
    const double scale = std::max(stiffness, omega * omega * mass);
    const double force = system.excitation.size() > 0 ? system.excitation.cwiseAbs().maxCoeff() : 0.0;
    return scale > 0.0 && std::isfinite(scale) ? 1e-9 * force / scale : 0.0;
}

double energy_balance_limit(double tolerance) { return std::max(1e-6, 100.0 * tolerance); }

PointSignals point_signals(HarmonicBalance& hb, const SolutionPoint& point, int contact) {
    Fourier& f = hb.fourier();
    const int nt = f.time_samples(), dofs = hb.system().dofs();
    PointSignals s;
    s.time = Eigen::VectorXd::LinSpaced(nt, 0.0, 2.0 * M_PI * (nt - 1) / nt) / point.omega;
    s.y.resize(nt, dofs);
    Eigen::VectorXd samples(nt);
    const Eigen::MatrixXd y = hb.dofs(point.x, point.omega);
    for (int i = 0; i < dofs; ++i) {
        f.to_time(y.col(i), samples);
        s.y.col(i) = samples;
    }
    // every direction of the contact, the first (the tangential one of an element with a
    // normal direction) also as q, v, f
    const Eigen::VectorXd all_q = hb.relative(point.x, contact), all_f = hb.force_samples(point.x, point.omega, contact);
    const auto signals = all_q.size() / f.size();
    s.q_directions.resize(nt, signals);
    s.f_directions = Eigen::Map<const Eigen::MatrixXd>(all_f.data(), nt, signals);
    for (Eigen::Index a = 0; a < signals; ++a) {
        f.to_time(all_q.segment(a * f.size(), f.size()), samples);
        s.q_directions.col(a) = samples;
    }
    const Eigen::VectorXd q = all_q.head(f.size());
    s.q = s.q_directions.col(0);
    s.v.resize(nt);
    f.to_time(point.omega * (f.derivative() * q), s.v);
    s.f = s.f_directions.col(0);
    Eigen::VectorXd coefficients(f.size());
    f.to_coefficients(s.f, coefficients);
    s.f_series.resize(nt);
    f.to_time(coefficients, s.f_series);
    s.phi = hb.stick_indicator(point.x, point.omega, contact);
    return s;
}

bool is_peak_value(double y, double largest, double floor) {
    return y > floor && y > 1e-8 * largest;
}

namespace detail {
PeakNewton peak_newton(const std::function<double(double, bool&)>& value, double w0, double h_rel, double max_move,
                       const std::function<bool(double, double)>& corner) {
    PeakNewton r;
    double w = w0;
    bool fine = false;
    // Relative steps of the 3- and 5-point stencils: h_rel and 10 h_rel, at most 0.5 % and 2 %
    // of the peak's relative width 1 / sqrt(c), c = -Y'' w^2 / Y (a sharp peak needs a short one).
    double coarse = h_rel, wide = 10.0 * h_rel, width = 1.0;
    // A bracket of the root of Y' once both signs were seen, one per stencil (the 3- and
    // 5-point derivatives differ by their truncation): Newton steps that leave it bisect it.
    double lo[2] = {0.0, 0.0}, hi[2] = {0.0, 0.0};
    bool has_lo[2] = {false, false}, has_hi[2] = {false, false};
    double last_fine = std::numeric_limits<double>::infinity();  // the last 5-point step
    int returns = 0;
    auto at = [&](double x, bool& good) {
        const double y = value(x, good);
        if (!good && r.message.empty()) r.message = "the solve at w = " + format_number(x) + " failed";
        return y;
    };
    for (int it = 0; it < 60; ++it) {
        r.iterations = it + 1;
        bool good = true;
        const double h = (fine ? wide : coarse) * w;
        const double y0 = at(w, good);
        const double ym = good ? at(w - h, good) : 0.0;
        const double yp = good ? at(w + h, good) : 0.0;
        const double ymm = good && fine ? at(w - 2.0 * h, good) : 0.0;
        const double ypp = good && fine ? at(w + 2.0 * h, good) : 0.0;
        if (!good) return r;
        const double d1 = fine ? (ymm - 8.0 * ym + 8.0 * yp - ypp) / (12.0 * h) : (yp - ym) / (2.0 * h);
        const double d2 = fine ? (-ymm + 16.0 * ym - 30.0 * y0 + 16.0 * yp - ypp) / (12.0 * h * h)
                               : (yp - 2.0 * y0 + ym) / (h * h);
        const bool concave = d2 < 0.0;
        if (concave && y0 > 0.0) {
            width = std::min(1.0, 1.0 / std::sqrt(-d2 * w * w / y0));
            coarse = std::min(h_rel, 5e-3 * width);
            wide = std::min(10.0 * h_rel, 2e-2 * width);
        }
        const int b = fine ? 1 : 0;
        if (d1 > 0.0) {
            lo[b] = w;
            has_lo[b] = true;
        } else {
            hi[b] = w;
            has_hi[b] = true;
        }
        if (has_lo[b] && has_hi[b] && lo[b] < hi[b] && hi[b] - lo[b] <= 1e-12 * w) {
            // Y' changes sign across a bracket of 1e-12 w without a concave stencil there: a
            // kink of Y (the largest turning point in time switches), whose maximum it is.
            const double mid = 0.5 * (lo[b] + hi[b]);
            const double y = at(mid, good);
            if (!good) return r;
            r.ok = true;
            r.kink = true;
            r.omega = mid;
            r.value = y;
            return r;
        }
        // Newton on a concave stretch; uphill by 0.2 % of w (at most half the width) on a convex one.
        double next = w + (concave ? std::clamp(-d1 / d2, -0.02 * w, 0.02 * w)
                                   : (d1 >= 0.0 ? 1.0 : -1.0) * std::min(2e-3, 0.5 * width) * w);
        const bool bracketed = has_lo[b] && has_hi[b] && lo[b] < hi[b];
        if (bracketed && !(next > lo[b] && next < hi[b])) next = 0.5 * (lo[b] + hi[b]);
        const double step = next - w;
        if (std::abs(next - w0) > max_move * w0) {
            r.no_maximum = true;
            r.message = "no maximum within " + format_number(100.0 * max_move) + " % of w = " + format_number(w0);
            return r;
        }
        // 5-point steps from within `close`; converged at a step below `done`: a Newton step's
        // error is about the step times the relative error of the stencil's Y'' (~1e-3), so a
        // step of 1e-8 w leaves ~1e-11 w.
        const double close = std::min(1e-6, 1e-3 * width) * w, done = std::min(1e-8, 1e-5 * width) * w;
        // A 5-point step that no longer halves is at the values' rounding (HB's tolerance): done.
        // After three returns from the 5-point stencil to the 3-point one (a Y too irregular at
        // the 5-point width, e.g. harmonic balance's near a kink), the 3-point one finishes.
        const bool last_stencil = fine || returns >= 3;
        const bool floor = last_stencil && concave && std::abs(step) <= close && std::abs(step) > 0.5 * last_fine;
        last_fine = last_stencil && concave ? std::abs(step) : std::numeric_limits<double>::infinity();
        if (last_stencil && concave && (std::abs(step) <= done || floor)) {
            // A stick/slip corner inside the stencil is the caller's to locate.
            if (corner && corner(w - 2.0 * h, w + 2.0 * h)) {
                r.ok = true;
                r.corner = true;
                r.omega = w;
                r.value = y0;
                return r;
            }
            const double y = at(next, good);
            if (!good) return r;
            r.ok = true;
            r.omega = next;
            r.value = y;
            r.curvature = d2 * next * next / y;
            return r;
        }
        const bool was_fine = fine;
        fine = concave && std::abs(step) <= close && returns < 3;
        if (was_fine && !fine) ++returns;
        w = next;
    }
    r.no_maximum = true;
    r.message = "Newton on dY/dw did not settle near w = " + format_number(w0);
    return r;
}
}  // namespace detail

void refine_peak(Peak& peak, const SolutionPoint& a, const SolutionPoint& m, const SolutionPoint& b,
                 const std::function<double(double, bool&)>& value) {
    peak.refined = false;
    for (const SolutionPoint* p : {&a, &m, &b})
        if (p->kind == PointKind::fold) {
            peak.why = "a fold at w = " + format_number(p->omega) + " beside it: y is not a function of w there";
            return;
        }
    if (!((m.omega - a.omega) * (b.omega - m.omega) > 0.0)) {
        peak.why = "the branch turns in w there (not a function of w)";
        return;
    }
    double failed_at = 0.0;
    bool ok = true;
    const auto search = [&](double lo, double hi) {
        return detail::brent_maximum(
            [&](double omega, bool& good) {
                const double y = value(omega, good);
                if (!good && failed_at == 0.0) failed_at = omega;
                return y;
            },
            lo, hi, 1e-9, ok);
    };
    const double lo = std::min(a.omega, b.omega), hi = std::max(a.omega, b.omega);
    detail::GoldenMaximum best = search(lo, hi);
    // Brent assumes one maximum in the bracket; a corner of y(w) (an HB sample switching
    // between stick and slip) can hold it on a lower local one: then each side of m alone.
    for (const auto& [from, to] : {std::make_pair(lo, m.omega), std::make_pair(m.omega, hi)}) {
        if (!ok || best.value >= peak.y_max) break;
        const detail::GoldenMaximum side = search(from, to);
        if (ok && side.value > best.value) best = side;
    }
    if (!ok) {
        peak.why = "the solve failed at w = " + format_number(failed_at);
        return;
    }
    if (best.value >= peak.y_max) {
        // Brent locates the maximum by values (to ~sqrt(rounding / curvature)); Newton on the
        // difference derivative sharpens it (peak_newton.hpp). Kept only when it stays within
        // 1e-6 w and its value is not below Brent's beyond rounding (a corner is Brent's).
        const detail::PeakNewton sharp = detail::peak_newton(value, best.x, 1e-5, 1e-6);
        if (sharp.ok && sharp.value >= best.value - 1e-9 * std::abs(best.value)) {
            best.x = sharp.omega;
            best.value = sharp.value;
        }
        peak.omega = best.x;
        peak.y_max = best.value;
        peak.refined = true;
        peak.why.clear();
    } else if (m.kind == PointKind::transition) {
        peak.refined = true;  // the corner at the located transition is the maximum
        peak.why.clear();
    } else {
        peak.why = "no value above the branch point's in [" + format_number(std::min(a.omega, b.omega)) + ", " +
                   format_number(std::max(a.omega, b.omega)) + "] (a corner of the curve, largest found " +
                   format_number(best.value) + " at w = " + format_number(best.x) + ")";
    }
}

std::string unrefined_peaks(const std::vector<Peak>& peaks, const std::vector<std::string>& names) {
    std::string list;
    int count = 0;
    for (const Peak& p : peaks) {
        if (p.refined) continue;
        ++count;
        const std::string name = p.output >= 0 && static_cast<std::size_t>(p.output) < names.size()
                                     ? names[static_cast<std::size_t>(p.output)] + " "
                                     : std::string();
        list += (list.empty() ? "" : "; ") + name + "at w = " + format_number(p.omega) + " (" + p.why + ")";
    }
    return count == 0 ? "" : std::to_string(count) + " peak(s) not refined: " + list;
}

namespace {
std::vector<Peak> output_peaks(HarmonicBalance& hb, const BranchResult& branch, const Output& output,
                               const CorrectorOptions& options) {
    const auto& points = branch.points;
    Analyser analyse(hb, {}, {output});
    std::vector<double> y(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) y[k] = analyse(points[k]).output_max.front();
    Corrector corrector(hb, options);
    std::vector<Peak> peaks;
    double weight = 0.0;  // |c|_1
    for (const auto& term : output.terms()) weight += std::abs(term.second);
    const double largest = y.empty() ? 0.0 : *std::max_element(y.begin(), y.end());
    for (std::size_t k = 1; k + 1 < points.size(); ++k) {
        const SolutionPoint &a = points[k - 1], &m = points[k], &b = points[k + 1];
        if (a.branch != m.branch || b.branch != m.branch || !(y[k] > y[k - 1] && y[k] >= y[k + 1])) continue;
        if (!is_peak_value(y[k], largest, weight * response_floor(hb.system(), m.omega))) continue;
        Peak peak{m.omega, y[k], m.branch, false, 0, {}};
        // y(omega) on the segment a-m-b, solved exactly at omega from the interpolation.
        const SolutionPoint& low = a.omega < b.omega ? a : b;
        const SolutionPoint& high = a.omega < b.omega ? b : a;
        refine_peak(peak, a, m, b, [&](double omega, bool& good) {
            const SolutionPoint& left = omega <= m.omega ? low : m;  // low < m < high in omega
            const SolutionPoint& right = omega <= m.omega ? m : high;
            const double s = (omega - left.omega) / (right.omega - left.omega);
            SolutionPoint p;
            p.omega = omega;
            p.x = left.x + s * (right.x - left.x);
            const double x_scale = hb.unknown_scale(p.x);
            if (!corrector.solve_at(p.x, omega, x_scale, p.iterations, p.residual)) {
                good = false;
                return 0.0;
            }
            return analyse(p).output_max.front();
        });
        peaks.push_back(peak);
    }
    return peaks;
}

}  // namespace

std::vector<Peak> find_peaks(HarmonicBalance& hb, const BranchResult& branch, int dof, const CorrectorOptions& options) {
    if (dof < 0 || dof >= hb.system().dofs())
        throw InvalidInput("peaks of DOF " + std::to_string(dof + 1) + ": out of range, allowed 1.." +
                           std::to_string(hb.system().dofs()));
    return find_peaks(hb, branch, std::vector<Output>{Output::dof(dof)}, options);
}

std::vector<Peak> find_peaks(HarmonicBalance& hb, const BranchResult& branch, const std::vector<Output>& outputs,
                             const CorrectorOptions& options) {
    std::vector<Peak> all;
    for (std::size_t o = 0; o < outputs.size(); ++o) {
        std::vector<Peak> peaks = output_peaks(hb, branch, outputs[o], options);
        for (Peak& p : peaks) p.output = static_cast<int>(o);
        all.insert(all.end(), peaks.begin(), peaks.end());
    }
    return all;
}

}  // namespace hbf
