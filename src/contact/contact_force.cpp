// hbfriction — the AFT force of a contact (contact_force.hpp) as its law provides it: the periodic
// model and the local linearisation, through the registry (contact_law.hpp).
#include "hbf/contact_force.hpp"

#include "hbf/contact_law.hpp"

namespace hbf {

std::unique_ptr<FrictionModel> make_friction_model(const Contact& contact) {
    return contact_law(contact.law).periodic_model(contact);
}

LocalLinearization linearize(const Contact& contact, double q, double v, double z) {
    return contact_law(contact.law).linearize(contact, q, v, z);
}

}  // namespace hbf
