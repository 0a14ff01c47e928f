// hbfriction — internal to event_exact: polynomials in time. Within a Taylor step every signal
// of the flow is a polynomial in s = (t - t0) / h; their evaluation, the step's Taylor
// coefficients, the matrix exponential, the roots of the guards and Gauss-Legendre quadrature.
// The functions the flow calls every step are defined here, inline: out of line (in another
// translation unit than the engine) the exact polish of the default FRF took 8 % longer.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>
#include <utility>

namespace hbf::detail::exact {

constexpr double pi = 3.14159265358979323846;

/// The polynomial c(0) + c(1) s + c(2) s^2 + ... at s (Horner), its derivative, and the vector
/// polynomial whose coefficients are the columns of u.
inline double horner(const Eigen::Ref<const Eigen::RowVectorXd>& c, double s) {
    double p = 0.0;
    for (Eigen::Index k = c.size() - 1; k >= 0; --k) p = p * s + c(k);
    return p;
}
inline double horner_derivative(const Eigen::Ref<const Eigen::RowVectorXd>& c, double s) {
    double p = 0.0;
    for (Eigen::Index k = c.size() - 1; k >= 1; --k) p = p * s + static_cast<double>(k) * c(k);
    return p;
}
inline Eigen::VectorXd evaluate(const Eigen::Ref<const Eigen::MatrixXd>& u, double s) {
    Eigen::VectorXd z = u.col(u.cols() - 1);
    for (Eigen::Index k = u.cols() - 2; k >= 0; --k) {
        z *= s;
        z += u.col(k);
    }
    return z;
}

/// Diagonal d with d^-1 a d balanced (rows and columns of similar size, powers of 2; the
/// Parlett-Reinsch iteration of LAPACK's gebal without permutations). A mechanical a has rows
/// of size 1 (y' = v) and K / M (v' = ...): balanced, its eigenvectors are accurate relative
/// to its largest eigenvalue instead of its largest stiffness over mass.
Eigen::VectorXd balance(Eigen::MatrixXd& a);

/// The eigenvalues of a (a period map's derivative: Floquet multipliers), balanced first. The
/// similarity by powers of 2 changes no eigenvalue, but the raw entries of a mechanical period
/// map spread over many decades (dy'/dy ~ w^2 T against dy/dy' ~ T, metres against radians),
/// and unbalanced the eigensolver's error scales with the largest of them: 1e-7 on the
/// multipliers of a 92-coordinate structure where balanced it is 1e-11.
Eigen::VectorXcd balanced_eigenvalues(Eigen::MatrixXd a);

/// exp(a d) by scaling and squaring of its Taylor series (to rounding), on a balanced a.
Eigen::MatrixXd taylor_exp(const Eigen::MatrixXd& a, double d);

/// Taylor coefficients of the flow over one step: u_k = (a h)^k z / k!, until they vanish:
/// two consecutive terms below 1e-16 and 1e-18 of each component's largest term so far (its
/// own scale: components of very different sizes, e.g. displacements and velocities in any
/// units, each converge to rounding). `buffer` keeps its capacity between steps; returns the
/// number of columns used.
inline Eigen::Index step_polynomial(const Eigen::MatrixXd& a, const Eigen::VectorXd& z, double h, Eigen::MatrixXd& buffer) {
    constexpr int max_terms = 80;
    if (buffer.rows() != z.size() || buffer.cols() != max_terms) buffer.resize(z.size(), max_terms);
    buffer.col(0) = z;
    Eigen::ArrayXd size = z.cwiseAbs().array();
    Eigen::Index used = 1;
    bool previous_small = false;
    for (int k = 1; k < max_terms; ++k) {
        buffer.col(k).noalias() = a * buffer.col(k - 1);
        buffer.col(k) *= h / static_cast<double>(k);
        used = k + 1;
        const Eigen::ArrayXd term = buffer.col(k).cwiseAbs().array();
        size = size.max(term);
        const bool small = (term <= 1e-18 * size).all();
        if (k >= 4 && small && previous_small) break;
        previous_small = (term <= 1e-16 * size).all();
    }
    return used;
}

/// The root of f in [lo, hi] where it changes sign (f(lo), f(hi) of opposite signs or zero),
/// by Newton on df safeguarded with bisection, to rounding.
template <class F, class D>
double refine_root(const F& f, const D& df, double lo, double hi) {
    double p_lo = f(lo);
    if (p_lo == 0.0) return lo;
    double x = 0.5 * (lo + hi);
    for (int it = 0; it < 200; ++it) {
        const double px = f(x);
        if (px == 0.0) return x;
        if ((px > 0.0) == (p_lo > 0.0)) {
            lo = x;
            p_lo = px;
        } else {
            hi = x;
        }
        if (hi - lo <= 2 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(hi))) break;
        const double dp = df(x);
        double next = dp != 0.0 ? x - px / dp : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const bool tiny = std::abs(next - x) <= 2 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(x));
        x = next;
        if (tiny) break;
    }
    return std::min(std::max(x, lo), hi);
}

/// The root of the polynomial c in [lo, hi] where it changes sign (p(lo), p(hi) of opposite
/// signs or zero), by Newton safeguarded with bisection, to rounding.
inline double refine_root(const Eigen::RowVectorXd& c, double lo, double hi) {
    return refine_root([&c](double x) { return horner(c, x); }, [&c](double x) { return horner_derivative(c, x); }, lo,
                       hi);
}

/// First root of the polynomial c on (0, s_end]: the first of 16 samples where it is below
/// -eta, or the first local minimum below -eta between two samples (a dip both samples miss:
/// a short phase near grazing), refined in the bracket before it. Returns -1 if none.
inline double first_root(const Eigen::RowVectorXd& c, double s_end, double eta) {
    constexpr int samples = 16;
    Eigen::RowVectorXd d(std::max<Eigen::Index>(1, c.size() - 1));
    d.setZero();
    for (Eigen::Index k = 1; k < c.size(); ++k) d(k - 1) = static_cast<double>(k) * c(k);
    double lo = 0.0, p_lo = c(0), d_lo = d(0);
    for (int j = 1; j <= samples; ++j) {
        const double s = s_end * j / samples;
        const double p = horner(c, s), dp = horner(d, s);
        if (p < -eta) {
            if (p_lo > 0.0) return refine_root(c, lo, s);
            if (j > 1) return lo;
            // Zero at the start (a slip or a stick that begins at the edge of its limit) and
            // negative at the first sample: a phase shorter than one sample, if the guard is
            // positive in between. Its end is the root after the first positive fine sample.
            constexpr int fine = 64;
            for (int k = 1; k < fine; ++k) {
                const double x = s * k / fine;
                if (horner(c, x) > 0.0) return refine_root(c, x, s);
            }
            return lo;
        }
        if (d_lo < 0.0 && dp > 0.0 && p_lo > 0.0) {  // a minimum between the samples
            const double bottom = refine_root(d, lo, s);
            if (horner(c, bottom) < -eta) return refine_root(c, lo, bottom);
        }
        lo = s;
        p_lo = p;
        d_lo = dp;
    }
    return -1.0;
}

/// A scalar signal of one step: a polynomial in s plus fast exponentials,
/// x(s) = sum_k poly(k) s^k + Re sum_j amp(j) exp(rate(j) s). The exponentials are the fast
/// modes of the pattern (engine.hpp): closed form, whatever their rate; none on most steps.
struct Signal {
    Eigen::RowVectorXd poly;
    Eigen::RowVectorXcd amp, rate;

    bool fast() const { return amp.size() > 0; }
    double value(double s) const {
        double p = horner(poly, s);
        for (Eigen::Index j = 0; j < amp.size(); ++j) p += (amp(j) * std::exp(rate(j) * s)).real();
        return p;
    }
    double slope(double s) const {
        double p = horner_derivative(poly, s);
        for (Eigen::Index j = 0; j < amp.size(); ++j) p += (amp(j) * rate(j) * std::exp(rate(j) * s)).real();
        return p;
    }
    double curvature(double s) const {
        double p = 0.0;
        for (Eigen::Index k = poly.size() - 1; k >= 2; --k) p = p * s + static_cast<double>(k * (k - 1)) * poly(k);
        for (Eigen::Index j = 0; j < amp.size(); ++j) p += (amp(j) * rate(j) * rate(j) * std::exp(rate(j) * s)).real();
        return p;
    }
    /// Value and slope at samples s_0 = 0 < s_1 < ... < s_end, by visit(s, value, slope),
    /// until visit returns false. The spacing resolves every exponential while its size exceeds
    /// `floor` (half a unit of its phase and decay: a decaying one only until it has fallen to
    /// the floor), at most s_end / 16; uniform between those instants, where the exponentials
    /// advance by one multiplication a sample.
    template <class Visit>
    void sample(double s_end, double floor, Visit&& visit) const {
        const double coarse = s_end / 16;
        const Eigen::Index n = amp.size();
        std::vector<double> until(static_cast<std::size_t>(n));
        for (Eigen::Index j = 0; j < n; ++j) {
            const double size = std::abs(amp(j)), decay = -rate(j).real();
            until[static_cast<std::size_t>(j)] = size <= floor ? 0.0
                                                 : decay > 0.0 ? std::log(size / floor) / decay
                                                               : std::numeric_limits<double>::infinity();
        }
        Eigen::ArrayXcd term = amp.transpose().array();
        double s = 0.0;
        auto emit = [&]() {
            double value = horner(poly, s), slope = horner_derivative(poly, s);
            for (Eigen::Index j = 0; j < n; ++j) {
                value += term(j).real();
                slope += (term(j) * rate(j)).real();
            }
            return visit(s, value, slope);
        };
        if (!emit()) return;
        while (s < s_end) {
            // The segment up to the next instant a resolved exponential falls to the floor.
            double fastest = 0.0, end = s_end;
            for (Eigen::Index j = 0; j < n; ++j)
                if (until[static_cast<std::size_t>(j)] > s) {
                    fastest = std::max(fastest, std::abs(rate(j)));
                    end = std::min(end, std::max(until[static_cast<std::size_t>(j)], s + coarse));
                }
            const double spacing = fastest > 0.0 ? std::min(coarse, 0.5 / fastest) : coarse;
            const long count = std::max(1L, static_cast<long>(std::ceil((end - s) / spacing - 1e-9)));
            const double delta = (end - s) / static_cast<double>(count);
            const Eigen::ArrayXcd factor = (rate.transpose().array() * delta).exp();
            const double start = s;
            for (long k = 1; k <= count; ++k) {
                term *= factor;
                s = k == count ? end : start + static_cast<double>(k) * delta;
                if (!emit()) return;
            }
        }
    }
};

/// The extremum of a signal between lo and hi where its slope changes sign (Newton on the
/// slope, safeguarded by bisection).
inline double signal_extremum(const Signal& g, double lo, double hi) {
    return refine_root([&g](double x) { return g.slope(x); }, [&g](double x) { return g.curvature(x); }, lo, hi);
}

/// first_root for a signal with fast exponentials: samples at least 16 a step and closer while
/// an exponential above eta requires (Signal::sample); a sign change or a dip below -eta
/// between samples is refined as in the polynomial version. Returns -1 if none.
inline double first_root(const Signal& g, double s_end, double eta) {
    if (!g.fast()) return first_root(g.poly, s_end, eta);
    // g >= poly - B with B the exponentials' largest size on the step: no root where the
    // polynomial version finds none for poly - B (the common case: a guard far from zero).
    double bound = 0.0;
    for (Eigen::Index j = 0; j < g.amp.size(); ++j)
        bound += (std::abs(g.amp(j).real()) + std::abs(g.amp(j).imag())) * std::max(1.0, std::exp(g.rate(j).real() * s_end));
    Eigen::RowVectorXd lowered = g.poly;
    lowered(0) -= bound;
    if (lowered(0) > 0.0 && first_root(lowered, s_end, 0.0) < 0.0) return -1.0;
    const auto f = [&g](double x) { return g.value(x); };
    const auto df = [&g](double x) { return g.slope(x); };
    double root = -1.0, lo = 0.0, p_lo = 0.0, d_lo = 0.0;
    g.sample(s_end, eta, [&](double s, double p, double dp) {
        if (s == 0.0) {
            p_lo = p;
            d_lo = dp;
            return true;
        }
        if (p < -eta) {
            root = lo;
            if (p_lo > 0.0) {
                root = refine_root(f, df, lo, s);
            } else if (lo == 0.0) {  // zero at the start: a phase shorter than one sample?
                constexpr int fine = 64;
                for (int k = 1; k < fine; ++k) {
                    const double x = s * k / fine;
                    if (g.value(x) > 0.0) {
                        root = refine_root(f, df, x, s);
                        break;
                    }
                }
            }
            return false;
        }
        if (d_lo < 0.0 && dp > 0.0 && p_lo > 0.0) {  // a minimum between the samples
            const double bottom = signal_extremum(g, lo, s);
            if (g.value(bottom) < -eta) {
                root = refine_root(f, df, lo, bottom);
                return false;
            }
        }
        lo = s;
        p_lo = p;
        d_lo = dp;
        return true;
    });
    return root;
}

/// E(mu, L) = int_0^L exp(mu t) dt = (exp(mu L) - 1) / mu, accurate also for small mu L.
inline std::complex<double> exp_integral(std::complex<double> mu, double length) {
    const std::complex<double> x = mu * length;
    if (std::abs(x) < 1e-3) return length * (1.0 + x / 2.0 + x * x / 6.0 + x * x * x / 24.0 + x * x * x * x / 120.0);
    return (std::exp(x) - 1.0) / mu;
}

/// Gauss-Legendre nodes and weights on [0, 1] (10 points: exact for degree 19).
const std::array<std::pair<double, double>, 10>& gauss_legendre();

}  // namespace hbf::detail::exact
