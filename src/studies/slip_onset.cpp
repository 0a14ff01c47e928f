// hbfriction — where a stuck mode starts to slip or open (modes.hpp: slip_onset).
//
// A stuck periodic motion y = y_m + a Re(phi e^{i theta}) leaves each slider anywhere in an
// admissible set; the slider places move the mean state y_m and with it every contact's mean
// forces (through the structure: a tangential mean force moves the normal ones). The onset is
// the largest amplitude at which some choice of the slider places keeps every contact inside
// its limit at every phase: a second-order cone programme in (slider places, a), solved here by
// a barrier method (Newton on -tau a - sum log(t^2 - |u|^2)).
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/modes.hpp"
#include "hbf/static_state.hpp"

namespace hbf {

namespace {

using Complex = std::complex<double>;

Eigen::MatrixXd dense_matrix(const SparseMatrix& matrix, int n) {
    if (matrix.rows() != n || matrix.cols() != n) return Eigen::MatrixXd::Zero(n, n);
    return Eigen::MatrixXd(matrix);
}

/// One constraint |d + E x| <= b + g^T x (a second-order cone in x; E with one row: |.| the
/// absolute value), of contact `contact`.
struct Cone {
    double b = 0;
    Eigen::VectorXd g, d;
    Eigen::MatrixXd e;
    int contact = 0;
};

struct ConeValues {
    bool inside = true;
    double barrier = 0;  ///< -sum log(t^2 - |u|^2)
};

ConeValues cone_barrier(const std::vector<Cone>& cones, const Eigen::VectorXd& x) {
    ConeValues out;
    for (const Cone& c : cones) {
        const double t = c.b + c.g.dot(x);
        const Eigen::VectorXd u = c.d + c.e * x;
        const double gap = t * t - u.squaredNorm();
        if (!(t > 0.0) || !(gap > 0.0)) {
            out.inside = false;
            return out;
        }
        out.barrier -= std::log(gap);
    }
    return out;
}

/// Maximises x(objective) over the cones from the strictly feasible x by the barrier method, to a
/// duality gap of `gap` (2 per cone over tau); stops early once x(objective) >= enough. Returns
/// false where x(objective) grows past `unbounded`. Slider places that move no force (a null
/// direction) are held by a small proximal term.
bool maximise(const std::vector<Cone>& cones, Eigen::Index objective, Eigen::VectorXd& x, double gap, double enough,
              double unbounded) {
    const Eigen::Index n = x.size();
    const double count = 2.0 * static_cast<double>(cones.size());
    for (double tau = 1.0; count / tau > gap; tau *= 8.0) {
        const double proximal = 1e-12 * tau;
        const auto value = [&](const Eigen::VectorXd& at, bool& inside) {
            const ConeValues v = cone_barrier(cones, at);
            inside = v.inside;
            Eigen::VectorXd sliders = at;
            sliders(objective) = 0.0;
            return -tau * at(objective) + v.barrier + 0.5 * proximal * sliders.squaredNorm();
        };
        for (int newton = 0; newton < 100; ++newton) {
            Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n);
            Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(n, n);
            for (const Cone& c : cones) {
                const double t = c.b + c.g.dot(x);
                const Eigen::VectorXd u = c.d + c.e * x;
                const double gap_i = t * t - u.squaredNorm();
                const Eigen::VectorXd dgap = 2.0 * t * c.g - 2.0 * c.e.transpose() * u;
                gradient -= dgap / gap_i;
                hessian += dgap * dgap.transpose() / (gap_i * gap_i);
                hessian -= (2.0 * c.g * c.g.transpose() - 2.0 * c.e.transpose() * c.e) / gap_i;
            }
            gradient(objective) -= tau;
            for (Eigen::Index i = 0; i < n; ++i)
                if (i != objective) {
                    gradient(i) += proximal * x(i);
                    hessian(i, i) += proximal;
                }
            const Eigen::VectorXd step = -hessian.ldlt().solve(gradient);
            const double decrement = -gradient.dot(step);
            if (!std::isfinite(decrement) || decrement < 1e-14) break;
            bool inside = true;
            const double f0 = value(x, inside);
            double length = 1.0;
            for (int halving = 0; halving < 80; ++halving, length *= 0.5) {
                const double f1 = value(x + length * step, inside);
                if (inside && f1 <= f0 - 0.25 * length * decrement) break;
            }
            if (!inside) break;
            x += length * step;
            if (x(objective) >= enough) return true;
            if (x(objective) > unbounded) return false;
            if (decrement < 1e-10) break;
        }
    }
    return true;
}

}  // namespace

SlipOnset slip_onset(const System& system, const LinearMode& mode) {
    system.validate();
    SlipOnset out;
    out.mode = mode.index;
    const int n = system.dofs();
    const Eigen::MatrixXd mass = dense_matrix(system.mass, n);
    Eigen::MatrixXd stiffness = dense_matrix(system.stiffness, n);
    const std::vector<std::vector<StuckElement>> elements = stuck_elements(system);
    const double omega = mode.omega;
    const Eigen::VectorXd& phi = mode.shape;
    // A sector's travelling wave: phi complex (LinearMode::shape_imag).
    Eigen::VectorXcd phi_c = phi.cast<Complex>();
    if (mode.shape_imag.size() == n) phi_c.imag() = mode.shape_imag;
    // Each contact direction's complex force amplitude at a = 1 (the element force, as the
    // static state's): springs directly, rigid ones after.
    std::vector<Eigen::MatrixXd> directions(system.contacts.size());
    std::vector<Eigen::VectorXcd> force(system.contacts.size());
    std::vector<std::pair<std::size_t, Eigen::Index>> rigid;  // (contact, direction)
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        directions[c] = system.contact_directions(system.contacts[c]);
        force[c] = Eigen::VectorXcd::Zero(directions[c].cols());
        for (Eigen::Index j = 0; j < directions[c].cols() && j < static_cast<Eigen::Index>(elements[c].size()); ++j) {
            const StuckElement& e = elements[c][static_cast<std::size_t>(j)];
            if (e.rigid) {
                rigid.emplace_back(c, j);
            } else {
                stiffness += e.stiffness * directions[c].col(j) * directions[c].col(j).transpose();
                force[c](j) = Complex(e.stiffness, omega * e.damping) * directions[c].col(j).cast<Complex>().dot(phi_c);
            }
        }
    }
    const auto rigid_count = static_cast<Eigen::Index>(rigid.size());
    Eigen::MatrixXd w(n, rigid_count);
    for (Eigen::Index j = 0; j < rigid_count; ++j)
        w.col(j) = directions[rigid[static_cast<std::size_t>(j)].first].col(rigid[static_cast<std::size_t>(j)].second);
    if (rigid_count > 0) {
        Eigen::VectorXcd lambda;
        if (system.cyclic.active()) {
            // A sector: the wheel's equations of its own DOFs, T^H (K' - omega^2 M) phi + T^H W lambda = 0.
            const Eigen::MatrixXcd t = cyclic_transform(system, system.cyclic.phase());
            const Eigen::VectorXcd r = t.adjoint() * ((stiffness - omega * omega * mass).cast<Complex>() * phi_c);
            const Eigen::MatrixXcd tw = t.adjoint() * w.cast<Complex>();
            lambda = -tw.completeOrthogonalDecomposition().solve(r);
        } else {
            const Eigen::VectorXd r = (stiffness - omega * omega * mass) * phi;
            lambda = (-w.completeOrthogonalDecomposition().solve(r)).cast<Complex>();
        }
        for (std::size_t j = 0; j < rigid.size(); ++j)
            force[rigid[j].first](rigid[j].second) = lambda(static_cast<Eigen::Index>(j));
    }

    // The contacts with a friction limit: those with friction_limit (one direction), those with a
    // normal direction and a friction coefficient (the normal last).
    std::vector<std::size_t> limited, coned;
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const Contact& contact = system.contacts[c];
        if (contact_law(contact.law).has_friction_limit())
            limited.push_back(c);
        else if (contact.values.count("friction_coefficient") && force[c].size() > 1)
            coned.push_back(c);
    }
    if (limited.empty() && coned.empty()) {
        out.why = "no contact has a friction limit (force elements alone)";
        return out;
    }
    std::string skipped;
    const auto keep = [&](std::size_t c, double a, bool opens) {
        if (!out.found || a < out.amplitude) {
            out.found = true;
            out.amplitude = a;
            out.contact = static_cast<int>(c);
            out.opens = opens;
        }
    };
    StaticState rest;
    if (!coned.empty()) {
        if (system.cyclic.active())
            skipped = "the static state of a sector model is not solved: no normal force at rest";
        else {
            rest = static_state(system);
            if (!rest.ok) skipped = "the static state was not solved (" + rest.message + ")";
        }
    }
    if (coned.empty() || !rest.ok) {
        // Friction limits alone: each contact's mean force is free (its slider), so each slips
        // where its force amplitude reaches its limit.
        for (std::size_t c : limited) {
            const double along = std::abs(force[c](0));
            if (!(along > 1e-12 * system.contacts[c].friction_limit)) {
                skipped = "mode " + std::to_string(mode.index) + " leaves contact " + std::to_string(c + 1) + " at rest";
                continue;
            }
            keep(c, system.contacts[c].friction_limit / along, false);
        }
    } else {
        // The joint problem. Included: the limited contacts and the coned ones pressed at rest.
        struct Member {
            std::size_t contact;
            int tangential;  // directions 0 .. tangential-1 are tangential (slider places)
            bool normal;     // the last direction is the normal one
            double limit;    // the constraint's scale: friction_limit or mu N_0
        };
        std::vector<Member> members;
        for (std::size_t c : limited) members.push_back({c, 1, false, system.contacts[c].friction_limit});
        for (std::size_t c : coned) {
            const Eigen::VectorXd& f0 = rest.contacts[c].force;
            const double normal = f0(f0.size() - 1);
            if (!(normal > 0.0)) {
                skipped = "contact " + std::to_string(c + 1) + " carries no normal force at rest";
                continue;
            }
            const double mu = system.contacts[c].values.at("friction_coefficient");
            members.push_back({c, static_cast<int>(force[c].size() - 1), true, mu * normal});
        }
        // The mean forces' response to the slider places, S (every direction of every member
        // against every tangential direction): the stuck structure's saddle system
        // [K' W_r; W_r^T 0] [y; lambda] = [k w s (springs); s (rigid)].
        std::vector<std::pair<std::size_t, Eigen::Index>> sliders;
        for (const Member& m : members)
            for (int j = 0; j < m.tangential; ++j) sliders.emplace_back(m.contact, j);
        const auto p = static_cast<Eigen::Index>(sliders.size());
        std::vector<Eigen::Triplet<double>> triplets;
        for (Eigen::Index i = 0; i < n; ++i)
            for (Eigen::Index j = 0; j < n; ++j)
                if (stiffness(i, j) != 0.0) triplets.emplace_back(i, j, stiffness(i, j));
        for (Eigen::Index r = 0; r < rigid_count; ++r)
            for (Eigen::Index i = 0; i < n; ++i)
                if (w(i, r) != 0.0) {
                    triplets.emplace_back(i, n + r, w(i, r));
                    triplets.emplace_back(n + r, i, w(i, r));
                }
        SparseMatrix saddle(n + rigid_count, n + rigid_count);
        saddle.setFromTriplets(triplets.begin(), triplets.end());
        Eigen::SparseLU<SparseMatrix> lu(saddle);
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + rigid_count, p);
        for (Eigen::Index k = 0; k < p; ++k) {
            const auto [c, j] = sliders[static_cast<std::size_t>(k)];
            const StuckElement& e = elements[c][static_cast<std::size_t>(j)];
            if (e.rigid) {
                for (Eigen::Index r = 0; r < rigid_count; ++r)
                    if (rigid[static_cast<std::size_t>(r)] == sliders[static_cast<std::size_t>(k)]) rhs(n + r, k) = 1.0;
            } else {
                rhs.col(k).head(n) = e.stiffness * directions[c].col(j);
            }
        }
        Eigen::MatrixXd solution;
        if (lu.info() == Eigen::Success) solution = lu.solve(rhs);
        if (lu.info() != Eigen::Success || !solution.allFinite()) {
            out.why = "the stuck structure's static stiffness is singular";
            return out;
        }
        // S row by row: member m's direction j.
        const auto response = [&](std::size_t c, Eigen::Index j) -> Eigen::RowVectorXd {
            const StuckElement& e = elements[c][static_cast<std::size_t>(j)];
            if (e.rigid) {
                for (Eigen::Index r = 0; r < rigid_count; ++r)
                    if (rigid[static_cast<std::size_t>(r)] == std::make_pair(c, j)) return solution.row(n + r);
            }
            Eigen::RowVectorXd row = e.stiffness * (directions[c].col(j).transpose() * solution.topRows(n));
            for (Eigen::Index k = 0; k < p; ++k)
                if (sliders[static_cast<std::size_t>(k)] == std::make_pair(c, j)) row(k) -= e.stiffness;
            return row;
        };
        // Scales: a by the per-contact estimate with the mean forces fixed, the slider places so
        // that each moves the largest force it moves by the smallest limit.
        double a_ref = std::numeric_limits<double>::infinity(), smallest_limit = std::numeric_limits<double>::infinity();
        Eigen::VectorXcd all(0);
        for (const Member& m : members) {
            const Eigen::VectorXcd& f = force[m.contact];
            smallest_limit = std::min(smallest_limit, m.limit);
            const double normal = m.normal ? m.limit / system.contacts[m.contact].values.at("friction_coefficient") : 0.0;
            const double tangential = f.head(m.tangential).norm();
            const double reach = std::max(tangential / m.limit, m.normal ? std::abs(f(f.size() - 1)) / normal : 0.0);
            if (reach > 0.0) a_ref = std::min(a_ref, 1.0 / reach);
            Eigen::VectorXcd grown(all.size() + f.size());
            grown << all, f;
            all = grown;
        }
        if (!std::isfinite(a_ref)) {
            out.why = "mode " + std::to_string(mode.index) + " leaves every contact with a friction limit at rest";
            return out;
        }
        std::vector<Eigen::MatrixXd> rows(members.size());
        Eigen::VectorXd slider_scale = Eigen::VectorXd::Ones(p);
        {
            Eigen::VectorXd largest = Eigen::VectorXd::Zero(p);
            for (std::size_t i = 0; i < members.size(); ++i) {
                const std::size_t c = members[i].contact;
                const Eigen::Index count = members[i].normal ? force[c].size() : 1;
                rows[i].resize(count, p);
                for (Eigen::Index j = 0; j < count; ++j) rows[i].row(j) = response(c, j);
                largest = largest.cwiseMax(rows[i].cwiseAbs().colwise().maxCoeff().transpose());
            }
            for (Eigen::Index k = 0; k < p; ++k)
                if (largest(k) > 0.0) slider_scale(k) = smallest_limit / largest(k);
        }
        // Phases: two (0, pi) where every force amplitude has one phase (an undamped real mode:
        // the cone condition is convex in cos theta), else 64.
        Eigen::Index big = 0;
        all.cwiseAbs().maxCoeff(&big);
        const Eigen::VectorXcd turned = all / (all(big) / std::abs(all(big)));
        const int phases = turned.imag().norm() <= 1e-12 * turned.norm() ? 2 : 64;
        const Complex unit = all(big) / std::abs(all(big));
        // The cones in x = (slider places / slider_scale, a / a_ref).
        std::vector<Cone> cones;
        for (std::size_t i = 0; i < members.size(); ++i) {
            const Member& m = members[i];
            const std::size_t c = m.contact;
            const Eigen::VectorXd& f0 = rest.contacts[c].force;
            const double mu = m.normal ? system.contacts[c].values.at("friction_coefficient") : 0.0;
            for (int k = 0; k < phases; ++k) {
                const Complex e = std::polar(1.0, 2.0 * M_PI * k / phases) / unit;
                Cone cone;
                cone.contact = static_cast<int>(i);
                cone.g = Eigen::VectorXd::Zero(p + 1);
                cone.e = Eigen::MatrixXd::Zero(m.tangential, p + 1);
                cone.d = f0.head(m.tangential) / m.limit;
                cone.e.leftCols(p) = rows[i].topRows(m.tangential) * slider_scale.asDiagonal() / m.limit;
                cone.e.col(p) = (force[c].head(m.tangential) * e).real() * a_ref / m.limit;
                if (m.normal) {
                    const Eigen::Index last = force[c].size() - 1;
                    cone.b = mu * f0(last) / m.limit;  // 1
                    cone.g.head(p) = mu * (rows[i].row(last).transpose().cwiseProduct(slider_scale)) / m.limit;
                    cone.g(p) = mu * (force[c](last) * e).real() * a_ref / m.limit;
                } else {
                    cone.b = 1.0;
                }
                cones.push_back(std::move(cone));
            }
        }
        Eigen::VectorXd x = Eigen::VectorXd::Zero(p + 1);
        if (!cone_barrier(cones, x).inside) {
            // The static state touches a limit: first slider places strictly inside every one
            // (maximise the margin m: |u| <= t - m), where they exist.
            std::vector<Cone> margin = cones;
            double worst = 0.0;
            for (Cone& c : margin) {
                c.g(p) = -1.0;  // the last variable is m here (a = 0)
                c.e.col(p).setZero();
                worst = std::min(worst, c.b - c.d.norm());
            }
            Eigen::VectorXd y = Eigen::VectorXd::Zero(p + 1);
            y(p) = worst - 1.0;
            maximise(margin, p, y, 1e-12, 1e-3, 1e12);
            if (!(y(p) > 0.0)) {
                out.why = "a contact slips or opens at rest for every place of the sliders";
                return out;
            }
            x.head(p) = y.head(p);
        }
        if (!maximise(cones, p, x, 1e-11, std::numeric_limits<double>::infinity(), 1e9)) {
            out.why = "no contact reaches its limit in mode " + std::to_string(mode.index) + " at any amplitude";
            return out;
        }
        // The contact that limits: the smallest margin t - |u| at the optimum.
        double least = std::numeric_limits<double>::infinity();
        const Cone* limiting = nullptr;
        for (const Cone& c : cones) {
            const double t = c.b + c.g.dot(x), margin = t - (c.d + c.e * x).norm();
            if (margin < least) {
                least = margin;
                limiting = &c;
            }
        }
        const Member& m = members[static_cast<std::size_t>(limiting->contact)];
        const bool opens = m.normal && limiting->b + limiting->g.dot(x) < 1e-6;
        keep(m.contact, x(p) * a_ref, opens);
        // The sliders where the static state leaves them (x_s = 0): each member's first touch of
        // its limit, by bisection on a (its cones are convex in a).
        out.static_amplitude = out.amplitude;
        out.static_contact = out.contact;
        for (std::size_t i = 0; i < members.size(); ++i) {
            const auto excess = [&](double alpha) {
                Eigen::VectorXd at = Eigen::VectorXd::Zero(p + 1);
                at(p) = alpha;
                double worst = -std::numeric_limits<double>::infinity();
                for (const Cone& c : cones)
                    if (c.contact == static_cast<int>(i))
                        worst = std::max(worst, (c.d + c.e * at).norm() - (c.b + c.g.dot(at)));
                return worst;
            };
            if (!(excess(0.0) < 0.0)) {
                out.static_amplitude = 0.0;
                out.static_contact = static_cast<int>(members[i].contact);
                break;
            }
            double lo = 0.0, hi = x(p);
            if (!(excess(hi) >= 0.0)) continue;  // inside at the joint onset: touches later
            for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
                const double mid = 0.5 * (lo + hi);
                (excess(mid) < 0.0 ? lo : hi) = mid;
            }
            if (lo * a_ref < out.static_amplitude) {
                out.static_amplitude = lo * a_ref;
                out.static_contact = static_cast<int>(members[i].contact);
            }
        }
    }
    if (out.found && out.static_contact < 0) {
        out.static_amplitude = out.amplitude;
        out.static_contact = out.contact;
    }
    if (out.found) {
        out.amplitude_min = out.amplitude / 10.0;
        out.amplitude_max = out.amplitude * 100.0;
    } else {
        out.why = skipped.empty() ? "no contact has a friction limit (force elements alone)" : skipped;
    }
    return out;
}

}  // namespace hbf
