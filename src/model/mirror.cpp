// hbfriction — a mirror symmetry of a System, and a state's distance from its mirror image
// (mirror.hpp).
#include "model/mirror.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

namespace hbf::detail {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// A matrix over its largest entry (itself where that is zero).
MatrixXd normalized(const SparseMatrix& a, int n) {
    MatrixXd d = a.size() == 0 ? MatrixXd::Zero(n, n) : MatrixXd(a);
    const double largest = d.size() > 0 ? d.cwiseAbs().maxCoeff() : 0.0;
    return largest > 0.0 ? MatrixXd(d / largest) : d;
}

VectorXd normalized(const VectorXd& v, int n) {
    if (v.size() == 0) return VectorXd::Zero(n);
    const double largest = v.cwiseAbs().maxCoeff();
    return largest > 0.0 ? VectorXd(v / largest) : v;
}

/// DOF i's entries that any mirror keeps: the diagonal entries, |F_i|, |F_s,i| and the sorted
/// magnitudes of its rows.
std::vector<double> fingerprint(const std::vector<MatrixXd>& matrices, const VectorXd& f, const VectorXd& s, int i) {
    std::vector<double> out;
    for (const MatrixXd& a : matrices) out.push_back(a(i, i));
    out.push_back(std::abs(f(i)));
    out.push_back(std::abs(s(i)));
    for (const MatrixXd& a : matrices) {
        std::vector<double> row(static_cast<std::size_t>(a.cols()));
        for (Eigen::Index j = 0; j < a.cols(); ++j) row[static_cast<std::size_t>(j)] = std::abs(a(i, j));
        std::sort(row.begin(), row.end());
        out.insert(out.end(), row.begin(), row.end());
    }
    return out;
}

bool same(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
        if (std::abs(a[k] - b[k]) > tolerance) return false;
    return true;
}

bool near(double a, double b, double tolerance) {
    return std::abs(a - b) <= tolerance * std::max({1.0, std::abs(a), std::abs(b)});
}

/// Whether two contacts have the same parameters (directions aside: lists of N entries).
bool same_parameters(const Contact& a, const Contact& b, int n, double tolerance) {
    if (a.law != b.law || !near(a.friction_limit, b.friction_limit, tolerance) || !near(a.stiffness, b.stiffness, tolerance) ||
        !near(a.damping, b.damping, tolerance) || !near(a.viscous, b.viscous, tolerance) ||
        !near(a.static_limit, b.static_limit, tolerance) || !near(a.stribeck_velocity, b.stribeck_velocity, tolerance) ||
        !near(a.regularization, b.regularization, tolerance) ||
        !near(a.lagrangian_penalty, b.lagrangian_penalty, tolerance) || !near(a.base_motion, b.base_motion, tolerance))
        return false;
    if (a.values.size() != b.values.size() || a.lists.size() != b.lists.size() || a.tables.size() != b.tables.size())
        return false;
    for (const auto& [key, value] : a.values) {
        const auto other = b.values.find(key);
        if (other == b.values.end() || !near(value, other->second, tolerance)) return false;
    }
    for (const auto& [key, list] : a.lists) {
        const auto other = b.lists.find(key);
        if (other == b.lists.end() || other->second.size() != list.size()) return false;
        if (static_cast<int>(list.size()) == n) continue;  // a direction: compared by the caller
        for (std::size_t k = 0; k < list.size(); ++k)
            if (!near(list[k], other->second[k], tolerance)) return false;
    }
    for (const auto& [key, table] : a.tables) {
        const auto other = b.tables.find(key);
        if (other == b.tables.end() || other->second.rows() != table.rows() || other->second.cols() != table.cols())
            return false;
        for (Eigen::Index k = 0; k < table.size(); ++k)
            if (!near(table.data()[k], other->second.data()[k], tolerance)) return false;
    }
    return true;
}

}  // namespace

VectorXd Mirror::apply(const VectorXd& y) const {
    VectorXd out(y.size());
    for (std::size_t i = 0; i < image.size(); ++i) out(image[i]) = sign[i] * y(static_cast<Eigen::Index>(i));
    return out;
}

int Mirror::swapped_pairs() const {
    int pairs = 0;
    for (std::size_t i = 0; i < image.size(); ++i) pairs += image[i] > static_cast<int>(i);
    return pairs;
}

std::optional<Mirror> find_mirror(const System& system, double tolerance) {
    const int n = system.dofs();
    if (n == 0 || system.cyclic.active()) return std::nullopt;
    const std::vector<MatrixXd> matrices = {normalized(system.mass, n), normalized(system.stiffness, n),
                                            normalized(system.damping, n)};
    const VectorXd f = normalized(system.excitation, n), s = normalized(system.static_load, n);

    // Each DOF's partner: the one other DOF of its fingerprint, or itself.
    std::vector<std::vector<double>> prints;
    for (int i = 0; i < n; ++i) prints.push_back(fingerprint(matrices, f, s, i));
    Mirror mirror;
    mirror.image.assign(static_cast<std::size_t>(n), -1);
    for (int i = 0; i < n; ++i) {
        std::vector<int> partners;
        for (int j = 0; j < n; ++j)
            if (j != i && same(prints[static_cast<std::size_t>(i)], prints[static_cast<std::size_t>(j)], tolerance))
                partners.push_back(j);
        if (partners.size() > 1) return std::nullopt;  // more than one symmetry: not chosen here
        mirror.image[static_cast<std::size_t>(i)] = partners.empty() ? i : partners.front();
    }
    for (int i = 0; i < n; ++i)
        if (mirror.image[static_cast<std::size_t>(mirror.image[static_cast<std::size_t>(i)])] != i) return std::nullopt;

    // The signs: sign_i sign_j A(image_i, image_j) = A(i, j) along every coupling, and a DOF's
    // sign its image's (P P = I); each connected set of DOFs from one sign, flipped where the
    // loads ask for it.
    const auto image = [&](int i) { return mirror.image[static_cast<std::size_t>(i)]; };
    std::vector<int> sign(static_cast<std::size_t>(n), 0), component(static_cast<std::size_t>(n), -1);
    int components = 0;
    for (int seed = 0; seed < n; ++seed) {
        if (sign[static_cast<std::size_t>(seed)] != 0) continue;
        sign[static_cast<std::size_t>(seed)] = 1;
        component[static_cast<std::size_t>(seed)] = components;
        std::deque<int> queue{seed};
        while (!queue.empty()) {
            const int i = queue.front();
            queue.pop_front();
            auto assign = [&](int j, int value) {
                if (sign[static_cast<std::size_t>(j)] == 0) {
                    sign[static_cast<std::size_t>(j)] = value;
                    component[static_cast<std::size_t>(j)] = components;
                    queue.push_back(j);
                    return true;
                }
                return sign[static_cast<std::size_t>(j)] == value;
            };
            if (!assign(image(i), sign[static_cast<std::size_t>(i)])) return std::nullopt;
            for (int j = 0; j < n; ++j) {
                if (j == i) continue;
                double coupling = 0.0, imaged = 0.0;
                for (const MatrixXd& a : matrices)
                    if (std::abs(a(i, j)) > std::abs(coupling)) {
                        coupling = a(i, j);
                        imaged = a(image(i), image(j));
                    }
                if (std::abs(coupling) <= tolerance) continue;
                const double ratio = imaged / coupling;
                if (std::abs(ratio - 1.0) > 1e-6 && std::abs(ratio + 1.0) > 1e-6) return std::nullopt;
                if (!assign(j, ratio > 0.0 ? sign[static_cast<std::size_t>(i)] : -sign[static_cast<std::size_t>(i)]))
                    return std::nullopt;
            }
        }
        ++components;
    }
    for (int c = 0; c < components; ++c) {
        bool keep = true, flip = true;
        for (int i = 0; i < n; ++i) {
            if (component[static_cast<std::size_t>(i)] != c) continue;
            for (const VectorXd* load : {&f, &s}) {
                const double a = (*load)(i), b = (*load)(image(i));
                keep = keep && std::abs(sign[static_cast<std::size_t>(i)] * a - b) <= tolerance;
                flip = flip && std::abs(-sign[static_cast<std::size_t>(i)] * a - b) <= tolerance;
            }
        }
        if (!keep && !flip) return std::nullopt;
        if (!keep)
            for (int i = 0; i < n; ++i)
                if (component[static_cast<std::size_t>(i)] == c) sign[static_cast<std::size_t>(i)] *= -1;
    }
    mirror.sign.assign(sign.begin(), sign.end());
    bool identity = true;
    for (int i = 0; i < n; ++i) identity = identity && image(i) == i && sign[static_cast<std::size_t>(i)] == 1;
    if (identity) return std::nullopt;

    // The check: the matrices and loads entry by entry.
    for (const MatrixXd& a : matrices)
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                if (std::abs(mirror.sign[static_cast<std::size_t>(i)] * mirror.sign[static_cast<std::size_t>(j)] *
                                 a(image(i), image(j)) -
                             a(i, j)) > tolerance)
                    return std::nullopt;
    if ((mirror.apply(f) - f).cwiseAbs().maxCoeff() > tolerance || (mirror.apply(s) - s).cwiseAbs().maxCoeff() > tolerance)
        return std::nullopt;

    // The contacts: each onto one whose directions P carries onto its own (tangential ones up
    // to their sign, the normal one exactly) and whose parameters are its own.
    const std::size_t nc = system.contacts.size();
    mirror.contact_image.assign(nc, -1);
    std::vector<MatrixXd> directions;
    for (const Contact& contact : system.contacts) directions.push_back(system.contact_directions(contact));
    double largest = 0.0;  // the directions' scale
    for (const MatrixXd& d : directions) largest = std::max(largest, d.cwiseAbs().maxCoeff());
    if (largest > 0.0)
        for (MatrixXd& d : directions) d /= largest;
    mirror.direction_sign.assign(nc, {});
    for (std::size_t c = 0; c < nc; ++c) {
        const Contact& contact = system.contacts[c];
        const bool normal = contact.lists.count("normal_direction") > 0;
        MatrixXd moved(directions[c].rows(), directions[c].cols());
        for (Eigen::Index k = 0; k < moved.cols(); ++k) moved.col(k) = mirror.apply(directions[c].col(k));
        for (std::size_t o = 0; o < nc && mirror.contact_image[c] < 0; ++o) {
            if (directions[o].cols() != moved.cols() || !same_parameters(contact, system.contacts[o], n, tolerance)) continue;
            bool match = true;
            std::vector<double> signs;
            for (Eigen::Index k = 0; k < moved.cols() && match; ++k) {
                const bool last_normal = normal && k == moved.cols() - 1;
                if ((moved.col(k) - directions[o].col(k)).cwiseAbs().maxCoeff() <= tolerance) {
                    signs.push_back(1.0);
                } else {
                    match = !last_normal && (moved.col(k) + directions[o].col(k)).cwiseAbs().maxCoeff() <= tolerance;
                    signs.push_back(-1.0);
                }
            }
            if (match) {
                mirror.contact_image[c] = static_cast<int>(o);
                mirror.direction_sign[c] = std::move(signs);
            }
        }
        if (mirror.contact_image[c] < 0) return std::nullopt;
    }
    for (std::size_t c = 0; c < nc; ++c)
        if (mirror.contact_image[static_cast<std::size_t>(mirror.contact_image[c])] != static_cast<int>(c)) return std::nullopt;
    return mirror;
}

double mirror_offset(const Mirror& mirror, const Eigen::VectorXd& y) {
    return y.size() == 0 ? 0.0 : (mirror.apply(y) - y).cwiseAbs().maxCoeff();
}

}  // namespace hbf::detail
