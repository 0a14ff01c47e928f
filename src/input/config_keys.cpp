// hbfriction — the keys of a system file (config.hpp: config_keys), one table that the reader
// checks every key against and the reference documentation is generated from.

#include <stdexcept>

#include "hbf/config.hpp"

namespace hbf::io {

const std::vector<ConfigKey>& config_keys() {
    static const std::vector<ConfigKey> keys = {
        {"", "structure", "table [structure]: the linear structure (required)"},
        {"", "contact", "tables [[contact]]: one per contact or force element"},
        {"", "interface", "tables [[interface]]: a meshed contact interface, one contact per node"},
        {"", "frequency", "table [frequency]: the frequency range"},
        {"", "solver", "table [solver]: harmonic-balance settings"},
        {"", "output", "table [output] (DOFs to report) or tables [[output]] (linear combinations of DOFs)"},
        {"", "reduction", "table [reduction]: reduce the finite-element model of [structure] onto its interface"},
        {"", "cyclic", "table [cyclic]: the model is one sector of a cyclically symmetric wheel under an engine-order excitation (with [reduction]: the cut faces and the contacts' neighbour DOFs kept physical)"},

        {"structure", "mass", "mass matrix M, N x N: rows, a flat list (diagonal) or a Matrix Market file; may be singular (massless DOFs), must be positive semi-definite (required)"},
        {"structure", "stiffness", "stiffness matrix K, N x N, as mass (required)"},
        {"structure", "damping", "damping matrix C, N x N, as mass (default: none)"},
        {"structure", "excitation", "force amplitude vector F of F cos(h w t): N numbers or an N x 1 Matrix Market file (required)"},
        {"structure", "excitation_harmonic", "h, the harmonic of the response's fundamental w at which the force acts, 1..100 (default 1)"},
        {"structure", "static_load", "constant load F_s: N numbers or an N x 1 Matrix Market file (default: none)"},
        {"structure", "fixed", "clamped DOFs (1-based list or N x 1 Matrix Market file): zero displacement, their rows and columns of M, C, K removed; every other key keeps the file's numbering (default: none)"},

        {"cyclic", "sectors", "N, the number of identical sectors of the wheel, >= 2 (required)"},
        {"cyclic", "engine_order", "EO: sector j is forced by F cos(w t - 2 pi EO j / N); 0..N-1, a larger one taken as EO mod N (required)"},
        {"cyclic", "left", "the left cut face: DOFs of this sector (1-based list), matched with right (default: none)"},
        {"cyclic", "right", "the right cut face: right[i] is the next sector's left[i] (1-based list of the same length, disjoint from left)"},

        {"contact", "law", "the contact law or force element (see the contact laws' reference; required)"},
        {"contact", "dof", "DOF a of the relative displacement q = y_a - y_b (1-based)"},
        {"contact", "other_dof", "DOF b (1-based); omitted: against the ground"},
        {"contact", "neighbour_dof", "instead of other_dof, in a sector model: the next sector's DOF (1-based, in this sector's numbering) the contact joins to dof across the cut"},
        {"contact", "force_direction", "instead of dof and other_dof: any direction w, q = w^T y (N numbers or an N x 1 Matrix Market file)"},
        {"contact", "friction_limit", "slip force F_c = mu N of the friction laws, > 0"},

        {"interface", "name", "the interface's name in messages and columns"},
        {"interface", "nodes", "each node's FE DOFs (1-based): [[x, y, z], ...] or an n x 3 (2D: n x 2) Matrix Market file (required)"},
        {"interface", "normal", "the closing direction n: one unit vector for all nodes (3 numbers; 2D: 2), or one row per node (required)"},
        {"interface", "tangent", "the first tangent t1, a unit vector orthogonal to n: one for all nodes or one row per node (3D; default: automatic)"},
        {"interface", "area", "each node's area, > 0: one number for all nodes or one per node (default 1)"},
        {"interface", "law", "elastic or unilateral: a law with a normal direction (required)"},
        {"interface", "preload_pressure", "normal pressure at zero displacement; each node's preload is it times the node's area"},

        {"frequency", "wmin", "first frequency of the branch, > 0"},
        {"frequency", "wmax", "last frequency of the branch, > wmin (= wmin: one point, solved from a cold start)"},

        {"solver", "harmonics", "number of harmonics H, 1..100 (default: the laws' own)"},
        {"solver", "time_samples", "AFT time samples per period N_t > 2H (0: automatic)"},
        {"solver", "modes", "condensed formulation: 0 solves the structure directly, m > 0 uses m modes and the static residual flexibility"},
        {"solver", "odd_harmonics", "true: balance the odd harmonics only (half-wave symmetric solutions)"},
        {"solver", "jacobian", "dense, structured or automatic: how the corrector holds the Jacobian"},

        {"output", "report", "the DOFs reported (1-based), default: the excited DOFs and the contacts' DOFs"},

        {"output[]", "name", "the output's name: its columns are <name>_max and <name>_amp1"},
        {"output[]", "dof", "a DOF (1-based), named y<i> unless a name is given"},
        {"output[]", "row", "c of o = c^T y: N numbers or a Matrix Market row or column"},

        {"reduction", "modes", "normal modes kept (required; 0: static condensation)"},
        {"reduction", "method", "craig-bampton (default), massless-boundary or macneal"},
        {"reduction", "interface", "FE DOFs kept as coordinates (1-based list or N x 1 Matrix Market file); default: the DOFs the contacts act on"},
        {"reduction", "damping_ratios", "modal damping ratios of the reduced model's modes (the last repeated)"},
        {"reduction", "rayleigh", "[a, b]: C = a M_r + b K_r on the reduced model"},
        {"reduction", "retain_loads", "true (default): the DOFs the excitation and static load act on are kept as coordinates (statically exact; with massless-boundary they lose their mass); false: only the interface is kept and those loads are projected onto the modes"},
    };
    return keys;
}

std::set<std::string> config_keys_of(const std::string& table) {
    std::set<std::string> keys;
    for (const ConfigKey& k : config_keys())
        if (table == k.table) keys.insert(k.key);
    if (keys.empty()) throw std::logic_error("config_keys_of: no table '" + table + "'");
    return keys;
}

}  // namespace hbf::io
