// hbfriction — harmonic layout and the alternating frequency/time (AFT) transforms.
//
// A periodic signal of phase theta = omega tau is represented by the real coefficients
//     x(theta) = c0 + sum_{k=1..H} (c_k cos k theta + s_k sin k theta),
// stored as [c0, c1, s1, c2, s2, ..., cH, sH] (size 2H + 1), and by N_t time samples
// x_j = x(2 pi j / N_t), j = 0..N_t-1. The derivative with respect to tau multiplies the
// harmonic k pair (c_k, s_k) by k omega [[0, 1], [-1, 0]].
#pragma once

#include <Eigen/Dense>

namespace hbf {

class Fourier {
public:
    /// H >= 0 harmonics and N_t > 2H time samples; throws InvalidInput otherwise.
    Fourier(int harmonics, int time_samples);
    /// The constructor's check alone: throws InvalidInput unless 0 <= H <= 10000 and
    /// 2H < N_t <= 2^24.
    static void check(int harmonics, int time_samples);
    ~Fourier();
    Fourier(const Fourier&) = delete;
    Fourier& operator=(const Fourier&) = delete;

    int harmonics() const { return harmonics_; }
    int time_samples() const { return time_samples_; }
    /// Number of real coefficients per signal, 2H + 1.
    int size() const { return 2 * harmonics_ + 1; }

    /// The default N_t for H harmonics: the smallest power of two >= max(64, 8 (2H + 1)).
    /// Friction forces are not band-limited; with N_t >= 8 (2H + 1) the harmonics that alias
    /// onto 0..H come from order > 7H, where the spectrum of a kink (decaying as 1/k^2) is
    /// at most ~2% of that of harmonic H.
    static int default_time_samples(int harmonics);

    /// Coefficients -> time samples (FFTW, plan made once in the constructor).
    void to_time(const Eigen::Ref<const Eigen::VectorXd>& coefficients, Eigen::Ref<Eigen::VectorXd> samples);
    /// Time samples -> coefficients of harmonics 0..H (FFTW); the higher ones are dropped.
    void to_coefficients(const Eigen::Ref<const Eigen::VectorXd>& samples, Eigen::Ref<Eigen::VectorXd> coefficients);

    /// P diag(d) E ((2H+1) x (2H+1)) for samples d: the coefficient-space matrix of the
    /// multiplication of a signal by d(theta), the building block of every Jacobian through the
    /// AFT. Computed from one FFT of d in O(N_t log N_t + H^2) (the product itself costs
    /// O(N_t H^2)); equal to it to rounding, since both are the same discrete sums:
    ///   (c_j, c_k): a_{j-k} + a_{j+k}   (c_j, s_k): b_{j+k} - b_{j-k}
    ///   (s_j, c_k): b_{j+k} + b_{j-k}   (s_j, s_k): a_{j-k} - a_{j+k}
    /// with a_m + i b_m = (1/N_t) sum_j d_j e^{+2 pi i m j / N_t} (a even, b odd in m); the
    /// row of c0 is (a_0, a_k, b_k), the column of c0 is (a_0; 2 a_j; 2 b_j).
    void multiplication_matrix(const Eigen::Ref<const Eigen::VectorXd>& samples, Eigen::Ref<Eigen::MatrixXd> out);
    /// A * D1 for any A with 2H+1 columns, using the 2x2 block structure of D1 (O(rows H)).
    Eigen::MatrixXd times_derivative(const Eigen::Ref<const Eigen::MatrixXd>& a) const;

    /// E (N_t x (2H+1)): samples = E * coefficients. Used for Jacobians through the AFT.
    const Eigen::MatrixXd& synthesis() const { return synthesis_; }
    /// P ((2H+1) x N_t): coefficients = P * samples (the discrete projection).
    const Eigen::MatrixXd& analysis() const { return analysis_; }
    /// D1 ((2H+1)^2): coefficients of d/dtheta; d/dtau is omega * D1.
    const Eigen::MatrixXd& derivative() const { return derivative_; }

private:
    int harmonics_;
    int time_samples_;
    Eigen::MatrixXd synthesis_, analysis_, derivative_;
    double* real_buffer_ = nullptr;
    void* complex_buffer_ = nullptr;  // fftw_complex[N_t / 2 + 1]
    void* forward_plan_ = nullptr;    // r2c
    void* backward_plan_ = nullptr;   // c2r
};

}  // namespace hbf
