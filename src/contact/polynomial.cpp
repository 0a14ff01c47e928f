// hbfriction — law `polynomial`: a nonlinear spring whose force is a polynomial of its relative
// displacement (a cubic spring, a Duffing oscillator's stiffness, a hardening or softening
// support), or of several coordinates (the quadratic and cubic stiffness of a reduced model's
// modal coordinates, a geometrically nonlinear beam).
//
// One coordinate: f = k2 q^2 + k3 q^3 + sum_j c_j q^(e_j), acting as -w f on the structure like
// every contact's force (so k3 > 0 stiffens, k3 < 0 softens). The structure's own K carries the
// linear stiffness; a term of exponent 1 adds to it.
// Several coordinates: q_1 = w^T y (the contact's own direction) and q_2..q_m the rows of
// `directions` (q_j = d_j^T y); the forces
//     f_i = sum_k C_ki prod_j q_j^(E_kj),   i = 1..m,
// act as -sum_i w_i f_i, with E (`exponents`) and C (`coefficients`) of one row per term and one
// column per coordinate (the form of NLvib's polynomial stiffness and of the implicit-
// condensation ROMs), plus the one-coordinate terms above on q_1. The degree of a term is its
// row sum; a linear term (degree 1) must act on its own coordinate only (a coupling linear
// stiffness belongs to K).
// Parameters: quadratic k2 and cubic k3 (finite, default 0); terms: pairs (e_j, c_j) with e_j an
// integer in 1..max_polynomial_degree and c_j finite; directions, exponents (integers >= 0, row
// sums 1..max_polynomial_degree) and coefficients (finite) as above; at least one non-zero
// coefficient. While stuck (the linear limits, the first guess): the springs of its linear terms.
//
// Harmonic balance: f_i = P f_i(E q_1, .., E q_m) with the exact Jacobian blocks
// P diag(d f_i / d q_j) E. The product of a degree-p polynomial of an H-harmonic signal has
// harmonics up to p H, which N_t samples alias onto N_t - p H and above: the H balanced
// harmonics are exact when N_t > (p + 1) H (time_samples_needed: (p + 1) H + 1; the automatic
// N_t, at least 16 H + 8, covers every allowed degree). Smooth: time integration, stability
// (f_q = f'(q), or the m x m slopes), no stick (friction() is false: regime "none"). No internal
// state; default H 10, the automatic H's floor (measured: H = 9 puts a Duffing oscillator's
// truncation at 1e-6 against time integration at moderate amplitude).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "base/stopwatch.hpp"
#include "contact/force_element.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

/// The largest degree a polynomial term may have (the alias-free N_t grows as (p + 1) H).
constexpr int max_polynomial_degree = 15;
const char* const directions_key = "directions";
const char* const exponents_key = "exponents";
const char* const coefficients_key = "coefficients";

/// The terms c q^e of a contact's first coordinate, merged by exponent (zero coefficients dropped).
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

/// The number of coordinates m: 1 + the rows of `directions`.
int coordinates(const Contact& contact) {
    const auto at = contact.tables.find(directions_key);
    return 1 + (at == contact.tables.end() ? 0 : static_cast<int>(at->second.rows()));
}

const Eigen::MatrixXd* table(const Contact& contact, const char* key) {
    const auto at = contact.tables.find(key);
    return at == contact.tables.end() ? nullptr : &at->second;
}

/// Whether the contact is a polynomial of several coordinates, or given by its tables.
bool several(const Contact& contact) { return coordinates(contact) > 1 || table(contact, exponents_key) != nullptr; }

/// Every term as a row: exponents (m) and coefficients (m), the one-coordinate terms on q_1
/// included; rows without a non-zero coefficient dropped.
struct Terms {
    Eigen::MatrixXi exponents;
    Eigen::MatrixXd coefficients;
    int degree = 1;
};

Terms all_terms(const Contact& contact) {
    const int m = coordinates(contact);
    const Eigen::MatrixXd* e = table(contact, exponents_key);
    const Eigen::MatrixXd* c = table(contact, coefficients_key);
    const std::vector<std::pair<int, double>> single = polynomial_terms(contact);
    std::vector<std::pair<Eigen::VectorXi, Eigen::VectorXd>> rows;
    for (const auto& [exponent, coefficient] : single) {
        Eigen::VectorXi er = Eigen::VectorXi::Zero(m);
        Eigen::VectorXd cr = Eigen::VectorXd::Zero(m);
        er(0) = exponent;
        cr(0) = coefficient;
        rows.emplace_back(er, cr);
    }
    if (e && c)
        for (Eigen::Index k = 0; k < e->rows(); ++k) {
            if (c->row(k).cwiseAbs().maxCoeff() == 0.0) continue;
            rows.emplace_back(e->row(k).transpose().cast<int>(), c->row(k).transpose());
        }
    Terms t;
    t.exponents.resize(static_cast<Eigen::Index>(rows.size()), m);
    t.coefficients.resize(static_cast<Eigen::Index>(rows.size()), m);
    for (std::size_t k = 0; k < rows.size(); ++k) {
        t.exponents.row(static_cast<Eigen::Index>(k)) = rows[k].first.transpose();
        t.coefficients.row(static_cast<Eigen::Index>(k)) = rows[k].second.transpose();
        t.degree = std::max(t.degree, rows[k].first.sum());
    }
    return t;
}

std::string samples_text(int degree) {
    return "is a polynomial of degree " + std::to_string(degree) + ", alias-free when N_t > (p + 1) H = " +
           std::to_string(degree + 1) + " H";
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
    std::string samples_reason() const override { return samples_text(degree_); }

private:
    std::vector<std::pair<int, double>> terms_;
    int degree_ = 1;
};

/// The forces of several coordinates at one instant: f (m) and, where asked, F(i, j) = d f_i / d q_j.
class SeveralCoordinates {
public:
    explicit SeveralCoordinates(Terms terms) : t_(std::move(terms)) {}
    int size() const { return static_cast<int>(t_.exponents.cols()); }
    int degree() const { return t_.degree; }

    void at(const double* q, Eigen::Ref<Eigen::VectorXd> f, Eigen::MatrixXd* slopes) const {
        const int m = size(), d = t_.degree;
        // powers(j, e) = q_j^e, e = 0..degree
        powers_.resize(m, d + 1);
        for (int j = 0; j < m; ++j) {
            powers_(j, 0) = 1.0;
            for (int e = 1; e <= d; ++e) powers_(j, e) = powers_(j, e - 1) * q[j];
        }
        f.setZero();
        if (slopes) slopes->setZero(m, m);
        for (Eigen::Index k = 0; k < t_.exponents.rows(); ++k) {
            double monomial = 1.0;
            for (int j = 0; j < m; ++j) monomial *= powers_(j, t_.exponents(k, j));
            f.noalias() += monomial * t_.coefficients.row(k).transpose();
            if (!slopes) continue;
            for (int j = 0; j < m; ++j) {
                const int e = t_.exponents(k, j);
                if (e == 0) continue;
                double derivative = e * powers_(j, e - 1);  // d monomial / d q_j
                for (int l = 0; l < m; ++l)
                    if (l != j) derivative *= powers_(l, t_.exponents(k, l));
                slopes->col(j).noalias() += derivative * t_.coefficients.row(k).transpose();
            }
        }
    }

private:
    Terms t_;
    mutable Eigen::MatrixXd powers_;
};

/// The AFT model of several coordinates (contact_force.hpp: signals() = m).
class SeveralModel final : public FrictionModel {
public:
    explicit SeveralModel(Terms terms) : force_(std::move(terms)) {}
    int state_signals() const override { return 0; }
    int signals() const override { return force_.size(); }

    void evaluate(Fourier& fourier, double, const Eigen::VectorXd& q, const Eigen::VectorXd&, FrictionEvaluation& out,
                  bool jacobian) const override {
        const int n = fourier.size(), m = force_.size();
        Eigen::MatrixXd f, slopes;
        samples(fourier, q, f, jacobian ? &slopes : nullptr);
        out.force.resize(m * n);
        for (int i = 0; i < m; ++i) fourier.to_coefficients(f.col(i), out.force.segment(i * n, n));
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        out.force_q = Eigen::MatrixXd::Zero(m * n, m * n);
        out.force_omega = Eigen::VectorXd::Zero(m * n);
        Eigen::MatrixXd p(n, n);
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < m; ++j) {
                const auto column = slopes.col(i * m + j);
                if (column.cwiseAbs().maxCoeff() == 0.0) continue;
                fourier.multiplication_matrix(column, p);
                out.force_q.block(i * n, j * n, n, n) = p;
            }
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        Eigen::MatrixXd f;
        samples(fourier, q, f, nullptr);
        return Eigen::Map<const Eigen::VectorXd>(f.data(), f.size());
    }
    Eigen::VectorXd stick_indicator(Fourier& fourier, double, const Eigen::VectorXd&,
                                    const Eigen::VectorXd&) const override {
        return Eigen::VectorXd::Ones(fourier.time_samples());
    }
    double time_samples_needed(Fourier& fourier, double, const Eigen::VectorXd&) const override {
        return (force_.degree() + 1.0) * fourier.harmonics() + 1.0;
    }
    std::string time_samples_reason() const override { return samples_text(force_.degree()); }

private:
    /// f: N_t x m samples; slopes (if asked): N_t x m^2, column i m + j the samples of d f_i / d q_j.
    void samples(Fourier& fourier, const Eigen::VectorXd& q, Eigen::MatrixXd& f, Eigen::MatrixXd* slopes) const {
        const int n = fourier.size(), nt = fourier.time_samples(), m = force_.size();
        Eigen::MatrixXd u(m, nt);
        Eigen::VectorXd column(nt);
        for (int j = 0; j < m; ++j) {
            fourier.to_time(q.segment(j * n, n), column);
            u.row(j) = column.transpose();
        }
        f.resize(nt, m);
        if (slopes) slopes->resize(nt, m * m);
        Eigen::VectorXd fj(m);
        Eigen::MatrixXd s(m, m);
        for (int t = 0; t < nt; ++t) {
            force_.at(u.col(t).data(), fj, slopes ? &s : nullptr);
            f.row(t) = fj.transpose();
            if (slopes)
                for (int i = 0; i < m; ++i)
                    for (int j = 0; j < m; ++j) (*slopes)(t, i * m + j) = s(i, j);
        }
    }

    SeveralCoordinates force_;
};

/// Several coordinates bound to a contact for the time domain (BoundLaw::forces).
class BoundSeveral final : public BoundLaw {
public:
    explicit BoundSeveral(Terms terms) : force_(std::move(terms)) {}
    int directions() const override { return force_.size(); }
    void forces(const Eigen::VectorXd& q, const Eigen::VectorXd&, Eigen::VectorXd& f, Eigen::MatrixXd* f_q,
                Eigen::MatrixXd* f_v) const override {
        f.resize(force_.size());
        force_.at(q.data(), f, f_q);
        if (f_v) f_v->setZero(force_.size(), force_.size());
    }
    /// No event: the force is smooth.
    double margin(double, double, double) const override { return 1.0; }
    double force(double, double, double, double&) const override {
        throw std::logic_error("a polynomial of several coordinates has no force along one direction: forces()");
    }
    LocalLinearization linearize(double, double, double) const override {
        throw std::logic_error("a polynomial of several coordinates has no slope along one direction: forces()");
    }

private:
    SeveralCoordinates force_;
};

class PolynomialLaw final : public detail::ForceElementLaw {
public:
    PolynomialLaw()
        : ForceElementLaw(FrictionLaw::polynomial, "polynomial",
                          "polynomial stiffness: f = k2 q^2 + k3 q^3 + sum c_j q^e_j, or f_i = sum_k C_ki prod_j "
                          "q_j^E_kj over several coordinates") {}
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        static_assert(max_polynomial_degree == 15, "the meanings below name the bound");
        LawParameter terms{"terms", nullptr, "polynomial terms (e_j, c_j): f += c_j q^e_j, e_j an integer in 1..15",
                           R::finite};
        terms.kind = LawParameter::Kind::pairs;
        LawParameter directions{directions_key, nullptr,
                                "further coordinates q_2..q_m: one row of N entries each (q_j = d_j^T y)", R::finite};
        directions.kind = LawParameter::Kind::direction_rows;
        LawParameter exponents{exponents_key, nullptr,
                               "exponents E: one row per term, one column per coordinate (integers >= 0, row sum "
                               "1..15): the term's monomial prod_j q_j^E_kj",
                               R::finite};
        exponents.kind = LawParameter::Kind::rows;
        LawParameter coefficients{coefficients_key, nullptr,
                                  "coefficients C: one row per term, one column per coordinate (finite): f_i += C_ki "
                                  "prod_j q_j^E_kj",
                                  R::finite};
        coefficients.kind = LawParameter::Kind::rows;
        return {{"quadratic", nullptr, "quadratic stiffness k2 (f += k2 q^2)", R::finite},
                {"cubic", nullptr, "cubic stiffness k3 (f += k3 q^3)", R::finite},
                terms,
                directions,
                exponents,
                coefficients};
    }
    int default_harmonics() const override { return 10; }
    StuckElement stuck(const Contact& contact) const override { return stuck_directions(contact).front(); }
    /// The springs of the linear terms, one per coordinate (a linear term acts on its own).
    std::vector<StuckElement> stuck_directions(const Contact& contact) const override {
        const Terms t = all_terms(contact);
        std::vector<StuckElement> out(static_cast<std::size_t>(t.exponents.cols()));
        for (Eigen::Index k = 0; k < t.exponents.rows(); ++k) {
            if (t.exponents.row(k).sum() != 1) continue;
            Eigen::Index j = 0;
            t.exponents.row(k).maxCoeff(&j);
            out[static_cast<std::size_t>(j)].stiffness += t.coefficients(k, j);
        }
        return out;
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
        validate_tables(contact, where);
        if (all_terms(contact).exponents.rows() == 0)
            throw InvalidInput(where + "law polynomial has no term: give cubic, quadratic, terms, or exponents and "
                                       "coefficients with a non-zero coefficient");
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        if (several(contact)) return std::make_unique<SeveralModel>(all_terms(contact));
        return ForceElementLaw::periodic_model(contact);
    }
    std::unique_ptr<BoundLaw> bind(const Contact& contact) const override {
        if (several(contact)) return std::make_unique<BoundSeveral>(all_terms(contact));
        return ForceElementLaw::bind(contact);
    }
    bool static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const override {
        if (!several(contact)) return ForceElementLaw::static_force(contact, q, out);
        const SeveralCoordinates force(all_terms(contact));
        out.force.resize(force.size());
        force.at(q.data(), out.force, &out.jacobian);
        out.state = "elastic";
        return true;
    }
    std::shared_ptr<const detail::PointwiseForce> force(const Contact& contact) const override {
        return std::make_shared<Polynomial>(polynomial_terms(contact));
    }

private:
    static void validate_tables(const Contact& contact, const std::string& where) {
        const Eigen::MatrixXd* e = table(contact, exponents_key);
        const Eigen::MatrixXd* c = table(contact, coefficients_key);
        const int m = coordinates(contact);
        if (!e && !c) {
            if (m > 1)
                throw InvalidInput(where + directions_key + " is given without exponents and coefficients: allowed "
                                           "only with them (the terms over the coordinates)");
            return;
        }
        if (!e || !c)
            throw InvalidInput(where + (e ? coefficients_key : exponents_key) + " is missing: exponents and "
                               "coefficients go together (one row per term each)");
        if (e->rows() != c->rows())
            throw InvalidInput(where + coefficients_key + " has " + std::to_string(c->rows()) + " rows: allowed " +
                               std::to_string(e->rows()) + ", one per row of exponents");
        for (const auto& [key, t] : {std::make_pair(exponents_key, e), std::make_pair(coefficients_key, c)})
            if (t->cols() != m)
                throw InvalidInput(where + key + " has " + std::to_string(t->cols()) + " columns: allowed " +
                                   std::to_string(m) + ", one per coordinate (the contact's direction and " +
                                   std::to_string(m - 1) + " rows of directions)");
        for (Eigen::Index k = 0; k < e->rows(); ++k) {
            const std::string at = where + exponents_key + "[" + std::to_string(k + 1) + "]";
            double degree = 0.0;
            for (Eigen::Index j = 0; j < m; ++j) {
                const double x = (*e)(k, j);
                if (!(std::isfinite(x) && x == std::floor(x) && x >= 0.0 && x <= max_polynomial_degree))
                    throw InvalidInput(at + ": exponent " + format_number(x) + " is out of range: allowed an integer in "
                                       "0.." + std::to_string(max_polynomial_degree));
                degree += x;
            }
            if (degree < 1.0 || degree > max_polynomial_degree)
                throw InvalidInput(at + ": degree (row sum) " + format_number(degree) + " is out of range: allowed 1.." +
                                   std::to_string(max_polynomial_degree) + (degree < 1.0 ? " (a constant force is a static_load)" : ""));
            if (!c->row(k).allFinite())
                throw InvalidInput(where + coefficients_key + "[" + std::to_string(k + 1) + "]: a coefficient is not "
                                   "finite: allowed finite numbers");
            if (degree == 1.0) {
                Eigen::Index j = 0;
                e->row(k).maxCoeff(&j);
                for (Eigen::Index i = 0; i < m; ++i)
                    if (i != j && (*c)(k, i) != 0.0)
                        throw InvalidInput(where + coefficients_key + "[" + std::to_string(k + 1) + "]: a linear term "
                                           "of coordinate " + std::to_string(j + 1) + " acts on coordinate " +
                                           std::to_string(i + 1) + ": allowed on its own coordinate only (a "
                                           "coupling linear stiffness belongs to the stiffness matrix K)");
            }
        }
    }
};

}  // namespace

const ContactLaw& polynomial_law() {
    static const PolynomialLaw law;
    return law;
}

}  // namespace hbf
