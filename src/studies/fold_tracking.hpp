// hbfriction — internal: fold curves of harmonic-balance FRFs through a second parameter
// (tracking.hpp, TrackFeature::fold; fold_tracking.cpp).
#pragma once

#include <functional>

#include "hbf/tracking.hpp"

namespace hbf::detail {

/// The folds of the FRF of system(p_start) (or the one nearest options.omega) followed in p
/// through their cusps. Options validated by the caller; `output` gives the points' values.
TrackResult track_folds(const std::function<System(double)>& system, const FrfSettings& settings,
                        const TrackOptions& options, const Output& output);

}  // namespace hbf::detail
