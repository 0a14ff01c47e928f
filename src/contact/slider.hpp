// hbfriction — internal to contact/: what the laws built of Jenkins sliders share (jenkins, and
// iwan's parallel sliders): not smooth, exact stick (the event-exact solver covers them), the
// slider position as their state in time, default H 10, stuck as the spring `stiffness`, and the
// preset's stiffness k_t = r wb^2 (the same as Dahl's sigma0). Not installed.
#pragma once

#include <string>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/contact_law.hpp"

namespace hbf::detail {

class SliderLaw : public ContactLaw {
public:
    using ContactLaw::ContactLaw;
    int default_harmonics() const override { return 10; }
    bool smooth() const override { return false; }
    bool exact_stick() const override { return true; }
    TimeState time_state() const override { return TimeState::slider; }
    StuckElement stuck(const Contact& contact) const override { return {false, contact.stiffness, 0.0}; }
    std::vector<std::string> preset_parameters() const override { return {"wb"}; }
    void from_preset(const AbsorberParameters& p, Contact& contact) const override {
        contact.stiffness = p.contact_stiffness();
    }
};

}  // namespace hbf::detail
