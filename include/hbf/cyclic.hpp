// hbfriction — cyclic symmetry: one sector of a wheel of N identical sectors (a bladed disk)
// under a travelling-wave (engine-order) excitation.
//
// The System is one sector, sector 0. Some of its DOFs belong to the next sector, sector 1:
// the right cut face (sector 1's left face) and any DOF of the neighbour that a spring or a
// contact of this sector reaches across the cut. Each such dependent DOF d is DOF m (its
// master, an independent DOF of this model) of sector 1. The wheel is the N sectors in a ring,
// sector j's dependent DOFs identified with sector j+1's masters (sector N is sector 0): its
// matrices are the sum of the sectors' and its contacts the sectors' contacts.
//
// Engine order EO (0..N-1): sector j is forced by F cos(omega t - j phi), phi = 2 pi EO / N.
// The tuned wheel's periodic responses of the same symmetry (travelling waves) have sector j
// moving as sector 0 delayed: y_j(t) = y_0(t - j phi / omega). A dependent DOF moves as its
// master delayed by phi / omega: harmonic k of d is harmonic k of m turned by k phi,
//     c_d = cos(k phi) c_m - sin(k phi) s_m,   s_d = sin(k phi) c_m + cos(k phi) s_m
// (complex amplitudes: Y_d,k = e^{-i k phi} Y_m,k, y = Re(Y e^{i k omega t})), and the equations
// of the independent DOFs are the wheel's: each dependent row folds onto its master, turned back
// (T_k^H). Per harmonic k the linear sector is T_k^H Z_k T_k, with T_k (N_sector x independent)
// the identity on the independent DOFs and e^{-i k phi} from a dependent DOF to its master:
// Hermitian, and the same for every k with the same harmonic index p = k EO mod N (the
// nodal-diameter family min(p, N - p) of the wheel's linear modes).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <utility>
#include <vector>

#include "hbf/model.hpp"

namespace hbf {

/// System::cyclic (model.hpp: CyclicSymmetry) checked against the model: throws InvalidInput
/// naming the field: N < 2, EO outside 0..N-1, a DOF outside the model, a dependent DOF listed
/// twice, a master that is itself dependent, a dependent DOF loaded by the excitation or the static
/// load (a DOF shared with the next sector carries its load on the master), an excitation
/// harmonic h > 1. Nothing when the model is not a sector.
void validate_cyclic(const System& system);

/// Throws InvalidInput "<what>: not available for a sector model (cyclic symmetry) ..." when
/// the system is a sector: the computations that do not take one call it.
void refuse_cyclic(const System& system, const std::string& what);

/// The independent DOFs of a sector model (every DOF but the dependent ones), ascending.
std::vector<int> independent_dofs(const System& system);

/// T for the phase `angle` (k phi for harmonic k): N_sector x independent, the identity on the
/// independent DOFs (in independent_dofs' order) and e^{-i angle} from a dependent DOF to its
/// master.
Eigen::MatrixXcd cyclic_transform(const System& system, double angle);

/// T at phase 0 (harmonic 0, or every harmonic of engine order 0), real and sparse: the sector
/// with each dependent DOF merged into its master, A0 = T0^T A T0 (its static structure).
SparseMatrix cyclic_merge(const System& system);

/// The wheel's linear natural frequencies by nodal diameter: for each nodal diameter
/// d = 0..floor(N / 2), the sector's eigenfrequencies sqrt(lambda) of (T^H K T, T^H M T) at
/// harmonic index d (the wheel's mode pairs of indices d and N - d share them). `stuck`: every
/// contact replaced by its stuck element (static_state.hpp: stuck_elements; a rigid contact
/// as a constraint), else released (the contacts removed).
struct NodalDiameterFamily {
    int sectors = 0;
    bool stuck = false;
    /// Row d: the frequencies of nodal diameter d, ascending (independent DOFs columns, fewer
    /// where rigid contacts constrain the sector: the rest NaN).
    Eigen::MatrixXd frequencies;
};
/// Largest sector (DOFs of its own) nodal_diameter_family takes: it solves dense eigenproblems.
constexpr int nodal_diameter_dof_limit = 2000;
/// M must be positive definite on the independent DOFs, at most nodal_diameter_dof_limit of them
/// (throws InvalidInput naming the reason).
NodalDiameterFamily nodal_diameter_family(const System& system, bool stuck);

/// The linear modes of a sector at the phase `angle` (harmonic index p: angle = 2 pi p / N;
/// the engine order's travelling waves: CyclicSymmetry::phase()), by ascending frequency: the
/// eigenpairs of (T^H K' T, T^H M T) on the sector's own DOFs, K' with every contact's stuck
/// element (`stuck`; a rigid one as a constraint) or without the contacts. The wheel moves in
/// sector j as y_j(t) = Re(phi e^{i (omega t - j angle)}), phi = T u on every DOF of the sector
/// (`shape`), u^H T^H M T u = 1 (the first entry of largest modulus real and positive). zeta =
/// u^H T^H C' T u / (2 omega), C' with the stuck elements' dampers (exact where C' is diagonal
/// in these modes, a first-order estimate otherwise). Throws as nodal_diameter_family.
struct SectorMode {
    int index = 0;  ///< 1-based, by ascending frequency
    double omega = 0;
    double zeta = 0;
    Eigen::VectorXcd own;    ///< u: the sector's own DOFs (independent_dofs' order)
    Eigen::VectorXcd shape;  ///< T u: every DOF of the sector
};
std::vector<SectorMode> sector_modes(const System& system, double angle, bool stuck);

/// The nodal diameter the response's harmonic k meets: min(p, N - p), p = k EO mod N.
int nodal_diameter(const CyclicSymmetry& cyclic, int harmonic);

/// ", engine order EO (nodal diameter d) of N sectors" for a sector, "" otherwise: plot titles.
std::string cyclic_label(const CyclicSymmetry& cyclic);

}  // namespace hbf
