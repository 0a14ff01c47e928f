// hbfriction — internal to contact/: what the laws with a normal direction share (elastic and
// unilateral: normal_contact.hpp): not smooth, no exact stick, a friction coefficient instead of
// a friction limit, no preset (the paper's absorber has no normal direction), their own time
// integrator instead of the general one, no time-domain state, and stuck as the element along
// their first direction. Not installed.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "hbf/contact_law.hpp"

namespace hbf::detail {

class NormalDirectionLaw : public ContactLaw {
public:
    using ContactLaw::ContactLaw;
    bool smooth() const override { return false; }
    bool exact_stick() const override { return false; }
    bool has_friction_limit() const override { return false; }
    bool has_preset() const override { return false; }
    bool time_domain() const override { return false; }
    TimeState time_state() const override { return TimeState::none; }
    StuckElement stuck(const Contact& contact) const override { return stuck_directions(contact).front(); }
};

/// The samples of a contact's d tangential directions (nt x d) and its normal (nt) as one
/// vector, direction by direction: the layout of FrictionModel::force_samples.
inline Eigen::VectorXd stack_directions(const Eigen::MatrixXd& tangential, const Eigen::VectorXd& normal) {
    const Eigen::Index nt = normal.size(), d = tangential.cols();
    Eigen::VectorXd f(nt * (d + 1));
    for (Eigen::Index j = 0; j < d; ++j) f.segment(j * nt, nt) = tangential.col(j);
    f.tail(nt) = normal;
    return f;
}

}  // namespace hbf::detail
