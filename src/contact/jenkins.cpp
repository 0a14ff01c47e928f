// hbfriction — contact law `jenkins`: a tangential spring in series with a Coulomb slider.
//
// Definition: f = k_t (q - s), the spring k_t (= stiffness) in series with a Coulomb slider at
// s: s' = 0 while |k_t (q - s)| < F_c (stick), else the slider moves with q and
// f = F_c sign(q') (slip); the elastic-contact variant of Coulomb.
// Parameters: friction_limit F_c (> 0), stiffness k_t (> 0).
// While stuck: the spring k_t.
//
// Harmonic balance needs no extra unknowns: on the samples q_j of one period the slider is
// marched, j = 0, 1, ..., N_t - 1, 0, 1, ...: the trial force k_t (q_j - s) either stays
// within F_c (stick: s is kept) or the slider moves to s = q_j - F_c sign(trial) / k_t (slip),
// period after period until s at the end of a period repeats. Started from the centred
// slider s = (max q + min q) / 2, which is the symmetric permanent-stick solution when
// k_t (max q - min q) <= 2 F_c (otherwise every period slips and the start is forgotten
// after the first slip). Each force sample is linear in the samples of q on its stick/slip
// pattern (f_j = k_t (q_j - q_k) + F_c sign_k, k the last slip sample), so the Jacobian
// P G E is exact on the pattern, like that of the dynamic Lagrangian.
//
// Not smooth; its stick is exact (the event-exact solver and time integration's modes); its
// state in time is the slider position; default H 10 (a continuous force: within 4e-6 of time
// integration at H = 10).
#include <cmath>
#include <vector>

#include "contact/slider.hpp"
#include "hbf/contact_law.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {

/// Jenkins element marched over the period (see the top of this file).
class MarchedJenkins final : public FrictionModel {
public:
    explicit MarchedJenkins(const Contact& c) : limit_(c.friction_limit), stiffness_(c.stiffness) {}
    int state_signals() const override { return 0; }

    void evaluate(Fourier& fourier, double, const Eigen::VectorXd& q, const Eigen::VectorXd&,
                  FrictionEvaluation& out, bool jacobian) const override {
        const int nt = fourier.time_samples(), n = fourier.size();
        Eigen::VectorXd qt(nt);
        fourier.to_time(q, qt);
        const Cycle cycle = march(qt);
        out.force.resize(n);
        fourier.to_coefficients(cycle.force, out.force);
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        // f_j = k_t (q_j - sum_k W_jk q_k) + const on stick samples, constant on slip samples:
        // df/dq = k_t P (diag(stick) - W) E, W the anchor weights of each stick sample.
        Eigen::MatrixXd m(n, n);
        fourier.multiplication_matrix(cycle.stick, m);
        const Eigen::MatrixXd& E = fourier.synthesis();
        const Eigen::MatrixXd& P = fourier.analysis();
        Eigen::MatrixXd anchored = Eigen::MatrixXd::Zero(n, nt);  // P W, column k: sum of P's
        std::vector<char> used(static_cast<std::size_t>(nt), 0);   // columns anchored at k
        auto anchor = [&](Eigen::Index k, double weight, int j) {
            anchored.col(k) += weight * P.col(j);
            used[static_cast<std::size_t>(k)] = 1;
        };
        for (int j = 0; j < nt; ++j) {
            if (cycle.stick(j) == 0.0) continue;
            if (cycle.anchor[j] >= 0) {
                anchor(cycle.anchor[j], 1.0, j);
            } else {  // permanent stick: s = (q_max + q_min) / 2
                anchor(cycle.highest, 0.5, j);
                anchor(cycle.lowest, 0.5, j);
            }
        }
        // P W E over the anchors only (one per stuck run: two a period, against N_t columns;
        // 9.6 us against 816 us for the dense product at H = 20, benchmarks/normal_contact).
        out.force_q = stiffness_ * m;
        for (int k = 0; k < nt; ++k)
            if (used[static_cast<std::size_t>(k)]) out.force_q.noalias() -= stiffness_ * anchored.col(k) * E.row(k);
        out.force_omega = Eigen::VectorXd::Zero(n);
        out.jacobian_seconds = watch.lap();
    }

    Eigen::VectorXd force_samples(Fourier& fourier, double, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd&) const override {
        Eigen::VectorXd qt(fourier.time_samples());
        fourier.to_time(q, qt);
        return march(qt).force;
    }

    Eigen::VectorXd stick_indicator(Fourier& fourier, double, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd&) const override {
        Eigen::VectorXd qt(fourier.time_samples());
        fourier.to_time(q, qt);
        const Cycle cycle = march(qt);
        return (cycle.stick.array() * (cycle.force.array().abs() / limit_ - 1.0)).matrix();
    }

private:
    /// The periodic slider cycle on the samples q_j.
    struct Cycle {
        Eigen::VectorXd force;    ///< f_j
        Eigen::VectorXd stick;    ///< 1 where the slider rests at sample j, 0 where it moves
        std::vector<int> anchor;  ///< stick samples: the last slip sample (-1: permanent stick)
        Eigen::Index highest = 0, lowest = 0;
    };

    Cycle march(const Eigen::VectorXd& qt) const {
        const int nt = static_cast<int>(qt.size());
        Cycle c;
        c.force.resize(nt);
        c.stick.resize(nt);
        c.anchor.assign(static_cast<std::size_t>(nt), -1);
        double slider = 0.5 * (qt.maxCoeff(&c.highest) + qt.minCoeff(&c.lowest));
        int last_slip = -1;
        // Two periods settle the cycle (the first slip forgets the start); more are marched
        // only while the slider's position at the period's end still changes. The samples of
        // the last period before its first slip hang on the previous period's last slip,
        // which is the same sample once the cycle repeats.
        constexpr int max_periods = 8;
        for (int period = 0; period < max_periods; ++period) {
            const double start = slider;
            for (int j = 0; j < nt; ++j) {
                const double trial = stiffness_ * (qt(j) - slider);
                if (std::abs(trial) > limit_) {
                    const double sign = trial > 0.0 ? 1.0 : -1.0;
                    slider = qt(j) - sign * limit_ / stiffness_;
                    c.force(j) = sign * limit_;
                    c.stick(j) = 0.0;
                    last_slip = j;
                } else {
                    c.force(j) = trial;
                    c.stick(j) = 1.0;
                }
                c.anchor[static_cast<std::size_t>(j)] = last_slip;
            }
            if (last_slip < 0 || (period > 0 && slider == start)) break;
        }
        return c;
    }

    double limit_, stiffness_;
};

class Jenkins final : public detail::SliderLaw {
public:
    Jenkins()
        : SliderLaw(FrictionLaw::jenkins, "jenkins",
              "spring k_t in series with a Coulomb slider: f = k_t (q - s), |f| <= F_c") {}
    std::vector<LawParameter> parameters() const override {
        return {{"stiffness", &Contact::stiffness, "tangential stiffness k_t", LawParameter::Range::positive}};
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        return std::make_unique<MarchedJenkins>(contact);
    }
};

}  // namespace

const ContactLaw& jenkins_law() {
    static const Jenkins law;
    return law;
}

}  // namespace hbf
