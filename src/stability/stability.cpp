// hbfriction — Floquet verdicts of HB points and branches (stability.hpp). The variational
// equation and Hill's matrix are in stability/variational, its CVODE monodromy in
// stability/monodromy.
#include "hbf/stability.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "hbf/contact_law.hpp"
#include "hbf/elastic_exact.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/modal_exact.hpp"
#include "hbf/rigid_exact.hpp"
#include "hbf/contact_force.hpp"
#include "stability/monodromy.hpp"
#include "time_integration/law_orbit.hpp"
#include "stability/variational.hpp"
#include "base/enum_table.hpp"

namespace hbf {

using detail::at_phase;
using detail::eigenvalues;
using detail::sorted_hill;
using detail::Variational;

constexpr detail::EnumName<Stability> stability_names[] = {
    {Stability::not_computed, ""}, {Stability::stable, "true"}, {Stability::unstable, "false"},
    {Stability::uncertain, "uncertain"}};

std::string to_string(Stability stability) { return detail::enum_name(stability_names, stability, "stability"); }

constexpr detail::EnumName<StabilityMethod> stability_method_names[] = {
    {StabilityMethod::hill, "hill"}, {StabilityMethod::monodromy, "monodromy"}, {StabilityMethod::both, "both"}};

std::string to_string(StabilityMethod method) {
    return detail::enum_name(stability_method_names, method, "stability method");
}

StabilityMethod parse_stability_method(const std::string& name) {
    return detail::parse_enum(stability_method_names, name, "stability method");
}

void StabilityOptions::validate() const {
    if (!(tolerance >= 0.0 && tolerance <= 1.0))
        throw InvalidInput("stability tolerance = " + format_number(tolerance) + " is out of range: allowed 0..1");
    if (!(confidence > 0.0 && confidence <= 1.0))
        throw InvalidInput("stability confidence = " + format_number(confidence) + " is out of range: allowed (0, 1]");
    if (!(integration_tolerance >= 1e-13 && integration_tolerance <= 1e-4))
        throw InvalidInput("stability integration_tolerance = " + format_number(integration_tolerance) +
                           " is out of range: allowed 1e-13..1e-4");
    if (max_hill_size < 10 || max_hill_size > 20000)
        throw InvalidInput("stability max_hill_size = " + std::to_string(max_hill_size) +
                           " is out of range: allowed 10..20000");
    if (!(exact_gap > 0.0 && std::isfinite(exact_gap)))
        throw InvalidInput("stability exact_gap = " + format_number(exact_gap) + " is out of range: allowed > 0");
    check_exact_threads(exact_threads, "stability exact_threads");
}

namespace {

bool smooth(FrictionLaw law) {
    return contact_law(law).smooth();
}

double largest_modulus(const Eigen::VectorXcd& mu) {
    return mu.size() == 0 ? std::numeric_limits<double>::quiet_NaN() : mu.cwiseAbs().maxCoeff();
}

Stability verdict(double margin, double tolerance) {
    if (!std::isfinite(margin)) return Stability::uncertain;
    return margin > 1.0 + tolerance ? Stability::unstable : Stability::stable;
}

}  // namespace

std::string stability_refusal(const System& system) {
    if (system.cyclic.active()) return "the stability analysis is not available for a sector model (cyclic symmetry)";
    if (system.contacts.empty()) {
        if (!system.has_positive_definite_mass())
            return "the mass matrix is singular (massless DOFs): the stability analysis needs M positive definite";
        return "";
    }
    if (rigid_contacts_only(system)) {
        const std::string why = rigid_solver_refusal(system);
        return why.empty() ? "" : "the stability of law unilateral comes from the rigid-contact exact solver, which refuses: " + why;
    }
    if (elastic_contacts_only(system)) {
        const std::string why = elastic_solver_refusal(system);
        return why.empty() ? "" : "the stability of law elastic comes from its periodic-orbit solver, which refuses: " + why;
    }
    for (const Contact& c : system.contacts)
        if (!contact_law(c.law).time_domain())
            return "law " + to_string(c.law) + " is not smooth and has no event-exact solver: no stability analysis";
    bool all_smooth = true, all_exact = true;
    for (const Contact& c : system.contacts) {
        all_smooth = all_smooth && smooth(c.law);
        all_exact = all_exact && !smooth(c.law);
    }
    if (all_exact) {
        const std::string why = exact_polish_refusal(system);
        return why.empty() ? "" : "coulomb/jenkins stability comes from the event-exact solver, which refuses: " + why;
    }
    if (!all_smooth)
        return "the contacts mix smooth laws (dahl, lugre, coulomb-reg) with coulomb/jenkins: no stability analysis "
               "covers both";
    if (!system.has_positive_definite_mass())
        return "the mass matrix is singular (massless DOFs): the variational equations need M positive definite";
    return "";
}

StabilityAnalyser::StabilityAnalyser(HarmonicBalance& hb, StabilityOptions options)
    : hb_(hb), options_(options) {
    options_.validate();
    const System& s = hb.system();
    refusal_ = stability_refusal(s);
    smooth_ = std::all_of(s.contacts.begin(), s.contacts.end(), [](const Contact& c) { return smooth(c.law); });
    if (!refusal_.empty() || !smooth_) return;
    const Eigen::MatrixXd m = Eigen::MatrixXd(s.mass);
    minv_ = m.llt().solve(Eigen::MatrixXd::Identity(m.rows(), m.cols()));
    w_.resize(s.dofs(), 0);  // every contact's directions, in order (Variational)
    for (const Contact& c : s.contacts) {
        const Eigen::MatrixXd w = s.contact_directions(c);
        w_.conservativeResize(Eigen::NoChange, w_.cols() + w.cols());
        w_.rightCols(w.cols()) = w;
    }
}

Eigen::VectorXd StabilityAnalyser::start_state(const SolutionPoint& point) {
    const System& s = hb_.system();
    Eigen::VectorXd state = exact_start_state(hb_, point);
    if (elastic_contacts_only(s)) return state;  // [y, y', sliders, modes], law elastic's own
    const int n = s.dofs(), nc = static_cast<int>(s.contacts.size());
    for (int c = 0; c < nc; ++c) {
        const FrictionLaw law = s.contacts[static_cast<std::size_t>(c)].law;
        if (contact_law(law).time_state() != TimeState::bristle) continue;
        double z, rate;
        at_phase(hb_.state(point.x, c), 0.0, z, rate);
        state(2 * n + c) = z;
        state(2 * n + nc + c) = 0;
    }
    return state;
}

Eigen::VectorXcd StabilityAnalyser::hill(const SolutionPoint& point) {
    if (!refusal_.empty() || !smooth_) return {};
    return sorted_hill(Variational(hb_, minv_, w_, point), hb_.fourier(), options_.max_hill_size);
}

Eigen::MatrixXd StabilityAnalyser::monodromy(const SolutionPoint& point) {
    if (!refusal_.empty() || !smooth_) return {};
    const Variational v(hb_, minv_, w_, point);
    Eigen::MatrixXd phi;
    std::string failure;
    if (!detail::integrate_monodromy(v, options_.integration_tolerance, phi, failure)) return {};
    return phi;
}

FloquetResult StabilityAnalyser::operator()(const SolutionPoint& point) {
    FloquetResult r;
    if (!refusal_.empty()) {
        r.message = refusal_;
        return r;
    }
    if (!smooth_) {
        // Coulomb / Jenkins: the event-exact orbit from the HB state at t = 0. A model beyond the
        // exact solver's size has its verdicts from the polish on its modal form
        // (analyse_branch_stability's `polish`); without it, none. Law unilateral: the
        // rigid-contact exact orbit from the same state (y and y' alone).
        const bool rigid = rigid_contacts_only(hb_.system()), elastic = elastic_contacts_only(hb_.system());
        if (!rigid && !elastic && !exact_solver_supports(hb_.system())) {
            r.message = "the stability of coulomb/jenkins contacts on this model comes from the exact polish on its "
                        "modal form (modal_exact.hpp), which did not run here (exact off)";
            return r;
        }
        ExactOptions exact;
        exact.stop = options_.stop;
        exact.threads = options_.exact_threads;
        const ExactOrbit orbit = detail::law_periodic_orbit(hb_.system(), point.omega, start_state(point), exact);
        r.route = "exact";
        r.multipliers = orbit.multipliers;
        r.margin = orbit.max_multiplier;
        if (!orbit.stopped.empty()) {
            r.multipliers.resize(0);
            r.margin = std::numeric_limits<double>::quiet_NaN();
            r.message = "stopped: " + orbit.stopped;
            return r;
        }
        if (!orbit.converged) {
            r.stability = Stability::uncertain;
            r.message = "the exact solver did not converge from the HB state: " + orbit.message;
            return r;
        }
        // The HB orbit's y_max on the AFT grid against the exact one (all DOFs).
        const Eigen::MatrixXd y = hb_.dofs(point.x, point.omega);
        double gap = 0.0, scale = 0.0;
        Eigen::VectorXd samples(hb_.time_samples());
        for (int i = 0; i < y.cols(); ++i) {
            hb_.fourier().to_time(y.col(i), samples);
            const double exact = orbit.y_max[static_cast<std::size_t>(i)];
            gap = std::max(gap, std::abs(samples.cwiseAbs().maxCoeff() - exact));
            scale = std::max(scale, exact);
        }
        if (gap > options_.exact_gap * scale) {
            r.stability = Stability::uncertain;
            r.message = "the exact orbit found from the HB state differs from it (y_max gap " +
                        format_number(gap / scale) + ")";
            return r;
        }
        if (!std::isfinite(orbit.max_multiplier)) {
            r.stability = Stability::uncertain;
            r.message = "the exact orbit's multipliers could not be computed: " + orbit.message;
            return r;
        }
        if (orbit.stability_unresolved()) {
            r.stability = Stability::uncertain;
            r.message = "the largest multiplier " + format_number(orbit.max_multiplier) +
                        " is within the exact orbit's multipliers' accuracy (" + format_number(orbit.multiplier_accuracy) +
                        ", central differences of the period map) of 1";
            return r;
        }
        r.stability = orbit.stable ? Stability::stable : Stability::unstable;
        return r;
    }
    const bool use_hill = options_.method != StabilityMethod::monodromy;
    const bool use_monodromy = options_.method != StabilityMethod::hill;
    const Variational v(hb_, minv_, w_, point);  // one linearisation for both routes
    if (use_hill) {
        r.hill_multipliers = sorted_hill(v, hb_.fourier(), options_.max_hill_size);
        r.hill_margin = largest_modulus(r.hill_multipliers);
    }
    std::string failure;
    if (use_monodromy) {
        Eigen::MatrixXd phi;
        if (detail::integrate_monodromy(v, options_.integration_tolerance, phi, failure)) {
            r.monodromy_multipliers = eigenvalues(phi);
            r.monodromy_margin = largest_modulus(r.monodromy_multipliers);
        }
    }
    const bool has_hill = r.hill_multipliers.size() > 0, has_monodromy = r.monodromy_multipliers.size() > 0;
    r.route = has_hill && has_monodromy ? "hill+monodromy" : has_hill ? "hill" : has_monodromy ? "monodromy" : "";
    if (has_monodromy) {
        r.multipliers = r.monodromy_multipliers;
        r.margin = r.monodromy_margin;
    } else if (has_hill) {
        r.multipliers = r.hill_multipliers;
        r.margin = r.hill_margin;
    }
    if (!has_hill && !has_monodromy) {
        r.stability = failure.empty() ? Stability::not_computed : Stability::uncertain;
        r.message = !failure.empty() ? failure
                                     : "Hill's matrix is larger than stability max_hill_size = " +
                                           std::to_string(options_.max_hill_size) + " rows";
        return r;
    }
    if (use_monodromy && !has_monodromy) {
        r.stability = Stability::uncertain;
        r.message = failure;
        return r;
    }
    const Stability h = has_hill ? verdict(r.hill_margin, options_.tolerance) : Stability::not_computed;
    const Stability m = has_monodromy ? verdict(r.monodromy_margin, options_.tolerance) : Stability::not_computed;
    if (has_hill && has_monodromy && h != m) {
        r.stability = Stability::uncertain;
        r.message = "Hill's sorted multipliers (largest " + format_number(r.hill_margin) +
                    ") and the monodromy's (largest " + format_number(r.monodromy_margin) + ") disagree";
        return r;
    }
    r.stability = has_monodromy ? m : h;
    return r;
}

std::string BranchStability::summary() const {
    std::string s = "stability: " + std::to_string(stable) + " stable, " + std::to_string(unstable_points) +
                    " unstable, " + std::to_string(uncertain) + " uncertain";
    if (not_computed > 0) s += ", " + std::to_string(not_computed) + " not computed";
    s += "; " + std::to_string(unstable.size()) + " unstable interval(s)";
    if (!bifurcations.empty()) s += ", " + std::to_string(bifurcations.size()) + " bifurcation(s)";
    if (both_confident > 0)
        s += "; Hill's sorting disagreed with the monodromy at " + std::to_string(sorting_disagreements) + " of " +
             std::to_string(both_confident) + " confident points";
    s += " (" + format_number(seconds) + " s)";
    return s;
}

namespace {

/// Unstable multipliers of each kind: real > 0, real < 0, complex.
struct Crossings {
    int positive = 0, negative = 0, complex = 0;
    double positive_max = 0, negative_max = 0, complex_max = 0;  // largest modulus of each kind
};
Crossings classify(const Eigen::VectorXcd& mu, double tolerance) {
    Crossings c;
    for (Eigen::Index k = 0; k < mu.size(); ++k) {
        const double m = std::abs(mu(k));
        const bool real = std::abs(mu(k).imag()) <= 1e-9 * std::max(1.0, m);
        double& largest = !real ? c.complex_max : mu(k).real() > 0 ? c.positive_max : c.negative_max;
        largest = std::max(largest, m);
        if (m <= 1.0 + tolerance) continue;
        if (!real)
            ++c.complex;
        else if (mu(k).real() > 0)
            ++c.positive;
        else
            ++c.negative;
    }
    return c;
}

}  // namespace

void find_bifurcations(const std::vector<SolutionPoint>& points, double tolerance, BranchStability& b) {
    if (b.points.size() != points.size())
        throw InvalidInput("stability verdicts = " + std::to_string(b.points.size()) +
                           " do not match the points = " + std::to_string(points.size()) + ": allowed one per point");
    b.unstable.clear();
    b.bifurcations.clear();
    // Unstable intervals and bifurcations along each branch (samples excluded).
    bool open = false;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const SolutionPoint& p = points[k];
        if (p.kind == PointKind::sample) continue;
        const bool unstable = b.points[k].stability == Stability::unstable;
        if (open && (!unstable || p.branch != b.unstable.back().branch)) open = false;
        if (unstable) {
            if (!open) b.unstable.push_back({p.omega, p.omega, p.branch});
            b.unstable.back().omega_to = p.omega;
            open = true;
        }
    }
    // Between consecutive points with a verdict (uncertain ones skipped: their multipliers
    // are in doubt) on one branch.
    auto certain = [&](std::size_t k) {
        const Stability s = b.points[k].stability;
        return points[k].kind != PointKind::sample && b.points[k].multipliers.size() > 0 &&
               (s == Stability::stable || s == Stability::unstable);
    };
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (!certain(k)) continue;
        std::size_t next = k + 1;
        while (next < points.size() && points[next].branch == points[k].branch && !certain(next)) ++next;
        if (next >= points.size() || !certain(next) || points[next].branch != points[k].branch) continue;
        const SolutionPoint &p = points[k], &q = points[next];
        const Eigen::VectorXcd &a = b.points[k].multipliers, &c = b.points[next].multipliers;
        const Crossings x = classify(a, tolerance), y = classify(c, tolerance);
        auto add = [&](const char* kind, double ma, double mc) {
            double omega = p.omega;
            if (std::abs(mc - ma) > 0.0) omega = p.omega + (1.0 - ma) / (mc - ma) * (q.omega - p.omega);
            if (!(std::isfinite(omega))) omega = p.omega;
            b.bifurcations.push_back({k, next, omega, kind, p.branch});
        };
        // Through +1: a fold where the branch turns between the two points (a located fold point
        // among them), else a branch point (symmetry breaking, or a nonsmooth jump of the
        // multipliers at a stick-slip transition).
        bool turns = false;
        for (std::size_t j = k; j <= next; ++j) turns = turns || points[j].kind == PointKind::fold;
        if (x.positive != y.positive) add(turns ? "fold" : "branch-point", x.positive_max, y.positive_max);
        if (x.negative != y.negative) add("period-doubling", x.negative_max, y.negative_max);
        if (x.complex != y.complex) add("neimark-sacker", x.complex_max, y.complex_max);
    }
}

void mark_bifurcations(const BranchStability& b, std::vector<SolutionPoint>& points) {
    for (const BranchStability::Bifurcation& f : b.bifurcations) {
        if (f.at >= points.size() || points[f.at].kind != PointKind::regular) continue;
        if (f.kind == "branch-point") points[f.at].kind = PointKind::branch_point;
        if (f.kind == "period-doubling") points[f.at].kind = PointKind::period_doubling;
        if (f.kind == "neimark-sacker") points[f.at].kind = PointKind::neimark_sacker;
    }
}

BranchStability analyse_branch_stability(HarmonicBalance& hb, const std::vector<SolutionPoint>& points,
                                         const StabilityOptions& options, const std::vector<ExactPoint>* polish) {
    const auto started = std::chrono::steady_clock::now();
    BranchStability b;
    StabilityAnalyser analyse(hb, options);
    // Asked until it answers (its answer is kept): whether the analysis has stopped.
    auto stop_asked = [&] {
        if (b.stopped.empty() && options.stop) b.stopped = options.stop();
        return !b.stopped.empty();
    };
    b.points.reserve(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (polish && k < polish->size() && (*polish)[k].status != PolishStatus::off) {
            const ExactPoint& e = (*polish)[k];
            FloquetResult r;
            r.route = "exact";
            if (e.status == PolishStatus::exact && !std::isfinite(e.max_multiplier)) {
                r.stability = Stability::uncertain;
                r.message = "the exact orbit's multipliers could not be computed: " + e.message;
            } else if (e.status == PolishStatus::exact) {
                r.stability = e.stability_unresolved ? Stability::uncertain
                              : e.stable             ? Stability::stable
                                                     : Stability::unstable;
                if (e.stability_unresolved)
                    r.message = "the largest multiplier is within the exact orbit's multipliers' accuracy of 1 "
                                "(central differences of the period map)";
                r.margin = e.max_multiplier;
                r.multipliers = e.multipliers;
            } else {
                r.stability = Stability::uncertain;
                r.message = "the exact polish failed here: " + e.message;
            }
            b.points.push_back(r);
        } else if (stop_asked()) {
            FloquetResult r;  // this point and the rest: not computed
            r.message = "stopped: " + b.stopped;
            b.points.push_back(r);
        } else {
            b.points.push_back(analyse(points[k]));
            FloquetResult& r = b.points.back();
            if (r.stability == Stability::not_computed) stop_asked();  // the exact solver stopped within the point
            // At a located fold a multiplier of the smooth problem is 1 by definition: the
            // verdict changes there, and the harmonic-balance branch may meet it at a corner (a
            // time sample's |v| changing sign) whose one-sided monodromy says 1.1 where time
            // integration from the orbit decays (measured on the Dahl superharmonic fold).
            // (The exact route's verdict is on the exact orbit itself, not on the HB branch: kept.)
            if (points[k].kind == PointKind::fold && r.route != "exact" &&
                (r.stability == Stability::stable || r.stability == Stability::unstable)) {
                r.stability = Stability::uncertain;
                r.message = "a fold: a Floquet multiplier passes through 1 here (stable on one side, unstable on the other)";
            }
        }
        const FloquetResult& r = b.points.back();
        switch (r.stability) {
            case Stability::stable: ++b.stable; break;
            case Stability::unstable: ++b.unstable_points; break;
            case Stability::uncertain: ++b.uncertain; break;
            case Stability::not_computed: ++b.not_computed; break;
        }
        if (points[k].kind != PointKind::fold && r.hill_multipliers.size() > 0 && r.monodromy_multipliers.size() > 0 &&
            std::abs(r.hill_margin - 1.0) > options.confidence && std::abs(r.monodromy_margin - 1.0) > options.confidence) {
            ++b.both_confident;
            if ((r.hill_margin > 1.0) != (r.monodromy_margin > 1.0)) ++b.sorting_disagreements;
        }
        if (options.progress) options.progress(static_cast<int>(k) + 1, static_cast<int>(points.size()));
    }
    find_bifurcations(points, options.tolerance, b);
    b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return b;
}

}  // namespace hbf
