// hbfriction — contact law `iwan`: a parallel-series Iwan joint, N Jenkins sliders in parallel on
// one relative displacement (bolted joints: micro-slip before macro-slip).
//
// Definition: f = sum_i k_i (q - s_i), slider i a spring k_i in series with a Coulomb slider of
// slip force F_i (the jenkins law, jenkins.cpp), all on the same q; phi_i = F_i / k_i is the
// displacement at which slider i first slips under monotonic loading.
//
// The sliders come from one of two descriptions:
// * the four-parameter model of Segalman (2005) (the default): a density of sliders over phi,
//       rho(phi) = R phi^chi on 0 < phi < phi_max, plus S delta(phi - phi_max),
//   given by F_S = friction_limit (the macro-slip force), K_T = stiffness (the initial
//   stiffness, the integral of rho), chi in (-1, 0] and beta >= 0 (S over the stiffness of the
//   continuous part). Derived here (not copied):
//       A = K_T / (1 + beta) = F_S / (phi_max (beta + (chi + 1) / (chi + 2))),   S = beta A,
//       R = (chi + 1) A / phi_max^(chi + 1),                   phi_max = F_S (1 + beta) / (K_T (beta + (chi + 1) / (chi + 2))),
//   from K_T = A + S (A = R phi_max^(chi+1) / (chi+1), the continuous part's stiffness) and
//   F_S = R phi_max^(chi+2) / (chi+2) + S phi_max (everything slips). Under monotonic loading
//       F(u) = K_T u - R u^(chi+2) / ((chi+1)(chi+2))   for 0 <= u <= phi_max,   F_S beyond,
//   and a symmetric cycle of amplitude a <= phi_max dissipates 4 R a^(chi+3) / ((chi+2)(chi+3))
//   (slider phi < a loses 4 k phi (a - phi) a cycle). The continuous part is split into
//   `sliders` sliders of equal stiffness A / N: slider i spans phi_(i-1)..phi_i with
//   phi_i = phi_max (i / N)^(1 / (chi + 1)), its stiffness the density's integral there and its
//   slip force the integral of phi rho there, so that the sum of the k_i is K_T and of the F_i
//   is F_S for every N. With beta > 0 one more slider (k = S, F = S phi_max) is the delta.
// * a table `slider_table` of pairs (k_i, F_i), which replaces the four parameters; then
//   friction_limit and stiffness must be the sums of the F_i and of the k_i (the joint's
//   macro-slip force and initial stiffness, checked to 1e-9).
// The sliders are ordered by phi_i, the first the one that slips first: time-domain results of
// contact 1's element 1 (the stick fraction, the regime) are those of the joint's first slip.
//
// Harmonic balance: the sum of the sliders' forces, each marched over the period by the jenkins
// law's model, and the sum of their exact Jacobians; no extra unknowns. While stuck: the spring
// K_T. Not smooth; its stick is exact: time integration and the event-exact solver integrate
// its sliders as N jenkins elements on the same direction (time_elements). Default H 10, as
// jenkins (a continuous force).
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "contact/slider.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

constexpr const char* table_key = "slider_table";
constexpr int max_sliders = 1000;

/// The sum of the sliders' periodic models (the jenkins law's) on one relative displacement.
class ParallelSliders final : public FrictionModel {
public:
    explicit ParallelSliders(const std::vector<Contact>& sliders) {
        for (const Contact& s : sliders) models_.push_back(contact_law(s.law).periodic_model(s));
    }
    int state_signals() const override { return 0; }

    void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
                  FrictionEvaluation& out, bool jacobian) const override {
        const int n = fourier.size();
        out.force = Eigen::VectorXd::Zero(n);
        out.jacobian_seconds = 0.0;
        if (jacobian) {
            out.force_q = Eigen::MatrixXd::Zero(n, n);
            out.force_omega = Eigen::VectorXd::Zero(n);
        }
        FrictionEvaluation one;
        for (const auto& model : models_) {
            model->evaluate(fourier, omega, q, z, one, jacobian);
            out.force += one.force;
            if (!jacobian) continue;
            out.force_q += one.force_q;
            out.force_omega += one.force_omega;
            out.jacobian_seconds += one.jacobian_seconds;
        }
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd& z) const override {
        Eigen::VectorXd f = Eigen::VectorXd::Zero(fourier.time_samples());
        for (const auto& model : models_) f += model->force_samples(fourier, omega, q, z);
        return f;
    }

    /// The joint sticks while every slider sticks: the largest of the sliders' indicators (0
    /// where one slips, else the margin of the one closest to slipping).
    Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& z) const override {
        Eigen::VectorXd phi = Eigen::VectorXd::Constant(fourier.time_samples(), -1.0);
        for (const auto& model : models_) phi = phi.cwiseMax(model->stick_indicator(fourier, omega, q, z));
        return phi;
    }

private:
    std::vector<std::unique_ptr<FrictionModel>> models_;
};

/// The preset (SliderLaw) sets K_T = r wb^2; chi, beta and N keep their defaults.
class Iwan final : public detail::SliderLaw {
public:
    Iwan()
        : SliderLaw(FrictionLaw::iwan, "iwan",
              "parallel Iwan joint: f = sum_i k_i (q - s_i), N Jenkins sliders (k_i, F_i) on one q; Segalman's "
              "four parameters F_S = friction_limit, K_T = stiffness, chi, beta, or a slider_table") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        using K = LawParameter::Kind;
        LawParameter chi{"chi", nullptr, "Segalman exponent chi of the slider density R phi^chi", R::interval};
        chi.low = -1.0;
        chi.low_open = true;
        chi.high = 0.0;
        chi.default_value = -0.5;
        LawParameter beta{"beta", nullptr, "Segalman ratio beta of the sliders at phi_max to the rest", R::non_negative};
        beta.default_value = 0.0;
        LawParameter count{"sliders", nullptr, "number N of equal-stiffness sliders below phi_max", R::interval};
        count.kind = K::integer;
        count.low = 1;
        count.high = max_sliders;
        count.default_value = 40;
        LawParameter table{table_key, nullptr, "sliders (stiffness k_i, slip force F_i) replacing chi, beta, sliders",
                           R::positive};
        table.kind = K::pairs;
        return {{"stiffness", &Contact::stiffness, "initial (tangential) stiffness K_T", R::positive}, chi, beta,
                count, table};
    }

    void validate(const Contact& contact, const std::string& where) const override {
        ContactLaw::validate(contact, where);  // stiffness, chi, beta, sliders
        const auto table = contact.lists.find(table_key);
        if (table == contact.lists.end()) return;
        for (const char* key : {"chi", "beta", "sliders"})
            if (contact.values.count(key))
                throw InvalidInput(where + key + " is given together with " + table_key +
                                   ": allowed one of them (the table replaces Segalman's parameters)");
        const std::vector<double>& t = table->second;
        const std::size_t rows = t.size() / 2;
        if (t.size() % 2 != 0 || rows < 1 || rows > static_cast<std::size_t>(max_sliders))
            throw InvalidInput(where + table_key + " has " + std::to_string(t.size()) +
                               " numbers: allowed 1.." + std::to_string(max_sliders) + " pairs (k_i, F_i)");
        double k_sum = 0.0, f_sum = 0.0;
        for (std::size_t i = 0; i < rows; ++i) {
            const std::string at = where + table_key + "[" + std::to_string(i + 1) + "]";
            require_positive(t[2 * i], (at + ".k").c_str(), "slider stiffness k_i");
            require_positive(t[2 * i + 1], (at + ".F").c_str(), "slider slip force F_i");
            k_sum += t[2 * i];
            f_sum += t[2 * i + 1];
        }
        auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); };
        if (!same(contact.friction_limit, f_sum))
            throw InvalidInput(where + "friction_limit = " + format_number(contact.friction_limit) + " with " +
                               table_key + ": allowed the sum of the slip forces F_i, " + format_number(f_sum) +
                               " (the macro-slip force)");
        if (!same(contact.stiffness, k_sum))
            throw InvalidInput(where + "stiffness = " + format_number(contact.stiffness) + " with " + table_key +
                               ": allowed the sum of the slider stiffnesses k_i, " + format_number(k_sum) +
                               " (the initial stiffness)");
    }

    std::vector<Contact> time_elements(const Contact& contact) const override {
        std::vector<std::pair<double, double>> sliders = slider_pairs(contact);  // (k_i, F_i)
        std::stable_sort(sliders.begin(), sliders.end(), [](const auto& a, const auto& b) {
            return a.second / a.first < b.second / b.first;  // by phi_i: the first slips first
        });
        std::vector<Contact> elements;
        for (const auto& [k, f] : sliders) {
            Contact e;
            e.dof = contact.dof;
            e.other_dof = contact.other_dof;
            e.direction = contact.direction;
            e.law = FrictionLaw::jenkins;
            e.stiffness = k;
            e.friction_limit = f;
            elements.push_back(e);
        }
        return elements;
    }

    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return std::make_unique<ParallelSliders>(time_elements(contact));
    }

private:
    /// The sliders (k_i, F_i), from the table or from Segalman's distribution (top of the file).
    std::vector<std::pair<double, double>> slider_pairs(const Contact& contact) const {
        std::vector<std::pair<double, double>> out;
        if (const auto table = contact.lists.find(table_key); table != contact.lists.end()) {
            for (std::size_t i = 0; i + 1 < table->second.size(); i += 2)
                out.emplace_back(table->second[i], table->second[i + 1]);
            return out;
        }
        const std::vector<LawParameter> p = parameters();  // stiffness, chi, beta, sliders, table
        const double chi = p[1].get(contact), beta = p[2].get(contact);
        const int n = static_cast<int>(p[3].get(contact));
        const double fs = contact.friction_limit, kt = contact.stiffness;
        const double c = (chi + 1.0) / (chi + 2.0);
        const double phi_max = fs * (1.0 + beta) / (kt * (beta + c));
        const double a = kt / (1.0 + beta);  // stiffness of the continuous part (K_T = A + S)
        const double r = (chi + 1.0) * a / std::pow(phi_max, chi + 1.0);
        // slider i: phi from phi_(i-1) to phi_i, phi_i^(chi+1) = phi_max^(chi+1) i / N; the last
        // one takes what the others leave of A and of the continuous part's slip force
        // F_S - S phi_max, so that the sums are K_T and F_S to rounding (N = 1, beta = 0: the
        // Jenkins element k_t = K_T, F_c = F_S exactly)
        double lower = 0.0, k_sum = 0.0, f_sum = 0.0;  // phi_(i-1), the sums so far
        for (int i = 1; i < n; ++i) {
            const double upper = phi_max * std::pow(static_cast<double>(i) / n, 1.0 / (chi + 1.0));
            const double k = r * (std::pow(upper, chi + 1.0) - std::pow(lower, chi + 1.0)) / (chi + 1.0);
            const double f = r * (std::pow(upper, chi + 2.0) - std::pow(lower, chi + 2.0)) / (chi + 2.0);
            out.emplace_back(k, f);
            k_sum += k;
            f_sum += f;
            lower = upper;
        }
        out.emplace_back(a - k_sum, fs - beta * a * phi_max - f_sum);
        if (beta > 0.0) out.emplace_back(beta * a, beta * a * phi_max);
        return out;
    }
};

}  // namespace

const ContactLaw& iwan_law() {
    static const Iwan law;
    return law;
}

}  // namespace hbf
