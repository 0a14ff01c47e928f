// hbfriction — law `polynomial`: a nonlinear spring whose force is a polynomial of its relative
// displacement (a cubic spring, a Duffing oscillator's stiffness, a hardening or softening
// support).
//
// Definition: f = k2 q^2 + k3 q^3 + sum_j c_j q^(e_j), acting as -w f on the structure like
// every contact's force (so k3 > 0 stiffens, k3 < 0 softens). The structure's own K carries the
// linear stiffness; a term of exponent 1 adds to it.
// Parameters: quadratic k2 and cubic k3 (finite, default 0), terms: pairs (e_j, c_j) with e_j an
// integer in 1..max_polynomial_degree and c_j finite; at least one non-zero coefficient.
// While stuck (the linear limits, the first guess): the spring of its exponent-1 terms.
//
// Harmonic balance: f = P f(E q) with the exact Jacobian P diag(f'(E q)) E. The product of a
// degree-p polynomial of an H-harmonic signal has harmonics up to p H, which N_t samples alias
// onto N_t - p H and above: the H balanced harmonics are exact when N_t > (p + 1) H
// (time_samples_needed: (p + 1) H + 1; the automatic N_t, at least 16 H + 8, covers every
// allowed degree). Smooth: time integration, stability (f_q = f'(q)), no stick (friction() is
// false: regime "none"). No internal state; default H 10, the automatic H's floor (measured: H
// = 9 puts a Duffing oscillator's truncation at 1e-6 against time integration at moderate
// amplitude).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "contact/force_element.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

/// The largest exponent a polynomial term may have (the alias-free N_t grows as (p + 1) H).
constexpr int max_polynomial_degree = 15;

/// The terms c q^e of a contact, merged by exponent (zero coefficients dropped).
std::vector<std::pair<int, double>> polynomial_terms(const Contact& contact) {
    std::vector<std::pair<int, double>> terms;
    auto add = [&](int e, double c) {
        if (c == 0.0) return;
        for (auto& t : terms)
            if (t.first == e) {
                t.second += c;
                return;
            }
        terms.emplace_back(e, c);
    };
    if (const auto k2 = contact.values.find("quadratic"); k2 != contact.values.end()) add(2, k2->second);
    if (const auto k3 = contact.values.find("cubic"); k3 != contact.values.end()) add(3, k3->second);
    if (const auto list = contact.lists.find("terms"); list != contact.lists.end())
        for (std::size_t i = 0; i + 1 < list->second.size(); i += 2)
            add(static_cast<int>(list->second[i]), list->second[i + 1]);
    std::sort(terms.begin(), terms.end());
    return terms;
}

class Polynomial final : public detail::PointwiseForce {
public:
    explicit Polynomial(std::vector<std::pair<int, double>> terms) : terms_(std::move(terms)) {
        for (const auto& t : terms_) degree_ = std::max(degree_, t.first);
    }
    detail::PointForce at(double q, double) const override {
        detail::PointForce p;
        for (const auto& [e, c] : terms_) {
            double power = 1.0;  // q^(e - 1)
            for (int k = 1; k < e; ++k) power *= q;
            p.force += c * power * q;
            p.slope_q += c * e * power;
        }
        return p;
    }
    bool uses_velocity() const override { return false; }
    double samples_needed(int harmonics) const override { return (degree_ + 1.0) * harmonics + 1.0; }
    std::string samples_reason() const override {
        return "is a polynomial of degree " + std::to_string(degree_) + ", alias-free when N_t > (p + 1) H = " +
               std::to_string((degree_ + 1)) + " H";
    }

private:
    std::vector<std::pair<int, double>> terms_;
    int degree_ = 1;
};

class PolynomialLaw final : public detail::ForceElementLaw {
public:
    PolynomialLaw()
        : ForceElementLaw(FrictionLaw::polynomial, "polynomial",
                          "polynomial stiffness: f = k2 q^2 + k3 q^3 + sum c_j q^e_j") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        static_assert(max_polynomial_degree == 15, "the meaning below names the bound");
        LawParameter terms{"terms", nullptr, "polynomial terms (e_j, c_j): f += c_j q^e_j, e_j an integer in 1..15",
                           R::finite};
        terms.kind = LawParameter::Kind::pairs;
        return {{"quadratic", nullptr, "quadratic stiffness k2 (f += k2 q^2)", R::finite},
                {"cubic", nullptr, "cubic stiffness k3 (f += k3 q^3)", R::finite},
                terms};
    }
    int default_harmonics() const override { return 10; }
    StuckElement stuck(const Contact& contact) const override {
        StuckElement e;
        for (const auto& [exponent, c] : polynomial_terms(contact))
            if (exponent == 1) e.stiffness += c;
        return e;
    }
    void validate(const Contact& contact, const std::string& where) const override {
        ContactLaw::validate(contact, where);  // quadratic, cubic: finite
        if (const auto list = contact.lists.find("terms"); list != contact.lists.end())
            for (std::size_t i = 0; i + 1 < list->second.size(); i += 2) {
                const double e = list->second[i], c = list->second[i + 1];
                const std::string at = where + "terms[" + std::to_string(i / 2 + 1) + "]";
                if (!(std::isfinite(e) && e == std::floor(e) && e >= 1 && e <= max_polynomial_degree))
                    throw InvalidInput(at + ": exponent " + format_number(e) + " is out of range: allowed an integer in 1.." +
                                       std::to_string(max_polynomial_degree) + " (a constant force is a static_load)");
                if (!std::isfinite(c))
                    throw InvalidInput(at + ": coefficient " + format_number(c) + " is out of range: allowed finite");
            }
        if (polynomial_terms(contact).empty())
            throw InvalidInput(where + "law polynomial has no term: give cubic, quadratic or terms with a non-zero "
                                       "coefficient");
    }
    std::shared_ptr<const detail::PointwiseForce> force(const Contact& contact) const override {
        return std::make_shared<Polynomial>(polynomial_terms(contact));
    }
};

}  // namespace

const ContactLaw& polynomial_law() {
    static const PolynomialLaw law;
    return law;
}

}  // namespace hbf
