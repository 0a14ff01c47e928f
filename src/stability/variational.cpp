// hbfriction — the variational equation of an HB solution and Hill's matrix (variational.hpp).
#include "stability/variational.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>

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
    }
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

void Variational::slopes(double theta, std::vector<LocalLinearization>& out) const {
    out.resize(q_.size());
    for (std::size_t c = 0; c < q_.size(); ++c) {
        double q, dq, z = 0.0, dz;
        at_phase(q_[c], theta, q, dq);
        if (z_[c].size() > 0) at_phase(z_[c], theta, z, dz);
        out[c] = laws_[c]->linearize(q, omega_ * dq, z);
    }
}

void Variational::matrix(double theta, Eigen::MatrixXd& a) const {
    slopes(theta, scratch_);
    a = base_;
    for (std::size_t c = 0; c < q_.size(); ++c) add_contact(static_cast<int>(c), scratch_[c], a);
}

void Variational::add_contact(int c, const LocalLinearization& l, Eigen::MatrixXd& a) const {
    const auto col = static_cast<Eigen::Index>(c);
    a.block(n_, n_, n_, n_).noalias() -= l.f_v * mw_.col(col) * w_.col(col).transpose();
    if (l.f_q != 0.0) a.block(n_, 0, n_, n_).noalias() -= l.f_q * mw_.col(col) * w_.col(col).transpose();
    const int s = state_index_[static_cast<std::size_t>(c)];
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
    std::vector<Eigen::VectorXd> fq(static_cast<std::size_t>(nc), Eigen::VectorXd(nt)),
        fv = fq, fz = fq, gv = fq, gz = fq;
    std::vector<bool> springs(static_cast<std::size_t>(nc), false);
    // q_c, v_c and z_c on the AFT grid by the FFT (Fourier::to_time), then the slopes pointwise.
    Eigen::VectorXd q(nt), v(nt), z(nt);
    for (int c = 0; c < nc; ++c) {
        const auto cc = static_cast<std::size_t>(c);
        fourier.to_time(q_[cc], q);
        fourier.to_time(omega_ * (fourier.derivative() * q_[cc]), v);
        if (z_[cc].size() > 0)
            fourier.to_time(z_[cc], z);
        else
            z.setZero();
        for (int j = 0; j < nt; ++j) {
            const LocalLinearization l = laws_[cc]->linearize(q(j), v(j), z(j));
            fq[cc](j) = l.f_q;
            springs[cc] = springs[cc] || l.f_q != 0.0;
            fv[cc](j) = l.f_v;
            fz[cc](j) = l.f_z;
            gv[cc](j) = l.g_v;
            gz[cc](j) = l.g_z;
        }
    }
    Eigen::MatrixXd p(m, m);
    for (int c = 0; c < nc; ++c) {
        const auto cc = static_cast<std::size_t>(c);
        const auto col = static_cast<Eigen::Index>(c);
        const Eigen::MatrixXd outer = -mw_.col(col) * w_.col(col).transpose();
        fourier.multiplication_matrix(fv[cc], p);
        for (int i = 0; i < n_; ++i)
            for (int j = 0; j < n_; ++j)
                if (outer(i, j) != 0.0) h.block((n_ + i) * m, (n_ + j) * m, m, m) += outer(i, j) * p;
        if (springs[cc]) {  // the displacement's slope: the velocity rows, the displacement columns
            fourier.multiplication_matrix(fq[cc], p);
            for (int i = 0; i < n_; ++i)
                for (int j = 0; j < n_; ++j)
                    if (outer(i, j) != 0.0) h.block((n_ + i) * m, j * m, m, m) += outer(i, j) * p;
        }
        const int s = state_index_[cc];
        if (s < 0) continue;
        fourier.multiplication_matrix(fz[cc], p);
        for (int i = 0; i < n_; ++i)
            if (mw_(i, col) != 0.0) h.block((n_ + i) * m, s * m, m, m) -= mw_(i, col) * p;
        fourier.multiplication_matrix(gv[cc], p);
        for (int j = 0; j < n_; ++j)
            if (w_(j, col) != 0.0) h.block(s * m, (n_ + j) * m, m, m) += w_(j, col) * p;
        fourier.multiplication_matrix(gz[cc], p);
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
