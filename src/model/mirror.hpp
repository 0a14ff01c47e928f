// hbfriction — internal to the model layer: a mirror symmetry of a System (a reflection of its
// DOFs that leaves the structure, its loads and its contacts unchanged), and how far a state is
// from its mirror image.
//
// A mirror is a signed permutation P of the DOFs, (P y)[image[i]] = sign[i] y[i], with P P = I,
// P^T M P = M, P^T C P = C, P^T K P = K, P F = F, P F_s = F_s, and a permutation of the contacts
// (contact c onto contact_image[c]) whose directions P carries onto the image's (of the same
// length), the tangential ones up to their sign (Coulomb's cone is isotropic: direction_sign),
// the normal one exactly, with every other parameter equal. The identity is not one. Such a structure has symmetric orbits (P x(t) =
// x(t)); where contacts of a symmetric pair change pattern at one instant the period map is only
// piecewise differentiable off the symmetric states.
//
// find_mirror looks for one among the signed permutations that pair DOFs of equal diagonal
// entries and equal sorted rows of |M|, |K|, |C| (each DOF with one other or with itself), the
// signs propagated along K's, M's and C's couplings and fixed by the excitation; it returns none
// where a DOF has more than one candidate partner (more than one symmetry) or the check fails.
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <vector>

#include "hbf/model.hpp"

namespace hbf::detail {

struct Mirror {
    std::vector<int> image;          ///< DOF i's image (image[image[i]] = i)
    std::vector<double> sign;        ///< +1 or -1: (P y)[image[i]] = sign[i] y[i]
    std::vector<int> contact_image;  ///< contact c's image
    /// Per contact, per direction (its columns in System::contact_directions): P carries
    /// direction k of contact c onto direction_sign[c][k] times direction k of its image (the
    /// normal one: +1), so that the image's relative displacements are q_c'(P y) = sign q_c(y).
    std::vector<std::vector<double>> direction_sign;

    /// P y.
    Eigen::VectorXd apply(const Eigen::VectorXd& y) const;
    /// Pairs of DOFs swapped (i < image[i]).
    int swapped_pairs() const;
};

/// The system's mirror symmetry, or none; entries compared to `tolerance` relative to each
/// matrix's (vector's) largest entry.
std::optional<Mirror> find_mirror(const System& system, double tolerance = 1e-10);

/// max_i |(P y)_i - y_i|: a state's distance from its mirror image (0: symmetric).
double mirror_offset(const Mirror& mirror, const Eigen::VectorXd& y);

}  // namespace hbf::detail
