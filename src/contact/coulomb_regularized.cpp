// hbfriction — contact law `coulomb-reg`: Coulomb friction regularised by tanh.
//
// Definition: f = F_c tanh(v / eps), a smooth (memoryless) Coulomb law.
// Parameters: friction_limit F_c (> 0), regularization eps (> 0, a velocity).
// While stuck: the damper F_c / eps (the slope at v = 0).
// Harmonic balance maps velocity samples to force samples pointwise: f = P f(E D q).
// Smooth (stick: |f| < stick_force_ratio F_c, i.e. |v| < eps atanh(ratio)); no state in time;
// default H 20. The AFT must resolve the tanh's turn (a phase of eps / max|v|): with too few
// time samples the FRF wiggles with spurious peaks at any H (the preset's eps = 0.05 at its
// resonance needs N_t = 4096); time_samples_needed says how many, and compute_frf raises an
// automatic N_t to it.
#include <cmath>

#include "hbf/contact_law.hpp"
#include "hbf/absorber.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {

/// f = F_c tanh(v / eps).
class Tanh final : public FrictionModel {
public:
    explicit Tanh(const Contact& c) : limit_(c.friction_limit), eps_(c.regularization) {}
    int state_signals() const override { return 0; }

    void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd&,
                  FrictionEvaluation& out, bool jacobian) const override {
        const Eigen::MatrixXd& D1 = fourier.derivative();
        const Eigen::VectorXd v_coefficients = omega * (D1 * q);
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(v_coefficients, v);
        const Eigen::ArrayXd t = (v.array() / eps_).tanh();
        out.force.resize(fourier.size());
        fourier.to_coefficients((limit_ * t).matrix(), out.force);
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        const Eigen::ArrayXd slope = limit_ / eps_ * (1.0 - t.square());  // df/dv
        // f = P f(v), v = omega E D1 q: df/dq = omega P diag(f') E D1, df/domega = P (f' v / omega).
        const int n = fourier.size();
        Eigen::MatrixXd p_slope(n, n);
        fourier.multiplication_matrix(slope.matrix(), p_slope);
        out.force_q = omega * fourier.times_derivative(p_slope);
        out.force_omega = p_slope * (D1 * q);
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(omega * (fourier.derivative() * q), v);
        return (limit_ * (v.array() / eps_).tanh()).matrix();
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd&) const override {
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(omega * (fourier.derivative() * q), v);
        return ((v.array() / eps_).tanh().abs() / stick_force_ratio - 1.0).matrix();
    }

    double time_samples_needed(Fourier& fourier, double omega, const Eigen::VectorXd& q) const override {
        Eigen::VectorXd v(fourier.time_samples());
        fourier.to_time(omega * (fourier.derivative() * q), v);
        return 2.0 * M_PI * v.cwiseAbs().maxCoeff() / eps_;
    }

private:
    double limit_, eps_;
};

class RegularizedCoulomb final : public ContactLaw {
public:
    RegularizedCoulomb()
        : ContactLaw(FrictionLaw::coulomb_regularized, "coulomb-reg",
              "regularised Coulomb: f = F_c tanh(v / eps)") {}
    std::vector<LawParameter> parameters() const override {
        return {{"regularization", &Contact::regularization, "tanh velocity scale eps", LawParameter::Range::positive}};
    }
    int default_harmonics() const override { return 20; }
    bool smooth() const override { return true; }
    bool exact_stick() const override { return false; }
    TimeState time_state() const override { return TimeState::none; }
    StuckElement stuck(const Contact& contact) const override {
        return {false, 0.0, contact.friction_limit / contact.regularization};
    }
    std::vector<std::string> preset_parameters() const override { return {"eps"}; }
    void from_preset(const AbsorberParameters& p, Contact& contact) const override {
        contact.regularization = p.regularization;
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return std::make_unique<Tanh>(contact);
    }
    double time_force(const Contact& contact, double, double v, double, double& rate) const override {
        rate = 0.0;
        return contact.friction_limit * std::tanh(v / contact.regularization);
    }
    double time_margin(const Contact& contact, double, double v, double) const override {
        return std::abs(std::tanh(v / contact.regularization)) / stick_force_ratio - 1.0;
    }
    /// A velocity law: at rest it carries no force (f = F_c tanh(0) = 0), so statically it slips.
    bool static_force(const Contact&, const Eigen::VectorXd&, StaticForce& out) const override {
        out.force = Eigen::VectorXd::Zero(1);
        out.jacobian = Eigen::MatrixXd::Zero(1, 1);
        out.state = "slipping";
        return true;
    }
    LocalLinearization linearize(const Contact& contact, double, double v, double) const override {
        LocalLinearization l;
        const double t = std::tanh(v / contact.regularization);
        l.f_v = contact.friction_limit * (1.0 - t * t) / contact.regularization;
        return l;
    }
};

}  // namespace

const ContactLaw& coulomb_regularized_law() {
    static const RegularizedCoulomb law;
    return law;
}

}  // namespace hbf
