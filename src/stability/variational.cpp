// hbfriction — the variational equation of an HB solution and Hill's matrix (variational.hpp).
#include "stability/variational.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <stdexcept>
#include <string>

namespace hbf::detail {

void at_phase(const Eigen::VectorXd& c, double theta, double& value, double& rate) {
    value = c(0);
    rate = 0.0;
    for (int k = 1; 2 * k < c.size(); ++k) {
        const double ck = std::cos(k * theta), sk = std::sin(k * theta);
        value += c(2 * k - 1) * ck + c(2 * k) * sk;
        rate += k * (c(2 * k) * ck - c(2 * k - 1) * sk);
    }
}

Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& a) {
    Eigen::EigenSolver<Eigen::MatrixXd> solver(a, false);
    if (solver.info() != Eigen::Success) return {};
    return solver.eigenvalues();
}

Variational::Variational(HarmonicBalance& hb, const Eigen::MatrixXd& minv, const Eigen::MatrixXd& w,
                         const SolutionPoint& p)
    : system_(hb.system()), omega_(p.omega), n_(hb.system().dofs()) {
    const int nc = static_cast<int>(system_.contacts.size());
    state_index_.assign(static_cast<std::size_t>(nc), -1);
    int s = 0;
    for (int c = 0; c < nc; ++c) {
        q_.push_back(hb.relative(p.x, c));
        z_.push_back(hb.state(p.x, c));
        const Contact& contact = system_.contacts[static_cast<std::size_t>(c)];
        laws_.push_back(contact_law(contact.law).bind(contact));
        if (z_.back().size() > 0) state_index_[static_cast<std::size_t>(c)] = 2 * n_ + s++;
        first_.push_back(c == 0 ? 0 : first_.back() + count_.back());
        count_.push_back(laws_.back()->directions());
    }
    if (nc > 0 && first_.back() + count_.back() != w.cols())
        throw std::logic_error("Variational: the contacts have " + std::to_string(first_.back() + count_.back()) +
                               " directions, w " + std::to_string(w.cols()) + " columns");
    d_ = 2 * n_ + s;
    base_ = Eigen::MatrixXd::Zero(d_, d_);
    base_.block(0, n_, n_, n_).setIdentity();
    const Eigen::MatrixXd K = Eigen::MatrixXd(system_.stiffness);
    const Eigen::MatrixXd C = system_.damping.size() > 0 && system_.damping.rows() == n_
                                  ? Eigen::MatrixXd(system_.damping)
                                  : Eigen::MatrixXd::Zero(n_, n_);
    base_.block(n_, 0, n_, n_) = -minv * K;
    base_.block(n_, n_, n_, n_) = -minv * C;
    w_ = w;
    mw_ = minv * w;
}

void Variational::motion(int c, double theta, Eigen::VectorXd& q, Eigen::VectorXd& v) const {
    const auto cc = static_cast<std::size_t>(c);
    const int count = count_[cc];
    const auto n = q_[cc].size() / count;
    q.resize(count);
    v.resize(count);
    for (int j = 0; j < count; ++j) {
        double dq = 0.0;
        at_phase(q_[cc].segment(j * n, n), theta, q(j), dq);
        v(j) = omega_ * dq;
    }
}

void Variational::matrix(double theta, Eigen::MatrixXd& a) const {
    a = base_;
    for (std::size_t c = 0; c < q_.size(); ++c) add_contact(static_cast<int>(c), theta, a);
}

void Variational::add_contact(int c, double theta, Eigen::MatrixXd& a) const {
    const auto cc = static_cast<std::size_t>(c);
    const int first = first_[cc], count = count_[cc];
    if (count > 1) {  // several coordinates: the m x m slopes, no state
        motion(c, theta, q_at_, v_at_);
        laws_[cc]->forces(q_at_, v_at_, f_at_, &fq_at_, &fv_at_);
        const auto mw = mw_.middleCols(first, count);
        const auto w = w_.middleCols(first, count);
        a.block(n_, 0, n_, n_).noalias() -= mw * fq_at_ * w.transpose();
        if (fv_at_.cwiseAbs().maxCoeff() > 0.0) a.block(n_, n_, n_, n_).noalias() -= mw * fv_at_ * w.transpose();
        return;
    }
    double q, dq, z = 0.0, dz;
    at_phase(q_[cc], theta, q, dq);
    if (z_[cc].size() > 0) at_phase(z_[cc], theta, z, dz);
    const LocalLinearization l = laws_[cc]->linearize(q, omega_ * dq, z);
    const auto col = static_cast<Eigen::Index>(first);
    a.block(n_, n_, n_, n_).noalias() -= l.f_v * mw_.col(col) * w_.col(col).transpose();
    if (l.f_q != 0.0) a.block(n_, 0, n_, n_).noalias() -= l.f_q * mw_.col(col) * w_.col(col).transpose();
    const int s = state_index_[cc];
    if (s < 0) return;
    a.block(n_, s, n_, 1) -= l.f_z * mw_.col(col);
    a.block(s, n_, 1, n_) += l.g_v * w_.col(col).transpose();
    a(s, s) += l.g_z;
}

Eigen::MatrixXd Variational::hill(Fourier& fourier) const {
    const int m = fourier.size(), nt = fourier.time_samples();
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(d_ * m, d_ * m);
    // The constant part: a_ij I per block.
    for (int i = 0; i < d_; ++i)
        for (int j = 0; j < d_; ++j)
            if (base_(i, j) != 0.0) h.block(i * m, j * m, m, m).diagonal().setConstant(base_(i, j));
    // The contacts' parts: each entry of A is a combination of the slopes' samples.
    const int nc = static_cast<int>(q_.size());
    Eigen::MatrixXd p(m, m);
    // Adds -M^-1 w_a slope w_b^T to the rows of the velocities and the columns `column` (0: the
    // displacements, n_: the velocities), `slope` sampled on the AFT grid.
    auto add_outer = [&](const Eigen::VectorXd& slope, Eigen::Index a, Eigen::Index b, int column) {
        if (slope.cwiseAbs().maxCoeff() == 0.0) return;
        fourier.multiplication_matrix(slope, p);
        const Eigen::MatrixXd outer = -mw_.col(a) * w_.col(b).transpose();
        for (int i = 0; i < n_; ++i)
            for (int j = 0; j < n_; ++j)
                if (outer(i, j) != 0.0) h.block((n_ + i) * m, (column + j) * m, m, m) += outer(i, j) * p;
    };
    for (int c = 0; c < nc; ++c) {
        const auto cc = static_cast<std::size_t>(c);
        const int first = first_[cc], count = count_[cc];
        // q_c, v_c (and z_c) on the AFT grid by the FFT (Fourier::to_time), then the slopes pointwise.
        Eigen::MatrixXd q(nt, count), v(nt, count);
        const auto n = q_[cc].size() / count;
        for (int j = 0; j < count; ++j) {
            fourier.to_time(q_[cc].segment(j * n, n), q.col(j));
            fourier.to_time(omega_ * (fourier.derivative() * q_[cc].segment(j * n, n)), v.col(j));
        }
        if (count > 1) {  // several coordinates: slope (i, j) of every sample
            Eigen::MatrixXd fq(nt, count * count), fv(nt, count * count);
            Eigen::VectorXd qt(count), vt(count), f;
            Eigen::MatrixXd sq, sv;
            for (int t = 0; t < nt; ++t) {
                qt = q.row(t).transpose();
                vt = v.row(t).transpose();
                laws_[cc]->forces(qt, vt, f, &sq, &sv);
                for (int a = 0; a < count; ++a)
                    for (int b = 0; b < count; ++b) {
                        fq(t, a * count + b) = sq(a, b);
                        fv(t, a * count + b) = sv(a, b);
                    }
            }
            for (int a = 0; a < count; ++a)
                for (int b = 0; b < count; ++b) {
                    add_outer(fq.col(a * count + b), first + a, first + b, 0);
                    add_outer(fv.col(a * count + b), first + a, first + b, n_);
                }
            continue;
        }
        Eigen::VectorXd z = Eigen::VectorXd::Zero(nt);
        if (z_[cc].size() > 0) fourier.to_time(z_[cc], z);
        Eigen::VectorXd fq(nt), fv(nt), fz(nt), gv(nt), gz(nt);
        for (int j = 0; j < nt; ++j) {
            const LocalLinearization l = laws_[cc]->linearize(q(j, 0), v(j, 0), z(j));
            fq(j) = l.f_q;
            fv(j) = l.f_v;
            fz(j) = l.f_z;
            gv(j) = l.g_v;
            gz(j) = l.g_z;
        }
        const auto col = static_cast<Eigen::Index>(first);
        add_outer(fv, col, col, n_);
        add_outer(fq, col, col, 0);  // the displacement's slope: the velocity rows, the displacement columns
        const int s = state_index_[cc];
        if (s < 0) continue;
        fourier.multiplication_matrix(fz, p);
        for (int i = 0; i < n_; ++i)
            if (mw_(i, col) != 0.0) h.block((n_ + i) * m, s * m, m, m) -= mw_(i, col) * p;
        fourier.multiplication_matrix(gv, p);
        for (int j = 0; j < n_; ++j)
            if (w_(j, col) != 0.0) h.block(s * m, (n_ + j) * m, m, m) += w_(j, col) * p;
        fourier.multiplication_matrix(gz, p);
        h.block(s * m, s * m, m, m) += p;
    }
    // - d/dt on every signal.
    const Eigen::MatrixXd d = omega_ * fourier.derivative();
    for (int i = 0; i < d_; ++i) h.block(i * m, i * m, m, m) -= d;
    return h;
}

Eigen::VectorXcd sorted_hill(const Variational& v, Fourier& fourier, int max_size) {
    if (v.size() * fourier.size() > max_size) return {};
    const Eigen::VectorXcd lambda = eigenvalues(v.hill(fourier));
    if (lambda.size() < v.size()) return {};
    std::vector<Eigen::Index> order(static_cast<std::size_t>(lambda.size()));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
        return std::abs(lambda(a).imag()) < std::abs(lambda(b).imag());
    });
    const double period = 2.0 * M_PI / v.omega();
    Eigen::VectorXcd mu(v.size());
    for (int k = 0; k < v.size(); ++k) mu(k) = std::exp(lambda(order[static_cast<std::size_t>(k)]) * period);
    return mu;
}

}  // namespace hbf::detail
