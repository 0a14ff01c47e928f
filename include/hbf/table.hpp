// hbfriction — result tables: columns with their documentation, CSV writing, and the tables of
// every study (FRF, time integration, closed forms), shared by the command line and Python.
#pragma once

#include <iosfwd>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "hbf/absorber.hpp"
#include "hbf/analytic.hpp"
#include "hbf/interface.hpp"
#include "hbf/continuation.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/post_processing.hpp"
#include "hbf/stability.hpp"
#include "hbf/static_state.hpp"
#include "hbf/time_integration.hpp"

namespace hbf::io {

/// A CSV field: shortest round-trip decimal, or empty when there is no value.
std::string csv_field(const std::optional<double>& value);

/// What a column holds: numbers (doubles), integers (counts, branch numbers) or words.
enum class ColumnType { number, integer, text };

/// A column of a table: its CSV name, what it means (for --help and the Python bindings) and
/// its type.
struct Column {
    std::string name;
    std::string meaning;
    ColumnType type = ColumnType::number;
};

/// One value of a table: none (an empty CSV field), a number, an integer or a word.
using Cell = std::variant<std::monostate, double, long long, std::string>;

/// A table of results, column by column: cells[j][k] is row k of columns[j]. The one source of
/// both the CSV files of the commands and the arrays of the Python bindings.
struct Table {
    Table() = default;
    /// A table of these columns and no rows (cells holds one empty list per column).
    explicit Table(std::vector<Column> columns_) : columns(std::move(columns_)), cells(columns.size()) {}
    std::vector<Column> columns;
    std::vector<std::vector<Cell>> cells;  ///< one list per column (or none at all: no rows)
    std::size_t rows() const { return cells.empty() ? 0 : cells.front().size(); }
    /// Appends one row (one cell per column, in order).
    void add_row(std::vector<Cell> row);
};

/// The header row and one line per row; numbers by format_number (15 significant digits),
/// integers and words as they are, none as an empty field.
void write_csv(std::ostream& out, const Table& table);

/// Column names and meanings of the analytic table, in order (used by the header and --help).
const std::vector<Column>& analytic_columns();

/// The analytic table (analytic_columns), one row per frequency.
Table analytic_table(const std::vector<analytic::Row>& rows);
/// Writes the header row and one row per frequency.
void write_analytic_csv(std::ostream& out, const std::vector<analytic::Row>& rows);

/// Columns of `hbf nodal-diameters` (cyclic.hpp: the wheel's nodal-diameter families).
const std::vector<Column>& nodal_diameter_columns();
/// The nodal-diameter families of a sector (cyclic.hpp: nodal_diameter_family), released and
/// stuck, one row per nodal diameter and mode, with the harmonics 1..`harmonics` of a response to
/// `cyclic`'s engine order that meet each nodal diameter.
Table nodal_diameter_table(const CyclicSymmetry& cyclic, const NodalDiameterFamily& released,
                           const NodalDiameterFamily& stuck, int harmonics);
/// Columns of `hbf frf` reporting `outputs` (model.hpp; in this order: `<name>_max` for each,
/// then `<name>_amp1` for each; a DOF i is the output `y<i+1>`), or all `dofs` DOFs. With several
/// `contacts`, `stick_fraction_c<i>` and `regime_c<i>` for each contact i replace stick_fraction
/// and regime (the tables count the contacts of their rows). For each contact i (0-based) in
/// `normal` (those with a normal direction: laws elastic, unilateral), separated_fraction, normal_force_mean
/// and normal_force_amp (suffixed `_c<i+1>` with several contacts) follow the regimes, and with
/// several contacts `energy_c<i+1>` of every contact follows energy. For each meshed interface k
/// (1-based, `interfaces`: its nodes' contacts), `stuck_share_i<k>`, `slip_share_i<k>` and
/// `open_share_i<k>` (its nodes' period shares, averaged over the nodes) come before energy.
std::vector<Column> frf_columns(const std::vector<Output>& outputs, int contacts = 1,
                                const std::vector<int>& normal = {},
                                const std::vector<InterfaceContacts>& interfaces = {});
/// The contacts of `system` with a normal direction (friction contacts whose
/// System::contact_directions has more than one column), 0-based: frf_columns' `normal`.
std::vector<int> normal_contacts(const System& system);
std::vector<Column> frf_columns(int dofs);

/// An interface's node-averaged period shares at one point (frf_table's `*_share_i<k>` columns,
/// hbf frf --plot-contacts): stuck (mean stick_fraction), open (mean separated_fraction, 0 for
/// laws without a normal direction) and slipping = 1 - stuck - open. Empty when a contact's
/// stick fraction is unknown (NaN) or the group has no contacts.
struct InterfaceShares {
    double stuck = 0.0, slipping = 0.0, open = 0.0;
};
std::optional<InterfaceShares> interface_shares(const PointMetrics& metrics, const InterfaceContacts& group);
/// The same from every contact's regime (PointMetrics::contacts, PeriodicResponse::contacts).
std::optional<InterfaceShares> interface_shares(const std::vector<ContactRegime>& contacts, const InterfaceContacts& group);

/// The table of `hbf frf` (frf_columns(outputs)), one row per point (metrics[k] and exact[k]
/// belong to points[k]; as write_frf_csv below).
Table frf_table(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics,
                const std::vector<Output>& outputs, const std::vector<ExactPoint>& exact = {},
                const BranchStability* stability = nullptr, const std::vector<InterfaceContacts>& interfaces = {});

/// Writes the header row and one row per point (metrics[k] and exact[k] belong to points[k];
/// metrics[k].output_max[j] and output_amp1[j] belong to outputs[j]; `exact` empty: no
/// polish, the columns exact = off, stable and hb_gap empty).
void write_frf_csv(std::ostream& out, const std::vector<SolutionPoint>& points,
                   const std::vector<PointMetrics>& metrics, const std::vector<Output>& outputs,
                   const std::vector<ExactPoint>& exact = {}, const BranchStability* stability = nullptr,
                   const std::vector<InterfaceContacts>& interfaces = {});

/// Columns of `hbf timeint` for a system with `dofs` DOFs: the `hbf frf` columns that apply
/// (w, `y<i>_max`, `y<i>_amp1`, stick_fraction, regime, the interfaces' shares, energy), then
/// periods, converged and the diagnostics stick_margin_min, stick_margin_max, switches.
std::vector<Column> timeint_columns(int dofs);
/// The same for `outputs` (in this order; as frf_columns(outputs)).
std::vector<Column> timeint_columns(const std::vector<Output>& outputs, int contacts = 1,
                                    const std::vector<int>& normal = {},
                                    const std::vector<InterfaceContacts>& interfaces = {});

/// The table of `hbf timeint` (timeint_columns(outputs)), one row per response; a response
/// without a single integrated period has empty numbers and regime failed.
Table timeint_table(const std::vector<PeriodicResponse>& responses, const std::vector<Output>& outputs,
                    const std::vector<InterfaceContacts>& interfaces = {});

/// Writes the header row and one row per response (time-integration steady states), with the
/// columns of `outputs` (r.output_max[j] and r.output_amp1[j] belong to outputs[j]: the
/// integration ran with TimeIntegrationOptions::outputs = outputs) and the shares of each
/// interface (stuck_share_i<k>, slip_share_i<k>, open_share_i<k>, as hbf frf's).
void write_timeint_csv(std::ostream& out, const std::vector<PeriodicResponse>& responses,
                       const std::vector<Output>& outputs, const std::vector<InterfaceContacts>& interfaces = {});

/// The "parameters" of an FRF's JSON summary: the preset's (r, wa, mu, fe, wb, xi, eps,
/// mu_static, stribeck_velocity, viscous) with `preset`, else the model's size (dofs,
/// contacts); then the solver's (wmin, wmax, harmonics, excitation_harmonic, odd_harmonics,
/// time_samples, condensed, modes, max_amplitude, tolerance) from `hb` and `continuation`.
std::vector<std::pair<std::string, double>> frf_parameters(const System& system, const AbsorberParameters* preset,
                                                           const HarmonicBalance& hb,
                                                           const ContinuationOptions& continuation);

/// Writes the JSON summary of an FRF run: the parameters (name, value; integral values are
/// written as integers), the number of branch points and samples, solver statistics, the
/// peaks (of the outputs `outputs`, Peak::output indexing them: each with w, output (its
/// name), dof (1-based, for an output that is one DOF), y_max (= max over one period of
/// |o(t)|), branch, refined), the folds (w, `<name>_max` of every output, branch), the
/// stick-slip transitions (the same, and between: the regimes on either side), status,
/// message and wall time.
/// `metrics[k]` belongs to `branch.points[k]`; `samples` counts the --at rows. With `polish`
/// (the exact polish of the branch), folds and transitions are read from its points and
/// metrics, and an "exact" object reports the polish (counts, largest HB gap, time). With
/// `stability` (one result per point), a "stability" object gives the counts, the unstable
/// intervals (w_from, w_to, branch) and the bifurcations (kind, w, branch).
void write_frf_summary(std::ostream& out, const std::string& law,
                       const std::vector<std::pair<std::string, double>>& parameters, const BranchResult& branch,
                       const std::vector<PointMetrics>& metrics, const std::vector<Peak>& peaks, std::size_t samples,
                       double wall_seconds, const std::vector<Output>& outputs,
                       const PolishedBranch* polish = nullptr, const std::vector<std::string>& errors = {},
                       const std::vector<std::string>& warnings = {},
                       const std::vector<std::string>& notes = {},
                       const BranchStability* stability = nullptr,
                       const StaticState* static_state = nullptr);

}  // namespace hbf::io
