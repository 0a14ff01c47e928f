// hbfriction — contact law `unilateral`: rigid unilateral contact with Coulomb friction
// (Signorini + Coulomb) on massless contact coordinates, by the dynamic Lagrangian.
//
// Definition: along the contact's tangential direction(s) u (w_t^T y; in 3D also the
// second_direction) and its normal direction v (normal_direction^T y, positive closing), with
// the initial gap g_0 >= 0 and the friction coefficient mu >= 0, the forces (T, N) on the
// structure (along w_t and the normal direction, as every law's force f along w) satisfy
//   Signorini:  N >= 0,  g = g_0 - v >= 0,  N g = 0      (no penetration, no adhesion);
//   Coulomb:    |T| <= mu N;  u' = 0 where |T| < mu N (stick);  T = mu N u' / |u'| where
//               u' != 0 (slip along the force: maximal dissipation, a circular cone in 3D).
// Open (g > 0): N = 0 and T = 0. The contact is rigid: while closed, v = g_0 is held and N is a
// constraint's multiplier; while stuck, u is held. On a coordinate with mass such a contact
// impacts (velocity jumps, which a Fourier series cannot carry), so the law takes massless
// contact coordinates only: every direction w must carry no inertia, w^T M w = 0 (a reduced
// model's massless interface nodes, linked to the structure by its stiffness). A massless node
// tied by springs k_t, k_n to a mass is then law elastic's element (its slider the node).
// Parameters: friction_coefficient mu (>= 0), gap g_0 (>= 0, default 0), normal_direction
// (required) and second_direction (3D), as for law elastic (orthogonal, the tangential ones of
// equal length); tangential_penalty eps_t and normal_penalty eps_n (force per displacement),
// 0 = automatic (complete()). No friction_limit, no stiffness.
// A preload is a static load (System::static_load) pushing the node onto its obstacle.
// While stuck (harmonic balance's first guess): rigid along every direction when closed at rest
// (g_0 = 0), released when open (g_0 > 0).
//
// Harmonic balance by the dynamic Lagrangian (Nacivet et al. 2003, here in the fixed-point form
// of law coulomb): the forces lambda_T, lambda_N themselves are unknown signals (d + 1 state
// signals) and the law is written as the projections
//   lambda_N = max(0, a),                 a = lambda_N + eps_n (v - g_0),
//   lambda_T = proj_{|.| <= mu max(0, a)} (lambda_T + eps_t du/dtheta),
// which hold, for any eps_n, eps_t > 0, iff the Signorini and Coulomb conditions above do
// (a <= 0: open, v <= g_0, lambda = 0; a > 0: v = g_0, and the tangential projection is
// Coulomb's, as in coulomb.cpp, within the cone of radius mu lambda_N). The tangential rate is
// taken in the phase theta = w t (du/dtheta = u' / w), so that both penalties are stiffnesses,
// of the size of the contact nodes' own (n^T K n: a massless node has no impedance sqrt(k m) to
// scale a velocity with, and the structure's, through a stiff support, can be 1e-8 of it: the
// iteration then stalls). Balanced like the
// equations of motion: r = Lambda - P proj(E ...), with the force f = lambda. The Jacobian is
// exact on each open/stick/slip pattern of the samples (semi-smooth). In permanent stick (every
// sample closed, and a constant shift of the trial forces t_j = lambda_T,j + eps_t u'_j puts every
// sample strictly inside the cone: a stuck motion exists, whether or not the current iterate's
// forces touch the cone) every sample is taken as stuck (its force t, unprojected) and the mean
// tangential force, which the stuck equations leave free, is fixed by replacing its c0 row with
//   2D: max_j (t_j - mu N_j) + min_j (t_j + mu N_j) = 0, the force centred between the cone's
//       limits: law elastic's centred slider (normal_contact.hpp) when the node is tied to its
//       structure by a spring;
//   3D: the largest-margin force, t shifted by argmin_c max_j (|t_j + c| - mu N_j)
//       (enclosing_circle.hpp; rotation-equivariant; law elastic's centred slider likewise).
// (At a solution in stick u' = 0 and t = lambda_T; deciding on t, the samples the projection
// classifies, keeps the switch consistent with the slip states.) Away from a solution the
// residual jumps at the switch (the two forms agree there only on the centred state), so a
// corrector holds the form for each Newton solve (hold_switch) and judges the solution with it
// free (measured on liftoff3_rigid: Newton cycling across the switch for 20 iterations otherwise).
// A node then leaves permanent stick where its cone can no longer hold the motion with any mean,
// continuously (the centred forces touch the cone there). Deciding permanent stick by the
// iterate's own samples instead (all strictly inside) leaves other roots: a mean at the edge of
// the admissible set with one sample on the cone, or a little beyond it with a slip spread over
// the harmonics, a one-parameter family along which a continuation wanders (measured on the
// mitre example: a backbone stalled at the first touch, 9.86e-8; liftoff3_rigid: steps of 1e-6
// jumping back 5 % in amplitude).
// Not smooth (its stability verdicts come from the rigid-contact exact solver, rigid_exact.hpp), no
// exact-stick solver; the time-domain reference is its own
// integrator with a complementarity solve per step (time_integration/unilateral_contacts.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/enclosing_circle.hpp"
#include "contact/normal_law.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/normal_contact.hpp"
#include "base/stopwatch.hpp"

namespace hbf {

namespace {

constexpr const char* normal_key = "normal_direction";
constexpr const char* second_key = "second_direction";

/// A tangential vector (d = 1 or 2 entries) on the stack: no allocation per sample.
using Tangential = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 2, 1>;

/// The law's parameters as the AFT reads them.
struct Unilateral {
    double mu = 0, gap = 0, eps_t = 0, eps_n = 0;
    int d = 1;  // tangential directions
};

Unilateral unilateral_element(const Contact& c) {
    Unilateral e;
    e.mu = c.values.at("friction_coefficient");
    const auto gap = c.values.find("gap");
    e.gap = gap == c.values.end() ? 0.0 : gap->second;
    const auto eps_t = c.values.find("tangential_penalty"), eps_n = c.values.find("normal_penalty");
    e.eps_t = eps_t == c.values.end() ? 0.0 : eps_t->second;
    e.eps_n = eps_n == c.values.end() ? 0.0 : eps_n->second;
    e.d = c.lists.count(second_key) ? 2 : 1;
    return e;
}

/// The samples of one evaluation: a = lambda_N + eps_n (v - g_0), t = lambda_T + eps_t u', and
/// the projected forces.
struct Samples {
    Eigen::VectorXd a, normal;    // a_j, N*_j = max(0, a_j)
    Eigen::MatrixXd t, force;     // t_j, the projected lambda_T,j (N_t x d)
    Eigen::MatrixXd lambda;       // lambda_T,j (N_t x d)
    std::vector<ContactState> state;
};

/// The dynamic Lagrangian for unilateral contact (see the top of this file).
class UnilateralModel final : public FrictionModel {
public:
    explicit UnilateralModel(const Unilateral& e) : e_(e) {}
    int state_signals() const override { return e_.d + 1; }
    int signals() const override { return e_.d + 1; }

    void evaluate(Fourier& fourier, double, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
                  FrictionEvaluation& out, bool jacobian) const override {
        const int n = fourier.size(), d = e_.d, m = (d + 1) * n;
        Samples s = samples(fourier, q, z);
        const int nt = fourier.time_samples();
        // Permanent stick: every sample closed and some constant shift of the tangential forces
        // puts them strictly inside the cone at every sample (a stuck motion exists), whether or
        // not the current forces touch it. Every sample is then stuck (its force t, unprojected),
        // and the mean is the largest-margin one.
        const bool closed = std::all_of(s.state.begin(), s.state.end(),
                                        [](ContactState c) { return c != ContactState::separated; });
        Eigen::Index high = 0, low = 0;
        detail::EnclosingCircle circle;
        Eigen::MatrixXd points;
        Eigen::VectorXd radii;
        bool permanent_stick = false;
        double centring[2] = {0.0, 0.0};  // the c0 rows' residuals in permanent stick
        if (closed) {
            if (d == 1) {
                const Eigen::VectorXd lt = s.t.col(0);
                const double upper = (lt - e_.mu * s.normal).maxCoeff(&high);
                const double lower = (lt + e_.mu * s.normal).minCoeff(&low);
                permanent_stick = upper < lower;
                centring[0] = 0.5 * (upper + lower);
            } else {
                // The shift c of the mean that centres the forces, argmin_c max_k (|t_k + c| - mu
                // N_k): the residual is -c (0 at the largest-margin force).
                points = -s.t;
                radii = e_.mu * s.normal;
                const double scale =
                    std::max({s.t.cwiseAbs().maxCoeff(), radii.maxCoeff(), std::numeric_limits<double>::min()});
                circle = detail::smallest_enclosing_circle(points, radii, scale);
                permanent_stick = circle.value < 0.0;
                for (int j = 0; j < d; ++j) centring[j] = -circle.centre(j);
            }
        }
        if (holding_ && closed) {  // the form held for this solve (FrictionModel::hold_switch)
            if (held_ < 0)
                held_ = permanent_stick ? 1 : 0;
            else
                permanent_stick = held_ == 1;
        }
        if (permanent_stick) {
            s.force = s.t;
            s.state.assign(s.state.size(), ContactState::stuck);
        }
        Eigen::VectorXd projected(n);
        out.state_residual = z;
        for (int j = 0; j < d; ++j) {
            fourier.to_coefficients(s.force.col(j), projected);
            out.state_residual.segment(j * n, n) -= projected;
        }
        fourier.to_coefficients(s.normal, projected);
        out.state_residual.segment(d * n, n) -= projected;
        out.force = z;
        if (permanent_stick)  // the mean tangential force is free (see the top of this file)
            for (int j = 0; j < d; ++j) out.state_residual(j * n) = centring[j];
        out.jacobian_seconds = 0.0;
        if (!jacobian) return;
        detail::Stopwatch watch;
        // Per sample: d proj_T / d t (d x d), d proj_T / d a (d), d N* / d a.
        std::vector<Eigen::VectorXd> dtt(static_cast<std::size_t>(d * d), Eigen::VectorXd::Zero(nt));
        std::vector<Eigen::VectorXd> dta(static_cast<std::size_t>(d), Eigen::VectorXd::Zero(nt));
        Eigen::VectorXd dna = Eigen::VectorXd::Zero(nt);
        for (int k = 0; k < nt; ++k) {
            const auto state = s.state[static_cast<std::size_t>(k)];
            if (state == ContactState::separated) continue;
            dna(k) = 1.0;
            if (state == ContactState::stuck) {
                for (int j = 0; j < d; ++j) dtt[static_cast<std::size_t>(j * d + j)](k) = 1.0;
                continue;
            }
            const Tangential t = s.t.row(k).transpose();
            const double size = t.norm();
            if (!(size > 0.0)) continue;
            const Tangential direction = t / size;
            const double radius = e_.mu * s.normal(k);
            for (int i = 0; i < d; ++i) {
                dta[static_cast<std::size_t>(i)](k) = e_.mu * direction(i);
                for (int j = 0; j < d; ++j)
                    dtt[static_cast<std::size_t>(i * d + j)](k) =
                        radius / size * ((i == j ? 1.0 : 0.0) - direction(i) * direction(j));
            }
        }
        out.state_z = Eigen::MatrixXd::Identity(m, m);
        out.state_q = Eigen::MatrixXd::Zero(m, m);
        out.state_omega = Eigen::VectorXd::Zero(m);
        Eigen::MatrixXd product(n, n);
        for (int i = 0; i < d; ++i) {
            for (int j = 0; j < d; ++j) {  // through t_j = lambda_T,j + eps_t u_j'
                fourier.multiplication_matrix(dtt[static_cast<std::size_t>(i * d + j)], product);
                out.state_z.block(i * n, j * n, n, n) -= product;
                out.state_q.block(i * n, j * n, n, n) = -e_.eps_t * fourier.times_derivative(product);
            }
            // through a = lambda_N + eps_n (v - g_0)
            fourier.multiplication_matrix(dta[static_cast<std::size_t>(i)], product);
            out.state_z.block(i * n, d * n, n, n) -= product;
            out.state_q.block(i * n, d * n, n, n) = -e_.eps_n * product;
        }
        fourier.multiplication_matrix(dna, product);
        out.state_z.block(d * n, d * n, n, n) -= product;
        out.state_q.block(d * n, d * n, n, n) = -e_.eps_n * product;
        if (permanent_stick) {
            if (d == 1) {
                const Eigen::MatrixXd& E = fourier.synthesis();
                out.state_z.row(0).setZero();
                out.state_q.row(0).setZero();
                out.state_z.block(0, 0, 1, n) = 0.5 * (E.row(high) + E.row(low));
                out.state_q.block(0, 0, 1, n) = 0.5 * e_.eps_t * (E.row(high) + E.row(low)) * fourier.derivative();
                out.state_z.block(0, n, 1, n) = 0.5 * e_.mu * (E.row(low) - E.row(high));
                out.state_q.block(0, n, 1, n) = 0.5 * e_.mu * e_.eps_n * (E.row(low) - E.row(high));
            } else {
                // d(-c) = -sum over the basis of (dc/du_i du_i + dc/dr_i dr_i), u_i = -t_i =
                // -(lambda_T,i + eps_t u'_i), r_i = mu N_i, N_i = lambda_N,i + eps_n (v_i - g_0)
                // (closed throughout).
                const Eigen::MatrixXd& E = fourier.synthesis();
                const detail::EnclosingDerivative dd = detail::enclosing_circle_derivative(points, radii, circle);
                for (int j = 0; j < d; ++j) {
                    out.state_z.row(j * n).setZero();
                    out.state_q.row(j * n).setZero();
                }
                for (int k = 0; k < circle.size; ++k) {
                    const int i = circle.member[static_cast<std::size_t>(k)];
                    const Eigen::Matrix2d& du = dd.du[static_cast<std::size_t>(k)];
                    const Eigen::Vector2d& dr = dd.dr[static_cast<std::size_t>(k)];
                    const Eigen::RowVectorXd rate = e_.eps_t * E.row(i) * fourier.derivative();
                    for (int j = 0; j < d; ++j) {
                        for (int c = 0; c < d; ++c) {
                            out.state_z.block(j * n, c * n, 1, n) += du(j, c) * E.row(i);
                            out.state_q.block(j * n, c * n, 1, n) += du(j, c) * rate;
                        }
                        out.state_z.block(j * n, d * n, 1, n) -= dr(j) * e_.mu * E.row(i);
                        out.state_q.block(j * n, d * n, 1, n) -= dr(j) * e_.mu * e_.eps_n * E.row(i);
                    }
                }
            }
        }
        out.force_q = Eigen::MatrixXd::Zero(m, m);
        out.force_z = Eigen::MatrixXd::Identity(m, m);
        out.force_omega = Eigen::VectorXd::Zero(m);
        out.jacobian_seconds = watch.lap();
    }

    /// The law's own forces: the projections (|T| <= mu N, N >= 0 at every sample), stacked
    /// per direction; at a solution their H-harmonic series are z.
    Eigen::VectorXd force_samples(Fourier& fourier, double, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd& z) const override {
        const Samples s = samples(fourier, q, z);
        return detail::stack_directions(s.force, s.normal);
    }

    /// As law elastic: |t| / (mu N) - 1 where stuck (< 0), 0 where slipping, 1 where open.
    Eigen::VectorXd stick_indicator(Fourier& fourier, double, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& z) const override {
        const Samples s = samples(fourier, q, z);
        Eigen::VectorXd phi(fourier.time_samples());
        constexpr double tiny = std::numeric_limits<double>::denorm_min();
        for (Eigen::Index k = 0; k < phi.size(); ++k) {
            switch (s.state[static_cast<std::size_t>(k)]) {
                case ContactState::separated: phi(k) = 1.0; break;
                case ContactState::slipping: phi(k) = 0.0; break;
                case ContactState::stuck: {
                    const double radius = e_.mu * s.normal(k);
                    phi(k) = radius > 0.0 ? std::min(s.t.row(k).norm() / radius - 1.0, -tiny) : -1.0;
                    break;
                }
            }
        }
        return phi;
    }

private:
    Samples samples(Fourier& fourier, const Eigen::VectorXd& q, const Eigen::VectorXd& z) const {
        const int n = fourier.size(), nt = fourier.time_samples(), d = e_.d;
        const Eigen::MatrixXd& D1 = fourier.derivative();
        Samples s;
        Eigen::VectorXd v(nt), lambda(nt), velocity(nt);
        fourier.to_time(q.segment(d * n, n), v);
        fourier.to_time(z.segment(d * n, n), lambda);
        s.a = lambda.array() + e_.eps_n * (v.array() - e_.gap);
        s.normal = s.a.cwiseMax(0.0);
        s.t.resize(nt, d);
        s.lambda.resize(nt, d);
        for (int j = 0; j < d; ++j) {
            fourier.to_time(D1 * q.segment(j * n, n), velocity);  // du/dtheta
            fourier.to_time(z.segment(j * n, n), lambda);
            s.lambda.col(j) = lambda;
            s.t.col(j) = lambda + e_.eps_t * velocity;
        }
        s.force = Eigen::MatrixXd::Zero(nt, d);
        s.state.assign(static_cast<std::size_t>(nt), ContactState::separated);
        for (int k = 0; k < nt; ++k) {
            if (!(s.a(k) > 0.0)) continue;
            const double radius = e_.mu * s.normal(k), size = s.t.row(k).norm();
            if (size < radius) {
                s.state[static_cast<std::size_t>(k)] = ContactState::stuck;
                s.force.row(k) = s.t.row(k);
            } else {
                s.state[static_cast<std::size_t>(k)] = ContactState::slipping;
                if (size > 0.0) s.force.row(k) = radius / size * s.t.row(k);
            }
        }
        return s;
    }

    bool hold_switch(bool on) const override {
        holding_ = on;
        held_ = -1;
        return true;
    }

    Unilateral e_;
    mutable bool holding_ = false;  // hold_switch
    mutable int held_ = -1;         // the held form: -1 not decided yet, 1 permanent stick, 0 not
};

class UnilateralLaw final : public detail::NormalDirectionLaw {
public:
    UnilateralLaw()
        : NormalDirectionLaw(FrictionLaw::unilateral, "unilateral",
              "rigid unilateral contact with Coulomb friction on massless coordinates: N >= 0, v <= g_0, "
              "N (g_0 - v) = 0; |T| <= mu N, T = mu N u'/|u'| where sliding (2D; 3D with second_direction)") {}
    // Measured on the mitre example at H = 5: cold starts at seven frequencies through stick,
    // slip and lift-off converge structured at every one, to the dense form's solutions, 17 to
    // 320 times faster (docs/benchmarks.md).
    bool states_prefer_dense() const override { return false; }
    std::vector<LawParameter> parameters() const override {
        using R = LawParameter::Range;
        const NormalContactParameters shared = normal_contact_parameters();
        return {shared.friction_coefficient,
                shared.gap,
                {"tangential_penalty", nullptr,
                 "dynamic Lagrangian eps_t, tangential (force per displacement, on du/dtheta; 0 = automatic)",
                 R::non_negative, "automatic: w^T K w, the contact node's own tangential stiffness"},
                {"normal_penalty", nullptr, "dynamic Lagrangian eps_n, normal (force per displacement; 0 = automatic)",
                 R::non_negative, "automatic: n^T K n, the contact node's own normal stiffness"},
                shared.second_direction,
                shared.normal_direction};
    }
    int default_harmonics() const override { return 20; }
    TimeIntegrator time_integrator() const override { return TimeIntegrator::unilateral_contacts; }
    /// Closed at rest (g_0 = 0): rigid along every direction; open: released (no force).
    std::vector<StuckElement> stuck_directions(const Contact& contact) const override {
        const Unilateral e = unilateral_element(contact);
        return std::vector<StuckElement>(static_cast<std::size_t>(e.d + 1),
                                         StuckElement{e.gap == 0.0, 0.0, 0.0, 0.0});
    }
    std::vector<StuckElement> stuck_directions_at(const Contact& contact, double normal) const override {
        std::vector<StuckElement> out = stuck_directions(contact);
        if (normal > 0.0)  // pressed shut
            for (StuckElement& e : out) e.rigid = true;
        return out;
    }
    std::unique_ptr<FrictionModel> periodic_model(const Contact& contact) const override {
        const Unilateral e = unilateral_element(contact);
        if (!(e.eps_t > 0.0) || !(e.eps_n > 0.0))
            throw InvalidInput("tangential_penalty = " + format_number(e.eps_t) + ", normal_penalty = " +
                               format_number(e.eps_n) + " are out of range: allowed > 0 (HarmonicBalance chooses them "
                               "when 0)");
        return std::make_unique<UnilateralModel>(e);
    }
    /// The stuck forces (harmonic h) and the mean forces (harmonic 0) of the linear response
    /// with the contact held; sliding: (4/pi) mu N_mean in phase with the tangential velocity.
    void guess_state(const Contact& contact, bool sliding, const Eigen::VectorXd& q, int cos_row,
                     const Eigen::VectorXcd& stuck_forces, const Eigen::VectorXd& mean_forces,
                     Eigen::Ref<Eigen::VectorXd> z) const override {
        const Unilateral e = unilateral_element(contact);
        const Eigen::Index n = z.size() / (e.d + 1);
        const double normal = std::max(mean_forces.size() > e.d ? mean_forces(e.d) : 0.0, 0.0);
        z(e.d * n) = normal;
        double speed = 0.0;
        for (int j = 0; j < e.d; ++j) speed = std::hypot(speed, std::hypot(q(j * n + cos_row), q(j * n + cos_row + 1)));
        for (int j = 0; j < e.d; ++j) {
            auto zj = z.segment(j * n, n);
            if (sliding && speed > 0.0) {
                const double limit = 4.0 / M_PI * e.mu * normal / speed;
                zj(cos_row) = limit * q(j * n + cos_row + 1);
                zj(cos_row + 1) = -limit * q(j * n + cos_row);
            } else if (!sliding && j < stuck_forces.size() && std::isfinite(std::abs(stuck_forces(j)))) {
                zj(cos_row) = stuck_forces(j).real();
                zj(cos_row + 1) = -stuck_forces(j).imag();
                if (j < mean_forces.size()) zj(0) = mean_forces(j);
            }
        }
        if (!sliding && e.d < stuck_forces.size() && std::isfinite(std::abs(stuck_forces(e.d)))) {
            z(e.d * n + cos_row) = stuck_forces(e.d).real();
            z(e.d * n + cos_row + 1) = -stuck_forces(e.d).imag();
        }
    }
    /// Requires massless directions (see the top of this file) and fills the penalties.
    void complete(Contact& c, const std::vector<DirectionScale>& scales, const std::string& where) const override {
        const auto directions = contact_direction_vectors(c);
        for (std::size_t a = 0; a < scales.size() && a < directions.size(); ++a) {
            const double inertia = scales[a].mass, size = directions[a].second.squaredNorm();
            if (std::abs(inertia) > 1e-12 * scales[a].largest_mass * size)
                throw InvalidInput(where + (a == 0 ? std::string("direction") : directions[a].first) +
                                   " carries mass: w^T M w = " + format_number(inertia) +
                                   "; law unilateral needs massless contact coordinates (allowed w^T M w = 0: a rigid "
                                   "contact on a mass impacts; law elastic gives the contact a stiffness)");
        }
        // The penalties: the contact nodes' own stiffness along the first tangential and the
        // normal direction (the structure's static stiffness there where w^T K w is 0).
        for (const auto& [key, scale] : {std::pair<const char*, const DirectionScale*>{"tangential_penalty", &scales.front()},
                                         {"normal_penalty", &scales.back()}})
            if (!c.values.count(key) || c.values.at(key) == 0.0)
                c.values[key] = scale->stiffness > 0.0 ? scale->stiffness : scale->static_stiffness;
        if (!(c.values.at("tangential_penalty") > 0.0) || !(c.values.at("normal_penalty") > 0.0))
            throw InvalidInput(where + "law unilateral: the structure has no stiffness along the contact's directions "
                               "(w^T K w = 0), from which the automatic tangential_penalty and normal_penalty follow: "
                               "allowed both given > 0, or a structure that holds the contact nodes");
    }

    void validate(const Contact& contact, const std::string& where) const override {
        if (!contact.values.count("friction_coefficient"))
            throw InvalidInput(where + "friction_coefficient is missing: law unilateral needs it (mu >= 0)");
        ContactLaw::validate(contact, where);  // the ranges
        if (contact.values.count("preload") && contact.values.at("preload") != 0.0)
            throw InvalidInput(where + "preload = " + format_number(contact.values.at("preload")) +
                               " is not a parameter of law unilateral (a rigid contact): allowed a static_load pushing "
                               "the contact node onto its obstacle");
        validate_normal_directions(contact, where, "unilateral");
    }
};

}  // namespace

RigidContact rigid_contact(const Contact& contact, int first) {
    const Unilateral e = unilateral_element(contact);
    return {first, e.d, e.mu, e.gap};
}

namespace {

/// The residual lambda - proj(...) of solve_rigid_contacts (returns its largest entry), the
/// projections' derivative and every contact's branch.
double rigid_residual(const std::vector<RigidContact>& contacts, const Eigen::VectorXd& eps, const Eigen::VectorXd& q,
                      const Eigen::VectorXd& reference, const Eigen::VectorXd& lambda, Eigen::VectorXd& residual,
                      Eigen::MatrixXd& slope, std::vector<int>& state) {
    const auto m = lambda.size();
    residual = lambda;
    slope.setZero(m, m);
    state.assign(contacts.size(), 0);
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const RigidContact& b = contacts[c];
        const int normal = b.first + b.d;
        const double a = lambda(normal) + eps(normal) * (q(normal) - b.gap);
        if (!(a > 0.0)) continue;  // open: lambda = 0
        residual(normal) -= a;
        slope(normal, normal) = 1.0;
        Eigen::VectorXd t(b.d);  // (a Tangential here trips GCC 12's -Warray-bounds in Eigen's SSE loads)
        for (int j = 0; j < b.d; ++j)
            t(j) = lambda(b.first + j) + eps(b.first + j) * (q(b.first + j) - reference(b.first + j));
        const double radius = b.mu * a, length = t.norm();
        if (length < radius) {
            state[c] = 1;
            residual.segment(b.first, b.d) -= t;
            slope.block(b.first, b.first, b.d, b.d).setIdentity();
            continue;
        }
        state[c] = 2;
        if (!(length > 0.0)) continue;
        const Eigen::VectorXd direction = t / length;
        residual.segment(b.first, b.d) -= radius * direction;
        slope.block(b.first, b.first, b.d, b.d) =
            radius / length * (Eigen::MatrixXd::Identity(b.d, b.d) - direction * direction.transpose());
        slope.block(b.first, normal, b.d, 1) = b.mu * direction;
    }
    return residual.size() > 0 ? residual.cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace

namespace {

/// One semi-smooth Newton solve of solve_rigid_contacts from out.lambda, its steps halved until
/// the residual's largest entry (two_norm: its 2-norm) falls; converged on the largest entry.
bool rigid_newton(const std::vector<RigidContact>& contacts, const Eigen::MatrixXd& G, const Eigen::VectorXd& q0,
                  const Eigen::VectorXd& reference, const Eigen::VectorXd& eps, bool two_norm, RigidContactSolution& out) {
    const auto m = q0.size();
    Eigen::VectorXd residual(m), trial(m), trial_residual(m);
    Eigen::MatrixXd slope(m, m), trial_slope(m, m);
    std::vector<int> trial_state;
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(m, m);
    const Eigen::MatrixXd coupling = I - eps.asDiagonal() * G;  // d(lambda + e q) / d lambda
    double size = rigid_residual(contacts, eps, q0 - G * out.lambda, reference, out.lambda, residual, slope, out.state);
    double merit = two_norm ? residual.norm() : size;
    const double free = m > 0 ? eps.cwiseProduct(q0).cwiseAbs().maxCoeff() : 0.0;
    for (out.iterations = 0; out.iterations <= 100; ++out.iterations) {
        const double scale = std::max(m > 0 ? out.lambda.cwiseAbs().maxCoeff() : 0.0, free);
        if (size <= 1e-12 * scale || size == 0.0) {
            out.q = q0 - G * out.lambda;
            out.residual = size;
            return true;
        }
        if (out.iterations == 100) break;
        const Eigen::VectorXd step = (I - slope * coupling).partialPivLu().solve(-residual);
        double fraction = 1.0, trial_size = size, trial_merit = merit;
        for (int halving = 0; halving < 30; ++halving, fraction *= 0.5) {
            trial = out.lambda + fraction * step;
            trial_size = rigid_residual(contacts, eps, q0 - G * trial, reference, trial, trial_residual, trial_slope,
                                        trial_state);
            trial_merit = two_norm ? trial_residual.norm() : trial_size;
            if (trial_merit < merit) break;
        }
        if (!(trial_merit < merit)) break;
        out.lambda = trial;
        residual = trial_residual;
        slope = trial_slope;
        out.state = trial_state;
        size = trial_size;
        merit = trial_merit;
    }
    out.q = q0 - G * out.lambda;
    out.residual = size;
    return false;
}

}  // namespace

bool solve_rigid_contacts(const std::vector<RigidContact>& contacts, const Eigen::MatrixXd& G, const Eigen::VectorXd& q0,
                          const Eigen::VectorXd& reference, RigidContactSolution& out) {
    const auto m = q0.size();
    // The augmentation per entry, 1 / G_ii; one value for the tangential entries of a contact
    // (their mean compliance): the fixed point of lambda_T = proj(lambda_T + eps (q_T - s)) has
    // the slip q_T - s along lambda_T only when eps is the same in both tangential directions.
    Eigen::VectorXd eps = G.diagonal().cwiseInverse();
    for (const RigidContact& b : contacts)
        if (b.d > 1) eps.segment(b.first, b.d).setConstant(1.0 / G.diagonal().segment(b.first, b.d).mean());
    if (out.lambda.size() != m) out.lambda = Eigen::VectorXd::Zero(m);
    // The halving test on the residual's largest entry or on its 2-norm can each stall where the
    // other converges (a kink of the projections across the step: on a meshed 3D interface a warm
    // start stopped at 4e-2 of the forces with the one and at 3e-5 with the other), and a start
    // from zero can succeed where the warm start fails: the four in turn, the best kept.
    const Eigen::VectorXd warm = out.lambda;
    RigidContactSolution best;
    int iterations = 0;
    for (int attempt = 0; attempt < 4; ++attempt) {
        RigidContactSolution trial;
        trial.lambda = attempt < 2 ? warm : Eigen::VectorXd::Zero(m);
        const bool ok = rigid_newton(contacts, G, q0, reference, eps, attempt % 2 == 1, trial);
        iterations += trial.iterations;
        if (ok || attempt == 0 || trial.residual < best.residual) best = std::move(trial);
        if (ok) {
            out = std::move(best);
            out.iterations = iterations;
            return true;
        }
        if (attempt == 1 && warm.isZero()) attempt = 3;  // a cold start already
    }
    out = std::move(best);
    out.iterations = iterations;
    return false;
}

const ContactLaw& unilateral_law() {
    static const UnilateralLaw law;
    return law;
}

}  // namespace hbf
