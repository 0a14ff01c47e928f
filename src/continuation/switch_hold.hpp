// hbfriction — internal: holds the contacts' switches between residual forms for one Newton
// solve (FrictionModel::hold_switch; the corrector's and the nonlinear modes' Newton).
#pragma once

#include "hbf/harmonic_balance.hpp"

namespace hbf::detail {

/// Holds the contacts' switches between residual forms while it lives, and frees them on
/// leaving (by an exception too). The first evaluation after it is made decides each form.
struct SwitchHold {
    explicit SwitchHold(HarmonicBalance& h) : hb(h) { hb.hold_switches(true); }
    ~SwitchHold() { hb.hold_switches(false); }
    SwitchHold(const SwitchHold&) = delete;
    SwitchHold& operator=(const SwitchHold&) = delete;
    HarmonicBalance& hb;
};

}  // namespace hbf::detail
