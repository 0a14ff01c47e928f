// hbfriction — the closed forms of the paper's friction absorber (analytic.hpp): stick and slip
// responses, limit and optimal friction coefficients, derived again from the equations of motion.
#include "hbf/analytic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hbf/absorber.hpp"
#include "hbf/error.hpp"

namespace hbf::analytic {

namespace {
constexpr double pi = 3.14159265358979323846;
constexpr double infinity = std::numeric_limits<double>::infinity();
const Complex i_unit(0.0, 1.0);

double sign(double x) { return (x > 0.0) - (x < 0.0); }

/// 1 - (1 + r) omega^2
double stuck_stiffness(const AbsorberParameters& p, double omega) {
    return 1.0 - (1.0 + p.mass_ratio) * omega * omega;
}

/// (1 - omega^2)(K2 - omega^2) - r K2 omega^2 for a (possibly complex) absorber stiffness K2.
Complex two_dof_determinant(double r, Complex k2, double omega) {
    const double w2 = omega * omega;
    return (1.0 - w2) * (k2 - w2) - r * k2 * w2;
}

/// Complex absorber stiffness wa^2 + wb^2 + 2 i xi wb omega of the pre-sliding contact.
Complex presliding_stiffness(const AbsorberParameters& p, double omega, FrictionLaw law) {
    if (law != FrictionLaw::dahl && law != FrictionLaw::lugre)
        throw InvalidInput("law = " + to_string(law) + " has no contact stiffness: allowed dahl, lugre");
    const double wb = p.contact_stiffness_ratio;
    const double xi = law == FrictionLaw::lugre ? p.contact_damping_ratio : 0.0;
    return Complex(p.tuning_ratio * p.tuning_ratio + wb * wb, 2.0 * xi * wb * omega);
}

std::optional<double> finite(double x) {
    if (std::isfinite(x)) return x;
    return std::nullopt;
}
}  // namespace

Response coulomb_stick(const AbsorberParameters& p, double omega) {
    const double s = stuck_stiffness(p, omega);
    const double y = s == 0.0 ? infinity : p.excitation / s;
    return {y, y};
}

double coulomb_limit_friction(const AbsorberParameters& p, double omega) {
    const double s = stuck_stiffness(p, omega);
    return s == 0.0 ? infinity : p.excitation * p.mass_ratio * omega * omega / std::abs(s);
}

std::optional<Response> coulomb_slip(const AbsorberParameters& p, double omega) {
    const double r = p.mass_ratio, fe = p.excitation, w2 = omega * omega;
    const double wa2 = p.tuning_ratio * p.tuning_ratio;
    const double s = stuck_stiffness(p, omega);
    const double delta = (1.0 - w2) * (wa2 - w2) - r * wa2 * w2;
    const double force = 4.0 * p.friction_coefficient / pi;  // first-harmonic friction amplitude
    const double p2 = std::pow(fe * r * w2, 2) - std::pow(force * s, 2);
    if (!(p2 > 0.0)) return std::nullopt;
    if (delta == 0.0) return Response{infinity, infinity};
    // Phase of D: e^{i phi} = -(P sign(Delta) - i (4 mu / pi) s) / (r fe omega^2), |e^{i phi}| = 1.
    const Complex phase = -Complex(std::sqrt(p2) * sign(delta), -force * s) / (r * fe * w2);
    // Y = Z^{-1} F - (i (4 mu / pi) e^{i phi}) Z^{-1} w, Z^{-1} w = (-r omega^2, -(1 - omega^2)) / (r Delta).
    const Complex friction = i_unit * force * phase;
    return Response{(fe * (wa2 - w2) + friction * w2) / delta,
                    (fe * wa2 + friction * (1.0 - w2) / r) / delta};
}

double equivalent_damping(const AbsorberParameters& p, double omega, const Response& slip) {
    return 4.0 * p.friction_coefficient / (pi * omega * std::abs(slip.y1 - slip.y2));
}

Response contact_stick(const AbsorberParameters& p, double omega, FrictionLaw law) {
    const Complex k2 = presliding_stiffness(p, omega, law);
    const Complex det = two_dof_determinant(p.mass_ratio, k2, omega);
    if (det == 0.0) return {infinity, infinity};
    return {p.excitation * (k2 - omega * omega) / det, p.excitation * k2 / det};
}

double contact_limit_friction(const AbsorberParameters& p, double omega, FrictionLaw law) {
    const Complex k2 = presliding_stiffness(p, omega, law);
    const double det = std::abs(two_dof_determinant(p.mass_ratio, k2, omega));
    const double contact = std::abs(k2 - p.tuning_ratio * p.tuning_ratio);  // |wb^2 + 2 i xi wb omega|
    return det == 0.0 ? infinity : p.excitation * p.mass_ratio * omega * omega * contact / det;
}

namespace {
/// The paper's closed forms are those of coulomb, dahl and lugre; any other law is refused rather
/// than answered with Coulomb's (a law added later falls here too).
void require_closed_form(FrictionLaw law) {
    if (law != FrictionLaw::coulomb && law != FrictionLaw::dahl && law != FrictionLaw::lugre)
        throw InvalidInput("law = " + to_string(law) + " has no closed form: allowed coulomb, dahl, lugre");
}
}  // namespace

Response stick(const AbsorberParameters& p, double omega, FrictionLaw law) {
    require_closed_form(law);
    return law == FrictionLaw::dahl || law == FrictionLaw::lugre ? contact_stick(p, omega, law)
                                                                 : coulomb_stick(p, omega);
}

double limit_friction(const AbsorberParameters& p, double omega, FrictionLaw law) {
    require_closed_form(law);
    return law == FrictionLaw::dahl || law == FrictionLaw::lugre ? contact_limit_friction(p, omega, law)
                                                                 : coulomb_limit_friction(p, omega);
}

std::vector<double> stuck_resonances(const AbsorberParameters& p, FrictionLaw law) {
    require_closed_form(law);
    const double r = p.mass_ratio;
    if (law != FrictionLaw::dahl && law != FrictionLaw::lugre) return {1.0 / std::sqrt(1.0 + r)};
    const double wb = p.contact_stiffness_ratio;
    const double k = p.tuning_ratio * p.tuning_ratio + wb * wb;
    const double b = 1.0 + (1.0 + r) * k;
    // b^2 - 4 K = (1 + (1 + r) K)^2 - 4 K > (1 - K)^2 >= 0 since r > 0; the smaller root from
    // the product of the roots (K) to avoid cancellation.
    const double root = std::sqrt(b * b - 4.0 * k);
    const double upper = 0.5 * (b + root);
    return {std::sqrt(k / upper), std::sqrt(upper)};
}

LimitFrictionMaximum limit_friction_maximum(const AbsorberParameters& p, FrictionLaw law, double wmin,
                                            double wmax, long long samples) {
    p.validate(law);
    std::vector<double> w = uniform_grid(wmin, wmax, samples);
    const bool undamped = law != FrictionLaw::lugre || p.contact_damping_ratio == 0.0;
    for (double resonance : stuck_resonances(p, law)) {
        if (resonance < wmin || resonance > wmax) continue;
        if (undamped) return {resonance, infinity, false};
        w.push_back(resonance);
    }
    std::sort(w.begin(), w.end());
    const auto f = [&](double omega) { return limit_friction(p, omega, law); };
    std::vector<double> value(w.size());
    for (std::size_t k = 0; k < w.size(); ++k) value[k] = f(w[k]);
    LimitFrictionMaximum best{w[0], value[0], true};
    const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
    for (std::size_t k = 0; k < w.size(); ++k) {
        if ((k > 0 && value[k - 1] > value[k]) || (k + 1 < w.size() && value[k + 1] > value[k])) continue;
        if (value[k] > best.value) best = {w[k], value[k], true};
        // Golden section on the neighbours' bracket (one peak there: it is a sampled maximum).
        double a = w[k > 0 ? k - 1 : k], b = w[k + 1 < w.size() ? k + 1 : k];
        double c = b - golden * (b - a), d = a + golden * (b - a);
        double fc = f(c), fd = f(d);
        while (b - a > 1e-13 * b) {
            if (fc >= fd) {
                b = d; d = c; fd = fc; c = b - golden * (b - a); fc = f(c);
            } else {
                a = c; c = d; fc = fd; d = a + golden * (b - a); fd = f(d);
            }
        }
        if (fc > best.value) best = {c, fc, true};
        if (fd > best.value) best = {d, fd, true};
    }
    if (!std::isfinite(best.value)) best.bounded = false;
    return best;
}

double den_hartog_tuning(double mass_ratio) {
    require_positive(mass_ratio, "r", "mass ratio m2/m1");
    return 1.0 / (1.0 + mass_ratio);
}

double den_hartog_damping_ratio(double mass_ratio) {
    require_positive(mass_ratio, "r", "mass ratio m2/m1");
    return std::sqrt(3.0 * mass_ratio / (8.0 * (1.0 + mass_ratio)));
}

double den_hartog_friction(const AbsorberParameters& p, double omega) {
    const double r = p.mass_ratio, w2 = omega * omega;
    const double wa = den_hartog_tuning(r);
    const double c = 2.0 * r * wa * den_hartog_damping_ratio(r);  // optimal viscous damper
    const double delta = (1.0 - w2) * (wa * wa - w2) - r * wa * wa * w2;
    const double s = stuck_stiffness(p, omega);
    const double d = p.excitation * w2 / std::hypot(delta, omega * c * s / r);  // |Y1 - Y2|
    return pi / 4.0 * omega * c * d;
}

namespace {
/// The upward half period of den_hartog: u(s) for s in [0, theta] from the minimum.
struct DenHartogHalf {
    double rho, eta, d, phi, b;
    double u(double s) const { return -rho + rho * std::cos(s) + b * std::sin(s) + d * std::cos(eta * s + phi); }
    double du(double s) const { return -rho * std::sin(s) + b * std::cos(s) - eta * d * std::sin(eta * s + phi); }
};

/// Solves the half period (no validity checks beyond existence); false if none exists.
bool den_hartog_half(double eta, double rho, DenHartogHalf& half, double& amplitude, std::string& reason) {
    const double theta = pi / eta;
    const double d = 1.0 / (1.0 - eta * eta);
    const double u_factor = std::tan(theta / 2.0) / eta;
    if (!std::isfinite(d) || !std::isfinite(u_factor) || std::abs(std::cos(theta / 2.0)) < 1e-12) {
        reason = "eta = " + format_number(eta) + " is a resonance of the closed form (eta = 1 or 1/(2k+1))";
        return false;
    }
    const double sin_phi = rho * u_factor / d;
    if (!(std::abs(sin_phi) < 1.0)) {
        reason = "(rho U)^2 >= D^2: no continuous (non-stopping) solution exists (friction too large)";
        return false;
    }
    // A = -D cos phi > 0 picks the sign of cos phi.
    const double cos_phi = -sign(d) * std::sqrt(1.0 - sin_phi * sin_phi);
    half = DenHartogHalf{rho, eta, d, std::atan2(sin_phi, cos_phi), rho * std::tan(theta / 2.0)};
    amplitude = -d * cos_phi;
    return true;
}
}  // namespace

DenHartogCheck den_hartog_check(double eta, double rho) {
    require_positive(eta, "eta", "frequency ratio Omega / omega_n");
    require_finite(eta, "eta", "frequency ratio Omega / omega_n");
    require_positive(rho, "rho", "friction ratio F_c / F0");
    require_finite(rho, "rho", "friction ratio F_c / F0");
    DenHartogCheck check;
    DenHartogHalf half{};
    double amplitude = 0;
    if (!den_hartog_half(eta, rho, half, amplitude, check.reason)) return check;
    const double start_acceleration = -rho - eta * eta * half.d * std::cos(half.phi);
    if (!(start_acceleration > 0.0)) {
        check.reason = "the motion sticks at the turning points: spring and forcing (" +
                       format_number(std::cos(half.phi) + amplitude) + ") do not exceed the friction " +
                       format_number(rho);
        return check;
    }
    const double theta = pi / eta;
    constexpr int points = 4096;
    for (int j = 1; j < points; ++j) {
        const double s = theta * j / points;
        if (!(half.du(s) > 0.0)) {
            check.reason = "the velocity vanishes inside the half period (at eta tau = " +
                           format_number(eta * s) + " after the stop): more than two stops per cycle";
            return check;
        }
    }
    check.valid = true;
    return check;
}

DenHartogResponse den_hartog(double eta, double rho) {
    const DenHartogCheck check = den_hartog_check(eta, rho);
    if (!check.valid)
        throw InvalidInput("Den Hartog's non-sticking solution does not apply at eta = " + format_number(eta) +
                           ", rho = " + format_number(rho) + ": " + check.reason);
    DenHartogHalf half{};
    double amplitude = 0;
    std::string reason;
    den_hartog_half(eta, rho, half, amplitude, reason);
    DenHartogResponse r;
    r.frequency_ratio = eta;
    r.friction_ratio = rho;
    r.amplitude = amplitude;
    r.phase = std::fmod(half.phi + pi + 2.0 * pi, 2.0 * pi);
    return r;
}

namespace {
/// s in [0, T) measured from the minimum of u and the sign of the half period.
void den_hartog_position(const DenHartogResponse& r, double tau, double& s, double& sign_half) {
    const double period = 2.0 * pi / r.frequency_ratio, half = period / 2.0;
    // the minimum is at eta tau = phi = psi - pi
    double t = std::fmod(tau - (r.phase - pi) / r.frequency_ratio, period);
    if (t < 0.0) t += period;
    sign_half = 1.0;
    if (t >= half) {
        t -= half;
        sign_half = -1.0;
    }
    s = t;
}
}  // namespace

namespace {
/// The half-period solution and where tau falls on it: u(tau) = sign_half * half.u(s).
DenHartogHalf den_hartog_at(const DenHartogResponse& r, double tau, double& s, double& sign_half) {
    DenHartogHalf half{};
    double amplitude_check = 0;
    std::string reason;
    den_hartog_half(r.frequency_ratio, r.friction_ratio, half, amplitude_check, reason);
    den_hartog_position(r, tau, s, sign_half);
    return half;
}
}  // namespace

double DenHartogResponse::displacement(double tau) const {
    double s = 0, sign_half = 1;
    const DenHartogHalf half = den_hartog_at(*this, tau, s, sign_half);
    return sign_half * half.u(s);
}

double DenHartogResponse::velocity(double tau) const {
    double s = 0, sign_half = 1;
    const DenHartogHalf half = den_hartog_at(*this, tau, s, sign_half);
    return sign_half * half.du(s);
}

std::vector<double> uniform_grid(double wmin, double wmax, long long points) {
    require_positive(wmin, "wmin", "lowest frequency");
    require_positive(wmax, "wmax", "highest frequency");
    if (!(wmax > wmin))
        throw InvalidInput("wmax (highest frequency) = " + format_number(wmax) +
                           " is out of range: allowed wmax > wmin = " + format_number(wmin));
    if (points < 2 || points > max_grid_points)
        throw InvalidInput("points (number of frequencies) = " + std::to_string(points) +
                           " is out of range: allowed 2.." + std::to_string(max_grid_points));
    std::vector<double> grid(static_cast<std::size_t>(points));
    const double step = (wmax - wmin) / static_cast<double>(points - 1);
    for (long long k = 0; k < points; ++k) grid[static_cast<std::size_t>(k)] = wmin + step * static_cast<double>(k);
    grid.back() = wmax;
    return grid;
}

std::vector<Row> table(const AbsorberParameters& p, FrictionLaw law, const std::vector<double>& omegas) {
    p.validate(law);
    std::vector<Row> rows;
    rows.reserve(omegas.size());
    for (double omega : omegas) {
        require_positive(omega, "w", "excitation frequency");
        Row row;
        row.omega = omega;
        const Response st = stick(p, omega, law);
        row.y1_stick = finite(std::abs(st.y1));
        row.y2_stick = finite(std::abs(st.y2));
        if (const auto sl = coulomb_slip(p, omega)) {
            row.y1_slip = finite(std::abs(sl->y1));
            row.y2_slip = finite(std::abs(sl->y2));
        }
        row.mu_limit = finite(limit_friction(p, omega, law));
        row.mu_opt_den_hartog = finite(den_hartog_friction(p, omega));
        rows.push_back(row);
    }
    return rows;
}

}  // namespace hbf::analytic
