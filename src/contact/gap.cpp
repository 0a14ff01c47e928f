// hbfriction — law `gap`: a unilateral spring (penalty contact without friction), along one
// direction: an impact stop, a beam closing a gap, a shroud's normal contact alone.
//
// Definition: f = max(0, p + k (q - g)): the spring k acts once q passes the gap g (open at
// rest by g), or from the start with the preload p (closed at rest, pressed by p, open where
// q < -p / k); f >= 0 pushes the structure back (-w f). Continuous and piecewise linear.
// Parameters: stiffness k (> 0); gap g (>= 0, default 0) or preload p (>= 0, default 0), not
// both.
// At rest (the linear limits' stuck element, the first guess, the modes' linear limit): the
// spring k carrying the preload where closed (no gap), nothing where a gap opens it.
//
// Harmonic balance: f = P f(E q) with the Jacobian P diag(k [closed]) E, exact on each open/
// closed pattern of the samples (the corner at the closing is smoothed by the sampling only:
// the AFT converges as the samples resolve the closing instants). Time integration stops at
// every closing and opening (time_margin); the stability analysis takes f_q = k closed, 0 open
// (the force is continuous, so the monodromy needs no saltation at the corner). The share of
// the period open is reported as the separated fraction, the force as the normal load.
// Default H 20 (a corner in the force, like the contact laws with a normal direction).
#include <cmath>
#include <string>

#include "contact/force_element.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

struct GapParameters {
    double stiffness = 0, gap = 0, preload = 0;
    explicit GapParameters(const Contact& c) : stiffness(c.stiffness) {
        if (const auto g = c.values.find("gap"); g != c.values.end()) gap = g->second;
        if (const auto p = c.values.find("preload"); p != c.values.end()) preload = p->second;
    }
    /// p + k (q - g): the force where closed (> 0), the closing's distance times k otherwise.
    double trial(double q) const { return preload + stiffness * (q - gap); }
};

class GapForce final : public detail::PointwiseForce {
public:
    explicit GapForce(const Contact& c) : p_(c) {}
    detail::PointForce at(double q, double) const override {
        const double t = p_.trial(q);
        detail::PointForce f;
        f.force = t > 0.0 ? t : 0.0;
        f.slope_q = t > 0.0 ? p_.stiffness : t < 0.0 ? 0.0 : 0.5 * p_.stiffness;  // the corner: the mean
        return f;
    }
    bool uses_velocity() const override { return false; }
    double samples_needed(int) const override { return 0.0; }
    std::string samples_reason() const override { return ""; }
    /// < 0 while closed: a root at each closing and opening.
    double margin(double q) const override { return -p_.trial(q) / p_.stiffness; }

private:
    GapParameters p_;
};

class GapLaw final : public detail::ForceElementLaw {
public:
    GapLaw()
        : ForceElementLaw(FrictionLaw::gap, "gap", "unilateral spring: f = max(0, p + k (q - g))") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        return {{"stiffness", &Contact::stiffness, "contact stiffness k", R::positive},
                {"gap", nullptr, "initial gap g (closes at q = g)", R::non_negative},
                {"preload", nullptr, "preload p (the force at q = 0; closed at rest)", R::non_negative}};
    }
    int default_harmonics() const override { return 20; }
    bool unilateral() const override { return true; }
    /// At rest: closed (the spring k, carrying the preload) unless a gap opens it.
    StuckElement stuck(const Contact& contact) const override {
        const GapParameters p(contact);
        const bool closed = p.trial(0.0) >= 0.0;
        return {false, closed ? p.stiffness : 0.0, 0.0, closed ? p.preload : 0.0};
    }
    void validate(const Contact& contact, const std::string& where) const override {
        ContactLaw::validate(contact, where);
        const GapParameters p(contact);
        if (p.gap > 0.0 && p.preload > 0.0)
            throw InvalidInput(where + "preload = " + format_number(p.preload) + " is given with gap = " +
                               format_number(p.gap) + ": allowed one of them (a preloaded spring is closed)");
    }
    std::shared_ptr<const detail::PointwiseForce> force(const Contact& contact) const override {
        return std::make_shared<GapForce>(contact);
    }
};

}  // namespace

const ContactLaw& gap_law() {
    static const GapLaw law;
    return law;
}

}  // namespace hbf
