// hbfriction — contact law `elastic`: the friction contact with a normal direction, whose
// normal load follows the motion and which separates (normal_contact.hpp: the element).
//
// Definition: along the contact's tangential direction(s) u (w_t^T y; in 3D also the
// second_direction) and its normal direction v (normal_direction^T y, positive closing):
//   N = max(0, N_0 - k_n g_0 + k_n v),  T = k_t (u - s),  |T| <= mu N  (a circular cone in 3D),
// the slider s moving in the direction of T while |T| = mu N; separated (N = 0): T = 0. The
// structure receives the force T along w_t (and the second direction) and N along the normal
// direction, as every law's force f along w (harmonic_balance.hpp).
// Parameters: stiffness k_t (> 0), normal_stiffness k_n (> 0), friction_coefficient mu (>= 0),
// preload N_0 (>= 0) or gap g_0 (>= 0), normal_direction (required) and second_direction (3D),
// vectors over the model's coordinates, orthogonal to each other and to the contact's own
// direction; the two tangential directions of equal length (the cone is circular in the units
// of u). No friction_limit: the slip force is mu N.
// While stuck (harmonic balance's first guess): k_t along the tangential directions and k_n
// along the normal one with the force N_0 at v = 0, when the contact is closed at rest.
//
// Harmonic balance: no extra unknowns; the AFT marches the slider over the period from its
// periodic fixed point (normal_contact.cpp), with the exact Jacobian on the
// stick/slip/separation pattern. Not smooth, no exact stick (its periodic orbits and stability
// verdicts come from its own solver, elastic_exact.hpp); time integration by its own
// event-driven integrator (time_integration/elastic_contacts.hpp).
#include <cmath>
#include <limits>

#include "contact/normal_law.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {

constexpr const char* normal_key = "normal_direction";
constexpr const char* second_key = "second_direction";


/// The element's AFT (normal_contact.hpp) as a FrictionModel of d + 1 signals.
class ElasticModel final : public FrictionModel {
public:
    explicit ElasticModel(const ElasticContact& element) : element_(element) {}
    int state_signals() const override { return 0; }
    int signals() const override { return element_.tangential_directions + 1; }

    void evaluate(Fourier& fourier, double, const Eigen::VectorXd& q, const Eigen::VectorXd&, FrictionEvaluation& out,
                  bool jacobian) const override {
        detail::Stopwatch watch;
        hbf::evaluate(element_, fourier, q, scratch_, jacobian);
        out.force = scratch_.force;
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        out.force_q = scratch_.jacobian;
        out.force_omega = Eigen::VectorXd::Zero(q.size());  // rate-independent
        out.jacobian_seconds = watch.lap();  // the march and its derivatives together
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        const NormalContactCycle cycle = cycle_of(fourier, q);
        return detail::stack_directions(cycle.tangential, cycle.normal);
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd&) const override {
        const NormalContactCycle cycle = cycle_of(fourier, q);
        Eigen::VectorXd phi(fourier.time_samples());
        constexpr double tiny = std::numeric_limits<double>::denorm_min();
        for (Eigen::Index j = 0; j < phi.size(); ++j) {
            const double limit = element_.friction_coefficient * cycle.normal(j);
            switch (cycle.state[static_cast<std::size_t>(j)]) {
                case ContactState::separated: phi(j) = 1.0; break;
                case ContactState::slipping: phi(j) = 0.0; break;
                case ContactState::stuck:
                    // < 0 also at the limit itself (a sample that sticks there)
                    phi(j) = limit > 0.0 ? std::min(cycle.tangential.row(j).norm() / limit - 1.0, -tiny) : -1.0;
                    break;
            }
        }
        return phi;
    }

private:
    NormalContactCycle cycle_of(Fourier& fourier, const Eigen::VectorXd& q) const {
        const int nt = fourier.time_samples(), n = fourier.size(), d = element_.tangential_directions;
        Eigen::MatrixXd u(nt, d);
        Eigen::VectorXd samples(nt), v(nt);
        for (int j = 0; j < d; ++j) {
            fourier.to_time(q.segment(j * n, n), samples);
            u.col(j) = samples;
        }
        fourier.to_time(q.segment(d * n, n), v);
        return march(element_, u, v);
    }

    ElasticContact element_;
    mutable NormalContactEvaluation scratch_;
};

class Elastic final : public detail::NormalDirectionLaw {
public:
    Elastic()
        : NormalDirectionLaw(FrictionLaw::elastic, "elastic",
              "elastic friction contact with a normal direction: N = max(0, N_0 - k_n g_0 + k_n v), "
              "T = k_t (u - s), |T| <= mu N (2D; 3D with second_direction: a circular cone), separated where N = 0") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        const NormalContactParameters shared = normal_contact_parameters();
        std::vector<LawParameter> list = {
            {"stiffness", &Contact::stiffness, "tangential stiffness k_t", R::positive},
            {"normal_stiffness", nullptr, "normal stiffness k_n", R::positive},
            shared.friction_coefficient,
            {"preload", nullptr, "normal preload N_0 (the normal force at v = 0)", R::non_negative},
            shared.gap,
            shared.second_direction,
            shared.normal_direction};
        for (int k : {0, 1, 3}) list[static_cast<std::size_t>(k)].per_area = true;  // k_t, k_n, N_0
        return list;
    }
    int default_harmonics() const override { return 10; }
    TimeIntegrator time_integrator() const override { return TimeIntegrator::elastic_contacts; }
    std::vector<StuckElement> stuck_directions(const Contact& contact) const override {
        const ElasticContact e = elastic_element(contact);
        const bool closed = e.normal_offset >= 0.0, loaded = e.normal_offset > 0.0 && e.friction_coefficient > 0.0;
        std::vector<StuckElement> out(static_cast<std::size_t>(e.tangential_directions),
                                      StuckElement{false, loaded ? e.tangential_stiffness : 0.0, 0.0, 0.0});
        out.push_back({false, closed ? e.normal_stiffness : 0.0, 0.0, std::max(e.normal_offset, 0.0)});
        return out;
    }
    std::vector<StuckElement> stuck_directions_at(const Contact& contact, double normal) const override {
        std::vector<StuckElement> out = stuck_directions(contact);
        if (!(normal > 0.0)) return out;
        const ElasticContact e = elastic_element(contact);  // pressed: closed, and stuck where mu > 0
        for (std::size_t j = 0; j + 1 < out.size(); ++j)
            out[j].stiffness = e.friction_coefficient > 0.0 ? e.tangential_stiffness : 0.0;
        out.back().stiffness = e.normal_stiffness;
        return out;
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return std::make_unique<ElasticModel>(elastic_element(contact));
    }
    /// q = (u_1, .., u_d, v): N = n_0 + k_n v (open where <= 0: no force); the trial force
    /// k_t u is kept within mu N (stuck, slider at 0), else scaled onto the cone along itself
    /// (slipping: under monotonic loading the slider moves along the force).
    bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const override {
        const ElasticContact e = elastic_element(contact);
        const int d = e.tangential_directions;
        out.force = Eigen::VectorXd::Zero(d + 1);
        out.jacobian = Eigen::MatrixXd::Zero(d + 1, d + 1);
        const double normal = e.normal_offset + e.normal_stiffness * q(d);
        out.slider = q.head(d);  // where open (T = 0)
        if (!(normal > 0.0)) {
            out.state = "open";
            return true;
        }
        out.force(d) = normal;
        out.jacobian(d, d) = e.normal_stiffness;
        const Eigen::VectorXd trial = e.tangential_stiffness * q.head(d);
        const double size = trial.norm(), limit = e.friction_coefficient * normal;
        if (size <= limit) {
            out.state = "stuck";
            out.slider.setZero();
            out.force.head(d) = trial;
            out.jacobian.topLeftCorner(d, d).diagonal().setConstant(e.tangential_stiffness);
            return true;
        }
        out.state = "slipping";
        const Eigen::VectorXd direction = trial / size;
        out.force.head(d) = limit * direction;
        out.slider = q.head(d) - out.force.head(d) / e.tangential_stiffness;
        out.jacobian.topLeftCorner(d, d) = (limit * e.tangential_stiffness / size) *
                                           (Eigen::MatrixXd::Identity(d, d) - direction * direction.transpose());
        out.jacobian.block(0, d, d, 1) = e.friction_coefficient * e.normal_stiffness * direction;
        return true;
    }

    void validate(const Contact& contact, const std::string& where) const override {
        for (const char* key : {"normal_stiffness", "friction_coefficient"})
            if (!contact.values.count(key))
                throw InvalidInput(where + key + " is missing: law elastic needs it (" +
                                   (std::string(key) == "normal_stiffness" ? "k_n > 0" : "mu >= 0") + ")");
        ContactLaw::validate(contact, where);  // the ranges
        const auto preload = contact.values.find("preload"), gap = contact.values.find("gap");
        if (preload != contact.values.end() && gap != contact.values.end() && preload->second > 0.0 && gap->second > 0.0)
            throw InvalidInput(where + "preload = " + format_number(preload->second) + " is given with gap = " +
                               format_number(gap->second) + ": allowed one of them (a preloaded contact is closed)");
        validate_normal_directions(contact, where, "elastic");
    }
};

}  // namespace

NormalContactParameters normal_contact_parameters() {
    using R = LawParameter::Range;
    NormalContactParameters p{
        {"friction_coefficient", nullptr, "friction coefficient mu", R::non_negative},
        {"gap", nullptr, "initial gap g_0 (open by g_0 at v = 0)", R::non_negative},
        {second_key, nullptr, "second tangential direction (3D)", R::positive},
        {normal_key, nullptr, "normal direction n (v = n^T y, positive closing)", R::positive}};
    p.second_direction.kind = LawParameter::Kind::direction;
    p.normal_direction.kind = LawParameter::Kind::direction;
    return p;
}

std::vector<std::pair<std::string, Eigen::VectorXd>> contact_direction_vectors(const Contact& contact) {
    const auto normal = contact.lists.find(normal_key);
    if (normal == contact.lists.end()) return {};
    const auto size = static_cast<Eigen::Index>(normal->second.size());
    Eigen::VectorXd tangential = contact.direction;
    if (tangential.size() == 0) {
        tangential = Eigen::VectorXd::Zero(size);
        if (contact.dof >= 0 && contact.dof < size) tangential(contact.dof) = 1.0;
        if (contact.other_dof >= 0 && contact.other_dof < size) tangential(contact.other_dof) = -1.0;
    }
    std::vector<std::pair<std::string, Eigen::VectorXd>> directions = {{"the tangential direction", tangential}};
    if (const auto second = contact.lists.find(second_key); second != contact.lists.end())
        directions.emplace_back(second_key, Eigen::Map<const Eigen::VectorXd>(second->second.data(), size));
    directions.emplace_back(normal_key, Eigen::Map<const Eigen::VectorXd>(normal->second.data(), size));
    return directions;
}

void validate_normal_directions(const Contact& contact, const std::string& where, const char* law) {
    if (!contact.lists.count(normal_key))
        throw InvalidInput(where + normal_key + " is missing: law " + law + " needs the normal direction, a vector over "
                           "the model's coordinates orthogonal to the tangential one");
    // The directions (System::validate checked their sizes): orthogonal, and the two
    // tangential ones of equal length.
    const auto directions = contact_direction_vectors(contact);
    for (std::size_t a = 0; a < directions.size(); ++a)
        for (std::size_t b = a + 1; b < directions.size(); ++b) {
            const Eigen::VectorXd &u = directions[a].second, &v = directions[b].second;
            if (u.size() != v.size() || std::abs(u.dot(v)) > 1e-12 * u.norm() * v.norm())
                throw InvalidInput(where + directions[b].first + " is not orthogonal to " + directions[a].first +
                                   " (cosine " + format_number(u.dot(v) / (u.norm() * v.norm())) +
                                   "): allowed orthogonal directions, to 1e-12");
        }
    if (directions.size() == 3) {
        const double a = directions[0].second.norm(), b = directions[1].second.norm();
        if (std::abs(a - b) > 1e-12 * std::max(a, b))
            throw InvalidInput(where + second_key + " has length " + format_number(b) +
                               " and the tangential direction " + format_number(a) +
                               ": allowed equal lengths (the friction cone is circular in the tangential plane)");
    }
}

ElasticContact elastic_element(const Contact& c) {
    ElasticContact e;
    e.tangential_stiffness = c.stiffness;
    e.normal_stiffness = c.values.at("normal_stiffness");
    e.friction_coefficient = c.values.at("friction_coefficient");
    const auto preload = c.values.find("preload"), gap = c.values.find("gap");
    e.normal_offset = (preload == c.values.end() ? 0.0 : preload->second) -
                      e.normal_stiffness * (gap == c.values.end() ? 0.0 : gap->second);
    e.tangential_directions = c.lists.count(second_key) ? 2 : 1;
    return e;
}

const ContactLaw& elastic_law() {
    static const Elastic law;
    return law;
}

}  // namespace hbf
