// hbfriction — internal: harmonic balance's truncation error estimated at points of an FRF
// (FrfSettings::error_points, PointMetrics::hb_error).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "hbf/frf.hpp"

namespace hbf::detail {

/// What the estimate did over one FRF.
struct HbErrorSummary {
    int harmonics = 0;       ///< the larger H it compared with (0: no estimate, why_not says why)
    std::string why_not;
    int estimated = 0;       ///< points with an estimate
    int failed = 0;          ///< points whose solve at the larger H did not converge
    bool structured = false; ///< solved with the structured Jacobian (automatic above structured_threshold)
    double largest = std::numeric_limits<double>::quiet_NaN();  ///< the largest estimate
    double omega = std::numeric_limits<double>::quiet_NaN();    ///< where
};

/// Solves the points chosen (the branch points where outputs[0] has a local maximum, largest
/// first, then points spread evenly over the branch: settings.error_points of each, at most) again with
/// twice the harmonics, from the point's own solution, and sets metrics[k].hb_error =
/// 2 |y(H) - y(2H)| / max y of outputs[0]'s y = max |o(t)| (max y: the largest on the FRF, its
/// scale; a point-relative error would make an antiresonance's small shift a large error).
/// Twice the change: for the nonsmooth laws
/// harmonic balance converges like 1/H, so the change when H doubles is half the error at H.
HbErrorSummary estimate_hb_error(HarmonicBalance& hb, const FrfSettings& settings, const std::vector<Output>& outputs,
                                 FrfResult& r);

/// Marks the peaks of outputs[0] in r.peaks whose prominence along their branch (the height
/// above the higher of the two lowest points between them and a higher point or the branch's
/// end), relative to the FRF's largest value, is below the largest hb_error estimated between
/// those two points (else at the nearest estimated point of the branch): Peak::within_error.
/// Returns how many.
int mark_peaks_within_error(FrfResult& r);

}  // namespace hbf::detail
