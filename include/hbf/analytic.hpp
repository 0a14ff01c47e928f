// hbfriction — closed-form results for the paper's friction absorber, derived from the
// equations of motion (paper eq. 2, see model.hpp) and verified in tests/test_analytic.cpp.
//
// Notation: omega = excitation frequency (nondimensional), r, wa, mu, fe, wb, xi as in
// AbsorberParameters, s = 1 - (1 + r) omega^2 (the one-DOF "stuck" dynamic stiffness),
// Delta = (1 - omega^2)(wa^2 - omega^2) - r wa^2 omega^2 (undamped two-DOF determinant / r).
// Amplitudes are complex: y(tau) = Re(Y e^{i omega tau}); |Y| is the amplitude.
//
// Where these formulas differ from the printed paper it is noted next to each function.
#pragma once

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/model.hpp"

namespace hbf::analytic {

using Complex = std::complex<double>;

/// Complex amplitudes of the two masses.
struct Response {
    Complex y1;
    Complex y2;
};

// ---- Coulomb ------------------------------------------------------------------------

/// Full stick (paper eqs. 11-13): both masses move as one, (1 + r) y'' + y = fe cos(omega tau),
/// Y1 = Y2 = fe / s. Infinite at s = 0.
Response coulomb_stick(const AbsorberParameters& p, double omega);

/// Limit friction coefficient (paper eqs. 14-15): in full stick the contact must carry
/// f = r y2'' (second row of eq. 2 with y1 = y2), amplitude r omega^2 |Y|; the masses stick
/// iff mu >= mu_limit = fe r omega^2 / |s|.
/// Departs from eq. 15, which puts fe under the square root (it must multiply).
double coulomb_limit_friction(const AbsorberParameters& p, double omega);

/// Full slip, equivalent viscous damping (paper eqs. 6-10), solved self-consistently.
/// The energy per cycle of mu sign(q') over q = |D| cos(.) is 4 mu |D|; a viscous damper
/// c_e q' dissipates pi c_e omega |D|^2, hence c_e = 4 mu / (pi omega |D|), D = Y1 - Y2
/// (eq. 8 with the modulus of the complex difference). This is also the one-harmonic
/// describing function of the Coulomb force. With Z = K - omega^2 M and w = (1, -1),
/// Sherman-Morrison gives D = a / (1 + i omega c_e b), a = w^T Z^{-1} F = -fe omega^2 / Delta,
/// b = w^T Z^{-1} w = s / (r Delta); taking the modulus with omega c_e |D| = 4 mu / pi:
///     |D|^2 = a^2 - (4 mu b / pi)^2 = [ (fe r omega^2)^2 - (4 mu s / pi)^2 ] / (r Delta)^2.
/// A slipping solution exists iff fe r omega^2 > (4/pi) mu |s|, i.e. mu < (pi/4) mu_limit;
/// otherwise returns nullopt. Infinite at Delta = 0 (undamped absorber resonances).
/// Departs from eq. 10, whose denominator lacks a square and mixes up the damping terms.
std::optional<Response> coulomb_slip(const AbsorberParameters& p, double omega);

/// Equivalent viscous damping c_e = 4 mu / (pi omega |Y1 - Y2|) of a slip response (eq. 8).
double equivalent_damping(const AbsorberParameters& p, double omega, const Response& slip);

// ---- Dahl and LuGre in the stick (pre-sliding) regime ---------------------------------

/// For small relative motion z ~ q, so the contact is a spring r wb^2 and (LuGre) a damper
/// 2 xi r wb (paper eqs. 20-21). With the complex absorber stiffness
/// K2 = wa^2 + wb^2 + 2 i xi wb omega (xi = 0 for Dahl) the 2-DOF solve gives
///     Y1 = fe (K2 - omega^2) / Delta2,  Y2 = fe K2 / Delta2,
///     Delta2 = (1 - omega^2)(K2 - omega^2) - r K2 omega^2,
/// whose moduli are paper eqs. 22-23 multiplied by fe (the paper omits fe).
/// `law` must be dahl or lugre.
Response contact_stick(const AbsorberParameters& p, double omega, FrictionLaw law);

/// Limit friction coefficient of Dahl / LuGre (paper eqs. 24-27): the pre-sliding force
/// f = r wb^2 q + 2 xi r wb q' has amplitude r |wb^2 + 2 i xi wb omega| |D| with
/// D = Y1 - Y2 = -fe omega^2 / Delta2; it must stay below mu:
///     mu_limit = fe r omega^2 sqrt(wb^4 + 4 xi^2 wb^2 omega^2) / |Delta2|.
/// Paper eqs. 25 and 27 lack the factor fe (eq. 24 also drops r from the force).
/// Tends to coulomb_limit_friction as wb -> infinity.
double contact_limit_friction(const AbsorberParameters& p, double omega, FrictionLaw law);

// ---- dispatch by law -----------------------------------------------------------------

/// Stick response of the given law (coulomb_stick or contact_stick).
Response stick(const AbsorberParameters& p, double omega, FrictionLaw law);
/// Limit friction coefficient of the given law; also the minimum-displacement
/// (Ricciardelli-Vickery) coefficient of paper section 4.2 (eq. 33 = eq. 27 with fe).
double limit_friction(const AbsorberParameters& p, double omega, FrictionLaw law);

/// Undamped resonance frequencies of the stuck system, in increasing order: the
/// frequencies at which the stick response and mu_limit of `law` are infinite when the
/// contact has no damping. Coulomb (rigid stick): the one-DOF w = 1/sqrt(1 + r). Dahl and
/// LuGre (contact spring r wb^2 in parallel with the absorber spring): the roots of the
/// undamped two-DOF determinant with K = wa^2 + wb^2,
///     w^4 - (1 + (1 + r) K) w^2 + K = 0,
///     w^2 = [ (1 + (1 + r) K) -+ sqrt((1 + (1 + r) K)^2 - 4 K) ] / 2.
/// For LuGre with xi > 0 they are where its (finite) mu_limit peaks sharply: |Delta2|^2 =
/// Delta^2 + (2 xi wb w s)^2 cannot vanish, since Delta = -w^2 (1 - w^2) != 0 where s = 0.
std::vector<double> stuck_resonances(const AbsorberParameters& p, FrictionLaw law);

/// The largest limit friction coefficient over a frequency band: mu >= value keeps the
/// contact stuck (pre-sliding) at every frequency of the band.
struct LimitFrictionMaximum {
    double omega = 0;      ///< frequency of the maximum (the resonance if unbounded)
    double value = 0;      ///< max of mu_limit over [wmin, wmax]; +infinity if unbounded
    bool bounded = true;   ///< false iff an undamped stuck resonance lies in the band
};

/// max over omega in [wmin, wmax] of limit_friction(p, omega, law). Samples a uniform grid
/// of `samples` frequencies together with the band's stuck resonances (so that a peak
/// narrower than the grid is never missed), then refines every sampled local maximum by
/// golden-section search between its neighbours, to a relative width of 1e-13 in omega.
/// Unbounded (value = infinity) iff Coulomb's or Dahl's resonance lies in the band.
/// Throws InvalidInput for invalid p, band or samples (2..max_grid_points).
LimitFrictionMaximum limit_friction_maximum(const AbsorberParameters& p, FrictionLaw law, double wmin,
                                            double wmax, long long samples = 2001);

// ---- Den Hartog optimisation (paper section 4.1) ------------------------------------

/// Optimal tuning wa_op = 1 / (1 + r) (eq. 28).
double den_hartog_tuning(double mass_ratio);

/// Optimal damping ratio xi_op = sqrt(3 r / (8 (1 + r))) (eq. 29). This value belongs to the
/// damping ratio normalised with the absorber's own frequency, xi = c / (2 m2 omega2), i.e.
/// nondimensional damping c = 2 r wa xi (eq. 30 / D.2). (Den Hartog's classical
/// sqrt(3 r / (8 (1 + r)^3)) is the same damper normalised with omega1: c = 2 r xi.)
double den_hartog_damping_ratio(double mass_ratio);

/// Friction coefficient whose equivalent viscous damping equals Den Hartog's optimal damping
/// at frequency omega, for the Den Hartog design (wa = wa_op whatever p.tuning_ratio is):
/// with c = 2 r wa_op xi_op, the slipping response is that of the linear damped absorber,
/// |D| = fe omega^2 / sqrt(Delta^2 + (omega c s / r)^2), and c_e = c requires
///     mu_op = (pi / 4) omega c |D|.
/// Paper eq. 32 prints (approximately) mu_op^2 instead of mu_op.
double den_hartog_friction(const AbsorberParameters& p, double omega);

// ---- Den Hartog (1930): the forced Coulomb oscillator without stops ------------------

/// Nondimensional form of m x'' + k x + F_c sign(x') = F0 cos(Omega t): with
/// x_st = F0 / k, omega_n = sqrt(k / m), u = x / x_st, tau = omega_n t,
///     u'' + u + rho sign(u') = cos(eta tau),   eta = Omega / omega_n,  rho = F_c / F0.
///
/// Derivation (continuous motion, two stops per cycle, each of zero duration). Seek a
/// T-periodic (T = 2 pi / eta) solution with the antisymmetry u(tau + T/2) = -u(tau) and
/// put tau = 0 at a minimum: u(0) = -A, u'(0) = 0, forcing cos(eta tau + phi) (phi to be
/// found). On the upward half period s in [0, theta], theta = pi / eta, sign(u') = +1 and
///     u = -rho + a cos s + b sin s + D cos(eta s + phi),   D = 1 / (1 - eta^2).
/// The four conditions u(0) = -A, u'(0) = 0, u(theta) = A, u'(theta) = 0 (the end of the
/// half period is the maximum, by antisymmetry; cos(eta theta + phi) = -cos phi) give
///     u'(0) = 0:      b = eta D sin phi
///     u'(theta) = 0:  a = eta D sin phi (1 + cos theta) / sin theta = eta D sin phi cot(theta/2)
///     u(0) + u(theta) = 0:  a (1 + cos theta) + b sin theta = 2 rho
///                     => 2 eta D sin phi cot(theta/2) = 2 rho => D sin phi = rho U,
///     U(eta) = tan(pi / (2 eta)) / eta = sin(pi/eta) / (eta (1 + cos(pi/eta))),
/// hence a = rho, b = rho tan(theta/2), and u(theta) - u(0) = 2A gives (the a and b terms
/// cancel) A = -D cos phi, so
///     A = sqrt(D^2 - (rho U)^2).
/// This is Den Hartog's x0 / x_st = sqrt(V^2 - (F_c U / F0)^2) with V = 1/(1 - eta^2) and
/// his U in trigonometric form (sin, cos: the hyperbolic form sinh/cosh quoted in some
/// secondary sources is not what the equation of motion gives).
/// Phase: the maximum of u is at eta tau = psi (mod 2 pi) with cos psi = A / D,
/// sin psi = -rho U / D (psi = phi + pi): the displacement lags the force by psi.
/// Valid only if the motion never stops longer than an instant (den_hartog_check).
struct DenHartogResponse {
    double frequency_ratio = 0;  ///< eta = Omega / omega_n
    double friction_ratio = 0;   ///< rho = F_c / F0
    double amplitude = 0;        ///< A = max |u|
    double phase = 0;            ///< psi in [0, 2 pi): lag of the maximum of u behind the force
    /// u(tau) and u'(tau) of the steady state over any tau (closed form, antisymmetric halves).
    double displacement(double tau) const;
    double velocity(double tau) const;
};

/// Whether the non-sticking (two instantaneous stops per cycle) assumption holds:
/// (1) the solution exists, (rho U)^2 < D^2 (and eta != 1, eta not 1/(2k+1) where U is
/// infinite); (2) at the stop the spring and forcing overcome friction, u''(0+) =
/// -rho - eta^2 D cos phi > 0 (Den Hartog's stop condition: cos(phi) + A > rho);
/// (3) u' > 0 inside the upward half period (no intermediate stop), checked on 4096 points.
struct DenHartogCheck {
    bool valid = false;
    std::string reason;  ///< which condition fails (empty when valid)
};
DenHartogCheck den_hartog_check(double frequency_ratio, double friction_ratio);

/// The closed form above. Throws InvalidInput when eta or rho is not positive and finite or
/// when den_hartog_check fails (the message gives the reason).
DenHartogResponse den_hartog(double frequency_ratio, double friction_ratio);

// ---- the table of `hbf analytic` -----------------------------------------------------

/// One frequency of the analytic table. An empty optional means no finite value exists
/// there (no slipping solution, or an exact undamped resonance).
struct Row {
    double omega = 0;
    std::optional<double> y1_stick, y2_stick;  ///< |Y1|, |Y2| in full stick (law's own)
    std::optional<double> y1_slip, y2_slip;    ///< |Y1|, |Y2| in full slip (equivalent viscous)
    std::optional<double> mu_limit;            ///< law's limit friction coefficient
    std::optional<double> mu_opt_den_hartog;   ///< den_hartog_friction
};

/// The uniform grid omega_i = wmin + i (wmax - wmin) / (points - 1), i = 0..points-1, with
/// both ends exact. Throws InvalidInput unless 0 < wmin < wmax (finite) and
/// 2 <= points <= max_grid_points.
constexpr int max_grid_points = 1000000;
std::vector<double> uniform_grid(double wmin, double wmax, long long points);

/// Evaluates every closed form at every frequency of the grid. Validates p for `law`.
std::vector<Row> table(const AbsorberParameters& p, FrictionLaw law, const std::vector<double>& omegas);

}  // namespace hbf::analytic
