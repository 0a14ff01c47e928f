// hbfriction — the force elements' shared AFT model and static force (force_element.hpp).
#include "contact/force_element.hpp"

#include "base/stopwatch.hpp"

namespace hbf::detail {

namespace {

/// f, f_q, f_v on the time samples.
struct Samples {
    Eigen::VectorXd f, fq, fv;
};

class PointwiseModel final : public FrictionModel {
public:
    explicit PointwiseModel(std::shared_ptr<const PointwiseForce> force) : force_(std::move(force)) {}
    int state_signals() const override { return 0; }

    void evaluate(Fourier& fourier, double omega, const Eigen::VectorXd& q, const Eigen::VectorXd&,
                  FrictionEvaluation& out, bool jacobian) const override {
        const int n = fourier.size();
        const Samples s = samples(fourier, omega, q);
        out.force.resize(n);
        fourier.to_coefficients(s.f, out.force);
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        Stopwatch watch;
        Eigen::MatrixXd p(n, n);
        out.force_q = Eigen::MatrixXd::Zero(n, n);
        out.force_omega = Eigen::VectorXd::Zero(n);
        if (s.fq.cwiseAbs().maxCoeff() > 0.0) {
            fourier.multiplication_matrix(s.fq, p);
            out.force_q += p;
        }
        if (force_->uses_velocity() && s.fv.cwiseAbs().maxCoeff() > 0.0) {
            fourier.multiplication_matrix(s.fv, p);
            out.force_q += omega * fourier.times_derivative(p);
            out.force_omega = p * (fourier.derivative() * q);
        }
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double omega, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        return samples(fourier, omega, q).f;
    }

    /// No stick: every sample "slips" (the regime is "none": ContactLaw::friction).
    Eigen::VectorXd stick_indicator(Fourier& fourier, double, const Eigen::VectorXd&,
                                    const Eigen::VectorXd&) const override {
        return Eigen::VectorXd::Ones(fourier.time_samples());
    }

    double time_samples_needed(Fourier& fourier, double, const Eigen::VectorXd&) const override {
        return force_->samples_needed(fourier.harmonics());
    }
    std::string time_samples_reason() const override { return force_->samples_reason(); }

private:
    Samples samples(Fourier& fourier, double omega, const Eigen::VectorXd& q) const {
        const int nt = fourier.time_samples();
        Eigen::VectorXd u(nt), v = Eigen::VectorXd::Zero(nt);
        fourier.to_time(q, u);
        if (force_->uses_velocity()) fourier.to_time(omega * (fourier.derivative() * q), v);
        Samples s{Eigen::VectorXd(nt), Eigen::VectorXd(nt), Eigen::VectorXd(nt)};
        for (int j = 0; j < nt; ++j) {
            const PointForce p = force_->at(u(j), v(j));
            s.f(j) = p.force;
            s.fq(j) = p.slope_q;
            s.fv(j) = p.slope_v;
        }
        return s;
    }

    std::shared_ptr<const PointwiseForce> force_;
};

/// A force element bound to its contact: the pointwise force, built once.
class BoundForceElement final : public BoundLaw {
public:
    explicit BoundForceElement(std::shared_ptr<const PointwiseForce> force) : force_(std::move(force)) {}
    double force(double q, double v, double, double& rate) const override {
        rate = 0.0;
        return force_->at(q, v).force;
    }
    double margin(double q, double, double) const override { return force_->margin(q); }
    LocalLinearization linearize(double q, double v, double) const override {
        const PointForce p = force_->at(q, v);
        LocalLinearization l;
        l.f_q = p.slope_q;
        l.f_v = p.slope_v;
        return l;
    }

private:
    std::shared_ptr<const PointwiseForce> force_;
};

}  // namespace

std::unique_ptr<BoundLaw> ForceElementLaw::bind(const Contact& contact) const {
    return std::make_unique<BoundForceElement>(force(contact));
}

std::unique_ptr<FrictionModel> pointwise_model(std::shared_ptr<const PointwiseForce> force) {
    return std::make_unique<PointwiseModel>(std::move(force));
}

bool ForceElementLaw::static_force(const Contact& contact, const Eigen::VectorXd& q, StaticForce& out) const {
    const PointForce p = force(contact)->at(q(0), 0.0);
    out.force = Eigen::VectorXd::Constant(1, p.force);
    out.jacobian = Eigen::MatrixXd::Constant(1, 1, p.slope_q);
    out.state = unilateral() && p.force <= 0.0 ? "open" : "elastic";
    return true;
}

}  // namespace hbf::detail
