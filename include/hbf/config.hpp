// hbfriction — general systems from a TOML file (`hbf frf --config system.toml`).
//
// The file describes any N-DOF structure M y'' + C y' + K y + sum_c w_c f_c = F cos(h w t)
// (model.hpp) in any consistent units:
//
//     [structure]
//     mass       = [[1.0, 0.0], [0.0, 0.1]]   # N x N rows; a flat list [1.0, 0.1] is diagonal;
//     stiffness  = "stiffness.mtx"            # or a Matrix Market file beside this one (read
//                                             # sparse; M may be singular: massless DOFs)
//     damping    = [0.0, 0.0]                 # optional: zero
//     excitation = [0.5, 0.0]                 # F, amplitude of F cos(h w t) (or an N x 1 .mtx)
//     excitation_harmonic = 1                 # optional: h, 1..100 (default 1): the force acts
//                                             # at h w, w the response's fundamental (h = 2:
//                                             # subharmonic response of order 1/2); HB needs H >= h
//     static_load = [0.0, 0.1]                # optional: F_s, a constant load (N numbers or an
//                                             # N x 1 .mtx): HB's harmonic 0, the static contact
//                                             # state (static_state.hpp)
//
//     [[contact]]                 # one table per friction contact, any number
//     dof = 1                     # DOF a (1-based)
//     other_dof = 2               # DOF b (1-based); omitted: against the ground
//     # force_direction = [0.0, 1.0, -1.0]  # instead of dof / other_dof: any direction w
//                                 # (N numbers or an N x 1 .mtx); q = w^T y
//     law = "coulomb"             # coulomb, jenkins, dahl, lugre, coulomb-reg
//     friction_limit = 0.2        # F_c = mu N
//     stiffness = 0.016           # sigma0 (dahl, lugre) or k_t (jenkins)
//     damping = 0.0               # sigma1 (lugre)
//     viscous = 0.0               # sigma2 (lugre)
//     static_limit = 0.0          # F_s (lugre; 0 means F_c)
//     stribeck_velocity = 0.0     # v_s (lugre; 0 means none)
//     regularization = 0.05       # eps of tanh (coulomb-reg)
//     lagrangian_penalty = 0.0    # dynamic Lagrangian eps (coulomb; 0 = automatic)
//
//     [frequency]                 # optional; command-line flags override
//     wmin = 0.5
//     wmax = 1.6
//
//     [solver]                    # optional; command-line flags override
//     harmonics = 20
//     time_samples = 0
//     odd_harmonics = false       # true: balance the odd harmonics 1, 3, ... <= H only (half-wave
//                                 # symmetric solutions: half the unknowns; needs an odd
//                                 # excitation_harmonic)
//     modes = 0                   # condensed HB: 0 solves the structure directly (sparse LU),
//                                 # m > 0 uses m modes + static residual flexibility
//                                 # (cost independent of N; M > 0, K > 0, C modal)
//     jacobian = "automatic"      # dense | structured (harmonic_balance.hpp, JacobianForm):
//                                 # structured keeps I + G Df in its block structure and solves
//                                 # Newton steps by preconditioned GMRES (interfaces of many
//                                 # nodes; condensed, memoryless laws, every harmonic);
//                                 # automatic: structured above 1500 unknowns where allowed
//
//     [output]
//     report = [1, 2]             # DOFs written as y<i>_max, y<i>_amp1 (1-based); default: the
//                                 # excited DOFs and the contacts' DOFs (all N would make a
//                                 # large model as slow as its output count)
//
//     # or, instead of [output], any outputs o(t) = c^T y(t), in order (the two forms exclude
//     # each other: TOML has either a table [output] or tables [[output]]):
//     [[output]]
//     name = "tip"                # columns tip_max (max over one period of |o(t)|), tip_amp1,
//                                 # and JSON peaks of "tip"
//     row = [0.0, 0.5, 0.5]       # c: N numbers, or a Matrix Market vector (a row or a column)
//     [[output]]
//     dof = 1                     # a DOF (1-based), named y1 unless a name is given
//
//     [reduction]                 # optional: [structure] is an FE model, reduced onto its
//                                 # interface before anything else (reduction.hpp); contacts,
//                                 # loads and outputs stay on FE DOFs (1-based)
//     interface = [101, 102, 103] # DOFs kept as coordinates (a list or an N x 1 .mtx of
//                                 # 1-based DOFs); default: the DOFs the contacts act on. The
//                                 # loaded DOFs are kept too (statics exact)
//     modes = 20                  # normal modes kept (fixed-interface; macneal: free)
//     method = "craig-bampton"    # or "massless-boundary" (CBMB: massless interface), "macneal"
//     damping_ratios = [0.01]     # optional: modal ratios of the reduced model's modes (the
//                                 # last repeated); or rayleigh = [a, b]: C = a M_r + b K_r;
//                                 # default: [structure] damping projected (T^T C T)
//
// Contact keys that do not apply to the contact's law are rejected, as are unknown keys and
// tables: a misspelt key is an error, not a silent default. Every error names the file, the
// line and the key.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hbf/frf.hpp"
#include "hbf/interface.hpp"
#include "hbf/model.hpp"
#include "hbf/output_file.hpp"
#include "hbf/reduction.hpp"

namespace hbf::io {

struct SystemConfig {
    System system;
    /// [frequency] wmin, wmax (omega_start, omega_end) and [solver] harmonics, time_samples,
    /// modes, odd_harmonics, jacobian as given, each unset where not: the FRF's choices
    /// (frf.hpp: frf_settings), for hbf and Python alike.
    FrfChoices choices;
    /// The reported outputs in file order: [output] report's DOFs, or the [[output]] tables;
    /// default the excited DOFs and those of the contacts, in DOF order (every DOF when there
    /// are none), with outputs_note saying so when that leaves DOFs out.
    std::vector<Output> outputs;
    std::string outputs_note;
    /// The files read: the config itself ("--config"), then every Matrix Market file it names
    /// (by its key, e.g. "structure.stiffness").
    std::vector<InputFile> inputs;
    /// The line of each [frequency] and [solver] key given ("solver.time_samples" -> 12), for
    /// front ends whose checks depend on other settings (time_samples > 2H) to name it.
    std::map<std::string, int> lines;
    /// [reduction]: the FE model's reduction (system is then the reduced one; outputs are
    /// rows of its recovery matrix); null without [reduction].
    std::shared_ptr<const ReducedModel> reduction;
    /// The [[interface]] tables' contacts in system.contacts (after the [[contact]] tables').
    std::vector<InterfaceContacts> interfaces;
};

/// Reads and validates a system file (see above). Throws InvalidInput with
/// "FILE:LINE: key 'K': ..." on any error (syntax, type, size, range, unknown key).
SystemConfig read_system_config(const std::string& path);

/// Reads a Matrix Market file ("%%MatrixMarket matrix coordinate|array real|integer
/// general|symmetric") as a sparse matrix (a coordinate file is never densified; a symmetric
/// file gives one triangle, mirrored). Every field is read whole: indices are integers, values
/// decimal numbers with an optional e, E, d or D exponent (hbf::parse_decimal: 1.0D-1 = 0.1
/// as Fortran prints it; a decimal comma, hexadecimal or trailing characters are refused);
/// the size line has exactly 3 fields (coordinate) or 2 (array), an entry line exactly 3 or
/// 1. Throws InvalidInput naming the file, line and field on any error: syntax, a field that
/// is not a number, a non-finite value, an index out of range, an entry given twice, data
/// beyond the announced entries.
SparseMatrix read_matrix_market(const std::string& path);

}  // namespace hbf::io
