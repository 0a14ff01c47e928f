// hbfriction tests — what the backbone tests share.
#pragma once

#include <cmath>

#include "hbf/modes.hpp"

namespace hbf::test {

/// The first amplitude at which a backbone's xi differs from its first point's by more than
/// `relative`: where it leaves the linear limit it starts in (0 where it never does).
inline double backbone_departure(const Backbone& b, double relative = 1e-9) {
    if (b.points.empty()) return 0.0;
    const double xi0 = b.points.front().xi;
    for (const ModePoint& p : b.points)
        if (std::abs(p.xi / xi0 - 1.0) > relative) return p.amplitude;
    return 0.0;
}

}  // namespace hbf::test
