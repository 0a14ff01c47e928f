// hbfriction — the elastic friction element with a varying normal load (normal_contact.hpp).
#include "hbf/normal_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "contact/enclosing_circle.hpp"
#include "hbf/error.hpp"

namespace hbf {

namespace {

void validate(const ElasticContact& e) {
    auto require = [](bool ok, const char* key, const char* allowed, double value) {
        if (!ok)
            throw InvalidInput(std::string(key) + " = " + format_number(value) + " is out of range: allowed " + allowed);
    };
    require(e.normal_stiffness > 0.0 && std::isfinite(e.normal_stiffness), "normal_stiffness", "finite and > 0",
            e.normal_stiffness);
    require(e.tangential_stiffness > 0.0 && std::isfinite(e.tangential_stiffness), "tangential_stiffness",
            "finite and > 0", e.tangential_stiffness);
    require(e.friction_coefficient >= 0.0 && std::isfinite(e.friction_coefficient), "friction_coefficient",
            "finite and >= 0", e.friction_coefficient);
    require(std::isfinite(e.normal_offset), "normal_offset", "finite", e.normal_offset);
    require(e.tangential_directions == 1 || e.tangential_directions == 2, "tangential_directions",
            "1 (2D element) or 2 (3D)", e.tangential_directions);
}

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;

/// The march of one element on given samples, with the derivatives of everything with respect
/// to the inputs' coefficients q = [u_1; ..; u_d; v] (m = (d + 1) n of them) when a synthesis
/// matrix E (N_t x n) is given. A derivative is a matrix with d + m columns: first with respect
/// to the slider s_0 before sample 0, then with respect to q.
class Marcher {
public:
    Marcher(const ElasticContact& e, const Matrix& u, const Vector& v, const Matrix* synthesis)
        : e_(e), u_(u), E_(synthesis), d_(e.tangential_directions), nt_(static_cast<int>(u.rows())),
          n_(synthesis ? static_cast<int>(synthesis->cols()) : 0), m_((d_ + 1) * n_) {
        gap_force_ = (e.normal_offset + e.normal_stiffness * v.array()).matrix();  // N before the max
        normal_ = gap_force_.cwiseMax(0.0);
        radius_ = e.friction_coefficient * normal_ / e.tangential_stiffness;
        scale_ = std::max({u.cwiseAbs().maxCoeff(), radius_.maxCoeff(), std::numeric_limits<double>::min()});
    }

    /// The periodic cycle; with `jacobian` (needs the synthesis matrix and the analysis P) the
    /// force coefficients' derivative d [T_1..T_d] / dq, (d n) x m.
    NormalContactCycle cycle(const Matrix* analysis, Matrix* jacobian, Vector* own_u = nullptr, Vector* own_v = nullptr) {
        NormalContactCycle c;
        c.normal = normal_;
        Vector centred(d_);
        Matrix centre_derivative;  // d s_0 / d q in permanent stick (d x m)
        centre(centred, jacobian ? &centre_derivative : nullptr);
        // Find the fixed point s_0 = Phi(s_0) from the centre: a pass without slip or separation
        // is permanent stick (then the centre is admissible, and taken); otherwise Newton on Phi
        // (Phi' = 0 after a 2D slip or any separation, so that is one plain step there).
        // Without the Jacobian every pass records the forces, and the last one (from the s_0
        // found) is the cycle; with it a last pass from s_0 carries the derivatives.
        c.tangential.resize(nt_, d_);
        c.state.resize(static_cast<std::size_t>(nt_));
        NormalContactCycle* record = jacobian ? nullptr : &c;
        Vector s0 = centred, previous_residual;
        bool recorded = false;  // the recorded forces are those of the final s_0
        for (int iteration = 0;; ++iteration) {
            Vector end;
            Matrix end_derivative;
            if (!pass(s0, end, end_derivative, record, nullptr, nullptr, false)) {
                recorded = iteration == 0;  // from the centre itself
                s0 = centred;
                c.permanent_stick = true;
                break;
            }
            recorded = true;
            const Vector residual = end - s0;
            if (residual.cwiseAbs().maxCoeff() <= 1e-13 * scale_) break;
            if (iteration >= 50)
                throw std::runtime_error("normal contact: the periodic slider was not found (residual " +
                                         format_number(residual.norm()) + " after 50 Newton steps)");
            const bool newton = previous_residual.size() == 0 || residual.norm() < 0.5 * previous_residual.norm();
            if (newton && d_ == 2)
                s0 += (Matrix::Identity(d_, d_) - end_derivative).fullPivLu().solve(residual);
            else
                s0 = end;  // a plain step where Newton did not halve the residual
            previous_residual = residual;
        }
        c.slider = s0;
        Vector end;
        Matrix end_derivative, force_derivative;
        if (!jacobian) {
            if (!recorded) pass(s0, end, end_derivative, &c, nullptr, nullptr, false);
            return c;
        }
        pass(s0, end, end_derivative, &c, analysis, &force_derivative, true, own_u, own_v);
        // d s_0 / d q: the centre's in permanent stick, else (I - Phi')^-1 dPhi/dq.
        Matrix ds0;
        if (c.permanent_stick)
            ds0 = centre_derivative;
        else
            ds0 = (Matrix::Identity(d_, d_) - end_derivative.leftCols(d_)).fullPivLu().solve(end_derivative.rightCols(m_));
        *jacobian = force_derivative.rightCols(m_) + force_derivative.leftCols(d_) * ds0;
        return c;
    }

private:
    /// u_j as a plane vector (second component 0 in 2D).
    Eigen::Vector2d sample(int j) const { return {u_(j, 0), d_ == 2 ? u_(j, 1) : 0.0}; }
    /// d u_j / dq (d rows) added into `out` (d + m columns), times factor.
    void add_du(int j, Eigen::Ref<Matrix> out, double factor) const {
        for (int k = 0; k < d_; ++k) out.block(k, d_ + k * n_, 1, n_) += factor * E_->row(j);
    }
    /// d r_j / dq added into row `row` of `out`, times factor: mu k_n / k_t on closed samples.
    void add_dr(int j, Eigen::Ref<Matrix> out, int row, double factor) const {
        if (normal_(j) <= 0.0) return;
        out.block(row, d_ + d_ * n_, 1, n_) +=
            factor * e_.friction_coefficient * e_.normal_stiffness / e_.tangential_stiffness * E_->row(j);
    }

    /// One period from s0: the slider after it (`end`) and, with derivatives (E given), its
    /// derivative (d x (d + m)). With `cycle` the forces and states are recorded; with
    /// `analysis` and `force` the force coefficients' derivative (d n x (d + m)) is summed, but
    /// for the parts diagonal in the samples, returned as sample weights instead (the caller's
    /// P diag(w) E, computed by FFT): own_u(j) = k_t on stuck samples (d T_k / d u_k) and, in
    /// 2D, own_v(j) = sign mu k_n on slipping ones (d T / d v). A stuck run's slider term
    /// -k_t d s is one rank-one update per run (d s does not change while the slider rests), and
    /// a 2D slip has no slider term at all; only a 3D slip adds a dense row block per sample.
    /// Returns whether a sample slipped or separated.
    bool pass(const Vector& s0, Vector& end, Matrix& end_derivative, NormalContactCycle* cycle, const Matrix* analysis,
              Matrix* force, bool with_q, Vector* own_u = nullptr, Vector* own_v = nullptr) const {
        // Derivatives with respect to s_0 always (Newton needs Phi'), to q when asked for.
        const bool derive_q = with_q && E_ != nullptr;
        const int columns = d_ + (derive_q ? m_ : 0);
        // Tangential vectors on the stack (the second component 0 in 2D): the march allocates
        // nothing per sample.
        Eigen::Vector2d s = Eigen::Vector2d::Zero();
        s.head(d_) = s0;
        Matrix ds = Matrix::Zero(d_, columns);
        ds.leftCols(d_).setIdentity();
        Vector run;  // sum of P's columns over the current stuck run
        bool in_run = false;
        if (force) {
            force->setZero(d_ * n_, columns);
            own_u->setZero(nt_);
            own_v->setZero(nt_);
            run.setZero(n_);
        }
        const double kt = e_.tangential_stiffness, mu = e_.friction_coefficient;
        auto flush = [&] {  // the stuck run's -k_t (sum_j P_j) d s
            if (!force || !in_run) return;
            run *= kt;
            for (int k = 0; k < d_; ++k) force->middleRows(k * n_, n_).noalias() -= run * ds.row(k);
            run.setZero();
            in_run = false;
        };
        bool event = false;
        Matrix dt(d_, columns), dtau(d_, columns), along(1, columns);
        for (int j = 0; j < nt_; ++j) {
            const auto index = static_cast<std::size_t>(j);
            if (normal_(j) <= 0.0) {  // separated: T = 0, s = u_j
                event = true;
                flush();
                s = sample(j);
                ds.setZero();
                if (derive_q) add_du(j, ds, 1.0);
                if (cycle) {
                    cycle->state[index] = ContactState::separated;
                    cycle->tangential.row(j).setZero();
                }
                continue;
            }
            const int p = j > 0 ? j - 1 : nt_ - 1;
            if (normal_(p) <= 0.0) {
                // Closing between samples p (open) and j: the slider is where u was at the
                // closing instant, theta of the way from p to j by linear interpolation of
                // g = N_0 + k_n v (g_p <= 0 < g_j), so that T grows from 0 there; the
                // alternative, u_p, is first order in the sample spacing (the tangential motion
                // between p and the closing would be seen as elastic load). At j = 0, p is the
                // period's last sample: s_0 = u_p then, and the interpolation overrides it.
                const double gp = gap_force_(p), gj = gap_force_(j), theta = gp / (gp - gj);
                s = sample(p) + theta * (sample(j) - sample(p));
                ds.setZero();
                if (derive_q) {
                    add_du(p, ds, 1.0 - theta);
                    add_du(j, ds, theta);
                    // d theta = k_n (g_p dv_j - g_j dv_p) / (g_p - g_j)^2
                    const double scale = e_.normal_stiffness / ((gp - gj) * (gp - gj));
                    for (int k = 0; k < d_; ++k) {
                        const double jump = sample(j)(k) - sample(p)(k);
                        ds.block(k, d_ + d_ * n_, 1, n_) += jump * scale * (gp * E_->row(j) - gj * E_->row(p));
                    }
                }
            }
            const Eigen::Vector2d trial = kt * (sample(j) - s);
            const double size = trial.norm(), limit = mu * normal_(j);
            if (size <= limit) {
                if (cycle) {
                    cycle->state[index] = ContactState::stuck;
                    cycle->tangential.row(j) = trial.head(d_).transpose();
                }
                if (force) {  // d T_j = k_t (d u_j - d s)
                    (*own_u)(j) = kt;
                    run += analysis->col(j);
                    in_run = true;
                }
                continue;
            }
            event = true;
            flush();
            const Eigen::Vector2d direction = trial / size, tau = limit * direction;
            if (d_ == 1) {
                // d tau = sign mu dN: no slider term (|trial| - limit scales it away)
                ds.setZero();
                if (derive_q) {
                    add_du(j, ds, 1.0);
                    ds.block(0, d_ + n_, 1, n_) -= direction(0) * mu * e_.normal_stiffness / kt * E_->row(j);
                }
                if (force) (*own_v)(j) = direction(0) * mu * e_.normal_stiffness;
            } else {
                // d tau = mu direction dN + limit (I - direction direction^T) d trial / |trial|,
                // d trial = k_t (d u_j - d s)
                dt = -kt * ds;
                if (derive_q) add_du(j, dt, kt);
                along.noalias() = direction.head(d_).transpose() * dt;
                dtau = dt;
                dtau.noalias() -= direction.head(d_) * along;
                dtau *= limit / size;
                if (derive_q)
                    for (int k = 0; k < d_; ++k)
                        dtau.block(k, d_ + d_ * n_, 1, n_) += mu * direction(k) * e_.normal_stiffness * E_->row(j);
                ds = -dtau / kt;  // s = u_j - tau / k_t
                if (derive_q) add_du(j, ds, 1.0);
                if (force)
                    for (int k = 0; k < d_; ++k)
                        force->middleRows(k * n_, n_).noalias() += analysis->col(j) * dtau.row(k);
            }
            s = sample(j) - tau / kt;
            if (cycle) {
                cycle->state[index] = ContactState::slipping;
                cycle->tangential.row(j) = tau.head(d_).transpose();
            }
        }
        flush();
        end = s.head(d_);
        end_derivative = ds;
        return event;
    }

    /// The permanent-stick slider argmin_s max_j (|s - u_j| - r_j) into s, and its derivative
    /// with respect to q (d x m) when `derivative` is given. Whether it is admissible shows in
    /// the march from it (a pass without slip or separation).
    void centre(Vector& s, Matrix* derivative) const {
        if (d_ == 1) {
            Eigen::Index a = 0, b = 0;
            const double lower = (u_.col(0).array() - radius_.array()).maxCoeff(&a);
            const double upper = (u_.col(0).array() + radius_.array()).minCoeff(&b);
            s.resize(1);
            s(0) = 0.5 * (lower + upper);
            if (derivative && E_) {
                Matrix full = Matrix::Zero(1, d_ + m_);
                add_du(static_cast<int>(a), full, 0.5);
                add_du(static_cast<int>(b), full, 0.5);
                add_dr(static_cast<int>(a), full, 0, -0.5);
                add_dr(static_cast<int>(b), full, 0, 0.5);
                *derivative = full.rightCols(m_);
            }
            return;
        }
        const detail::EnclosingCircle best = detail::smallest_enclosing_circle(u_, radius_, scale_);
        s = best.centre;
        if (derivative && E_) {
            Matrix full = Matrix::Zero(2, d_ + m_);
            const detail::EnclosingDerivative dd = detail::enclosing_circle_derivative(u_, radius_, best);
            for (int k = 0; k < best.size; ++k) {
                const int i = best.member[static_cast<std::size_t>(k)];
                for (int row = 0; row < 2; ++row) {
                    for (int c = 0; c < 2; ++c)
                        full.block(row, d_ + c * n_, 1, n_) += dd.du[static_cast<std::size_t>(k)](row, c) * E_->row(i);
                    add_dr(i, full, row, dd.dr[static_cast<std::size_t>(k)](row));
                }
            }
            *derivative = full.rightCols(m_);
        }
    }

    const ElasticContact& e_;
    const Matrix& u_;
    const Matrix* E_;
    int d_, nt_, n_, m_;
    Vector gap_force_, normal_, radius_;
    double scale_ = 1.0;
};

}  // namespace

NormalContactCycle march(const ElasticContact& e, const Eigen::MatrixXd& u, const Eigen::VectorXd& v) {
    validate(e);
    if (u.rows() != v.size() || u.rows() == 0 || u.cols() != e.tangential_directions)
        throw InvalidInput("normal contact: " + std::to_string(u.rows()) + " x " + std::to_string(u.cols()) +
                           " tangential and " + std::to_string(v.size()) +
                           " normal samples: allowed N_t x d and N_t, N_t > 0, d = tangential_directions");
    Marcher marcher(e, u, v, nullptr);
    return marcher.cycle(nullptr, nullptr);
}

void evaluate(const ElasticContact& e, Fourier& fourier, const Eigen::VectorXd& q, NormalContactEvaluation& out,
              bool jacobian) {
    validate(e);
    const int nt = fourier.time_samples(), n = fourier.size(), d = e.tangential_directions, m = (d + 1) * n;
    if (q.size() != m)
        throw InvalidInput("normal contact: " + std::to_string(q.size()) + " coefficients: allowed (d + 1) (2H + 1) = " +
                           std::to_string(m));
    Eigen::MatrixXd u(nt, d);
    Eigen::VectorXd v(nt);
    for (int k = 0; k < d; ++k) fourier.to_time(q.segment(k * n, n), u.col(k));
    fourier.to_time(q.segment(d * n, n), v);
    Marcher marcher(e, u, v, jacobian ? &fourier.synthesis() : nullptr);
    Eigen::MatrixXd tangential_jacobian;
    Eigen::VectorXd own_u, own_v;
    const NormalContactCycle cycle = marcher.cycle(jacobian ? &fourier.analysis() : nullptr,
                                                   jacobian ? &tangential_jacobian : nullptr, &own_u, &own_v);
    out.force.resize(m);
    for (int k = 0; k < d; ++k) fourier.to_coefficients(cycle.tangential.col(k), out.force.segment(k * n, n));
    fourier.to_coefficients(cycle.normal, out.force.segment(d * n, n));
    if (!jacobian) return;
    out.jacobian = Eigen::MatrixXd::Zero(m, m);
    out.jacobian.topRows(d * n) = tangential_jacobian;
    Eigen::VectorXd closed(nt);
    for (int j = 0; j < nt; ++j) closed(j) = cycle.normal(j) > 0.0 ? e.normal_stiffness : 0.0;
    Eigen::MatrixXd block(n, n);
    fourier.multiplication_matrix(closed, block);
    out.jacobian.block(d * n, d * n, n, n) = block;
    // The parts diagonal in the samples (Marcher::pass): d T_k / d u_k on stuck samples, and in
    // 2D d T / d v on slipping ones.
    fourier.multiplication_matrix(own_u, block);
    for (int k = 0; k < d; ++k) out.jacobian.block(k * n, k * n, n, n) += block;
    if (d == 1) {
        fourier.multiplication_matrix(own_v, block);
        out.jacobian.block(0, n, n, n) += block;
    }
}

}  // namespace hbf
