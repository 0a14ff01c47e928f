// hbfriction — the harmonic layout and the AFT transforms (fourier.hpp): FFTW plans made once
// per layout, and the synthesis, analysis and derivative matrices.
#include "hbf/fourier.hpp"

#include <fftw3.h>

#include <cmath>
#include <mutex>
#include <string>

#include "hbf/error.hpp"

namespace hbf {

namespace {
constexpr double two_pi = 6.28318530717958647692;
}

int Fourier::default_time_samples(int harmonics) {
    const int minimum = std::max(64, 8 * (2 * harmonics + 1));
    int n = 1;
    while (n < minimum) n *= 2;
    return n;
}

namespace {
std::mutex& planner_mutex() {
    static std::mutex m;
    return m;
}
}  // namespace

void Fourier::check(int harmonics, int time_samples) {
    if (harmonics < 0 || harmonics > 10000)
        throw InvalidInput("harmonics = " + std::to_string(harmonics) + " is out of range: allowed 0..10000");
    if (time_samples <= 2 * harmonics || time_samples > (1 << 24))
        throw InvalidInput("time_samples = " + std::to_string(time_samples) + " is out of range: allowed " +
                           std::to_string(2 * harmonics + 1) + ".." + std::to_string(1 << 24) +
                           " (more than 2 harmonics + 1)");
}

Fourier::Fourier(int harmonics, int time_samples) : harmonics_(harmonics), time_samples_(time_samples) {
    check(harmonics, time_samples);
    const int n = size(), nt = time_samples;
    synthesis_.resize(nt, n);
    analysis_.resize(n, nt);
    derivative_ = Eigen::MatrixXd::Zero(n, n);
    for (int j = 0; j < nt; ++j) {
        synthesis_(j, 0) = 1.0;
        analysis_(0, j) = 1.0 / nt;
        for (int k = 1; k <= harmonics; ++k) {
            const double angle = two_pi * static_cast<double>((static_cast<long long>(k) * j) % nt) / nt;
            synthesis_(j, 2 * k - 1) = std::cos(angle);
            synthesis_(j, 2 * k) = std::sin(angle);
            analysis_(2 * k - 1, j) = 2.0 * std::cos(angle) / nt;
            analysis_(2 * k, j) = 2.0 * std::sin(angle) / nt;
        }
    }
    for (int k = 1; k <= harmonics; ++k) {
        derivative_(2 * k - 1, 2 * k) = k;   // d/dtheta (s_k sin) = k s_k cos
        derivative_(2 * k, 2 * k - 1) = -k;  // d/dtheta (c_k cos) = -k c_k sin
    }
    // FFTW's planner is not thread-safe (only fftw_execute is): plans are made and destroyed
    // under one lock, so that design studies may build HarmonicBalance objects on threads.
    const std::lock_guard<std::mutex> lock(planner_mutex());
    real_buffer_ = fftw_alloc_real(static_cast<std::size_t>(nt));
    auto* spectrum = fftw_alloc_complex(static_cast<std::size_t>(nt / 2 + 1));
    complex_buffer_ = spectrum;
    forward_plan_ = fftw_plan_dft_r2c_1d(nt, real_buffer_, spectrum, FFTW_ESTIMATE);
    backward_plan_ = fftw_plan_dft_c2r_1d(nt, spectrum, real_buffer_, FFTW_ESTIMATE | FFTW_DESTROY_INPUT);
}

Fourier::~Fourier() {
    const std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_destroy_plan(static_cast<fftw_plan>(forward_plan_));
    fftw_destroy_plan(static_cast<fftw_plan>(backward_plan_));
    fftw_free(real_buffer_);
    fftw_free(complex_buffer_);
}

void Fourier::to_time(const Eigen::Ref<const Eigen::VectorXd>& c, Eigen::Ref<Eigen::VectorXd> samples) {
    auto* spectrum = static_cast<fftw_complex*>(complex_buffer_);
    const int nt = time_samples_;
    // x_j = sum_k Y_k e^{+2 pi i k j / N}: Y_0 = c0, Y_k = (c_k - i s_k) / 2 (Hermitian half).
    for (int k = 0; k <= nt / 2; ++k) spectrum[k][0] = spectrum[k][1] = 0.0;
    spectrum[0][0] = c(0);
    for (int k = 1; k <= harmonics_; ++k) {
        spectrum[k][0] = 0.5 * c(2 * k - 1);
        spectrum[k][1] = -0.5 * c(2 * k);
    }
    fftw_execute(static_cast<fftw_plan>(backward_plan_));
    samples = Eigen::Map<const Eigen::VectorXd>(real_buffer_, nt);
}

void Fourier::to_coefficients(const Eigen::Ref<const Eigen::VectorXd>& samples, Eigen::Ref<Eigen::VectorXd> c) {
    const int nt = time_samples_;
    Eigen::Map<Eigen::VectorXd>(real_buffer_, nt) = samples;
    fftw_execute(static_cast<fftw_plan>(forward_plan_));
    const auto* spectrum = static_cast<const fftw_complex*>(complex_buffer_);
    c(0) = spectrum[0][0] / nt;
    for (int k = 1; k <= harmonics_; ++k) {
        c(2 * k - 1) = 2.0 * spectrum[k][0] / nt;
        c(2 * k) = -2.0 * spectrum[k][1] / nt;
    }
}

void Fourier::multiplication_matrix(const Eigen::Ref<const Eigen::VectorXd>& samples,
                                    Eigen::Ref<Eigen::MatrixXd> out) {
    const int nt = time_samples_, h = harmonics_;
    Eigen::Map<Eigen::VectorXd>(real_buffer_, nt) = samples;
    fftw_execute(static_cast<fftw_plan>(forward_plan_));
    const auto* spectrum = static_cast<const fftw_complex*>(complex_buffer_);
    // FFTW: X_m = sum_j d_j e^{-2 pi i m j / N}, so a_m = Re X_m / N, b_m = -Im X_m / N;
    // beyond N/2 by the Hermitian symmetry X_m = conj(X_{N-m}).
    Eigen::VectorXd a(2 * h + 1), b(2 * h + 1);
    for (int m = 0; m <= 2 * h; ++m) {
        const int mm = m <= nt / 2 ? m : nt - m;
        const double sign = m <= nt / 2 ? 1.0 : -1.0;
        a(m) = spectrum[mm][0] / nt;
        b(m) = -sign * spectrum[mm][1] / nt;
    }
    auto B = [&](int m) { return m >= 0 ? b(m) : -b(-m); };
    out(0, 0) = a(0);
    for (int k = 1; k <= h; ++k) {
        out(0, 2 * k - 1) = a(k);
        out(0, 2 * k) = b(k);
        out(2 * k - 1, 0) = 2.0 * a(k);
        out(2 * k, 0) = 2.0 * b(k);
    }
    for (int j = 1; j <= h; ++j) {
        for (int k = 1; k <= h; ++k) {
            const double a_minus = a(std::abs(j - k)), a_plus = a(j + k);
            out(2 * j - 1, 2 * k - 1) = a_minus + a_plus;
            out(2 * j - 1, 2 * k) = B(j + k) - B(j - k);
            out(2 * j, 2 * k - 1) = B(j + k) + B(j - k);
            out(2 * j, 2 * k) = a_minus - a_plus;
        }
    }
}

Eigen::MatrixXd Fourier::times_derivative(const Eigen::Ref<const Eigen::MatrixXd>& a) const {
    // D1(2k-1, 2k) = k and D1(2k, 2k-1) = -k: column c_k of A D1 is -k A(:, s_k), column s_k
    // is k A(:, c_k), column c0 is zero.
    Eigen::MatrixXd out(a.rows(), a.cols());
    out.col(0).setZero();
    for (int k = 1; k <= harmonics_; ++k) {
        out.col(2 * k - 1) = -k * a.col(2 * k);
        out.col(2 * k) = k * a.col(2 * k - 1);
    }
    return out;
}

}  // namespace hbf
