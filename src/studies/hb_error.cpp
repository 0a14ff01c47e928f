// hbfriction — harmonic balance's truncation error estimated at points of an FRF (hb_error.hpp).
#include "studies/hb_error.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "hbf/corrector.hpp"
#include "hbf/error.hpp"

namespace hbf::detail {

namespace {
/// The FRF's scale: the largest value of outputs[0] over its points.
double frf_scale(const FrfResult& r) {
    double scale = 0.0;
    for (const PointMetrics& m : r.metrics)
        if (!m.output_max.empty() && std::isfinite(m.output_max[0])) scale = std::max(scale, m.output_max[0]);
    return scale;
}

/// The indices of r.points to estimate at: the branch points where outputs[0]'s max |o(t)| has
/// a local maximum along its branch (largest first: the peaks, found from the branch alone, so
/// that the same branch gets the same points whether or not its peaks are refined), then
/// `spread` points evenly over the points, each index once; at most `spread` of each.
std::vector<std::size_t> chosen_points(const FrfResult& r, int spread) {
    std::vector<std::size_t> out;
    const auto add = [&](std::size_t k) {
        if (out.size() < 2 * static_cast<std::size_t>(spread) && std::find(out.begin(), out.end(), k) == out.end())
            out.push_back(k);
    };
    const std::size_t n = r.points.size();
    const auto y = [&](std::size_t k) { return r.metrics[k].output_max.at(0); };
    const auto regular = [&](std::size_t k) { return r.points[k].kind != PointKind::sample; };
    std::vector<std::size_t> maxima;
    for (std::size_t k = 0; k < n; ++k) {
        if (!regular(k)) continue;
        const bool left = k == 0 || !regular(k - 1) || r.points[k - 1].branch != r.points[k].branch || y(k - 1) < y(k);
        const bool right = k + 1 >= n || !regular(k + 1) || r.points[k + 1].branch != r.points[k].branch || y(k + 1) <= y(k);
        if (left && right) maxima.push_back(k);
    }
    std::stable_sort(maxima.begin(), maxima.end(), [&](std::size_t a, std::size_t b) { return y(a) > y(b); });
    if (maxima.size() > static_cast<std::size_t>(spread)) maxima.resize(static_cast<std::size_t>(spread));
    for (std::size_t k : maxima) add(k);
    if (n == 0) return out;
    for (int j = 0; j < spread; ++j)
        add(spread == 1 ? 0 : static_cast<std::size_t>(std::llround(static_cast<double>(j) * static_cast<double>(n - 1) /
                                                                   static_cast<double>(spread - 1))));
    return out;
}
}  // namespace

HbErrorSummary estimate_hb_error(HarmonicBalance& hb, const FrfSettings& settings, const std::vector<Output>& outputs,
                                 FrfResult& r) {
    HbErrorSummary s;
    const int h = hb.harmonics();
    HarmonicBalanceOptions o = hb.options();
    const int wanted = std::min(2 * h, max_harmonics);
    o.harmonics = wanted;
    // The same sampling density of the period as the FRF's (a law that raised N_t needs it).
    const auto samples_for = [&](int harmonics) {
        return std::min(HarmonicBalanceOptions::max_time_samples,
                        std::max(hb.time_samples() * harmonics / h, 2 * harmonics + 2));
    };
    o.time_samples = samples_for(wanted);
    // Automatic (the FRF's choice; o has the form it resolved to at H): the structured
    // Jacobian from structured_threshold unknowns at the larger H on, for the laws with
    // internal states too (whose continuation keeps the dense form up to max_unknowns): each
    // solve starts from the point's own solution, Newton's favourable case, where the
    // structured form costs about (H + 1) n^2 and the dense (2H + 1)^3 n^3 (measured on
    // examples/systems/mitre at H = 7: the estimate at H = 14, 5,481 unknowns, took 13 minutes
    // dense and did not converge).
    std::optional<HarmonicBalance> built;
    const long long signals = hb.unknowns() / std::max(1, hb.coefficients());
    if (wanted > h && settings.harmonic_balance.jacobian == JacobianForm::automatic &&
        o.jacobian == JacobianForm::dense && signals * (2LL * wanted + 1) > HarmonicBalance::structured_threshold) {
        HarmonicBalanceOptions structured = o;
        structured.jacobian = JacobianForm::structured;
        try {
            built.emplace(hb.system(), structured);
        } catch (const InvalidInput&) {  // not structurable (full formulation, odd harmonics) or over its memory bound
        }
    }
    if (!built) {
        if (o.jacobian == JacobianForm::dense) {
            try {
                o.harmonics = HarmonicBalance::fitting_harmonics(hb.system(), o, wanted);
            } catch (const InvalidInput& e) {
                s.why_not = e.what();
                return s;
            }
        }
        if (o.harmonics <= h) {
            s.why_not = "no larger H fits the dense Jacobian's bound of " +
                        std::to_string(HarmonicBalance::max_unknowns) + " unknowns, or H is the largest allowed";
            return s;
        }
        o.time_samples = samples_for(o.harmonics);
        built.emplace(hb.system(), o);
    }
    s.structured = built->structured();
    s.harmonics = built->harmonics();
    HarmonicBalance& fine = *built;
    CorrectorOptions patient = settings.continuation.corrector;
    patient.max_iterations = std::max(100, 5 * patient.max_iterations);
    Corrector corrector(fine, patient);
    Analyser analyse(fine, {0}, outputs);
    // The FRF's scale: its largest value of outputs[0] (a point-relative error would read an
    // antiresonance's small shift as a large error).
    const double scale = frf_scale(r);
    for (const std::size_t k : chosen_points(r, settings.error_points)) {
        SolutionPoint q = r.points[k];
        q.x = fine.embed_harmonics(r.points[k].x, h);
        if (!corrector.solve_at(q.x, q.omega, fine.unknown_scale(q.x), q.iterations, q.residual)) {
            ++s.failed;
            continue;
        }
        const double coarse = r.metrics[k].output_max.at(0), refined = analyse(q).output_max.at(0);
        const double e = coarse == refined ? 0.0 : 2.0 * std::abs(coarse - refined) / std::max(scale, std::abs(refined));
        r.metrics[k].hb_error = e;
        ++s.estimated;
        if (!(e <= s.largest)) {
            s.largest = e;
            s.omega = q.omega;
        }
    }
    return s;
}

int mark_peaks_within_error(FrfResult& r) {
    const std::size_t n = r.points.size();
    const auto y = [&](std::size_t k) { return r.metrics[k].output_max.at(0); };
    const auto on_branch = [&](std::size_t k, int branch) {
        return k < n && r.points[k].kind != PointKind::sample && r.points[k].branch == branch;
    };
    const double scale = frf_scale(r);
    if (!(scale > 0.0)) return 0;
    int marked = 0;
    for (Peak& p : r.peaks) {
        if (p.output != 0) continue;
        std::size_t top = n;
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < n; ++k)
            if (on_branch(k, p.branch) && std::abs(r.points[k].omega - p.omega) < d) {
                d = std::abs(r.points[k].omega - p.omega);
                top = k;
            }
        if (top == n) continue;
        const double height = std::max(p.y_max, y(top));
        // The lowest point on each side before a higher one (or the branch's end).
        std::size_t left = top, right = top;
        double low_left = height, low_right = height;
        while (left > 0 && on_branch(left - 1, p.branch) && y(left - 1) <= height) low_left = std::min(low_left, y(--left));
        while (on_branch(right + 1, p.branch) && y(right + 1) <= height) low_right = std::min(low_right, y(++right));
        const double prominence = (height - std::max(low_left, low_right)) / scale;
        double error = std::numeric_limits<double>::quiet_NaN();
        for (std::size_t k = left; k <= right; ++k)
            if (std::isfinite(r.metrics[k].hb_error) && !(r.metrics[k].hb_error <= error)) error = r.metrics[k].hb_error;
        if (!std::isfinite(error)) {
            double nearest = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < n; ++k)
                if (on_branch(k, p.branch) && std::isfinite(r.metrics[k].hb_error) &&
                    std::abs(r.points[k].omega - p.omega) < nearest) {
                    nearest = std::abs(r.points[k].omega - p.omega);
                    error = r.metrics[k].hb_error;
                }
        }
        if (std::isfinite(error) && prominence < error) {
            p.within_error = true;
            ++marked;
        }
    }
    return marked;
}

}  // namespace hbf::detail
