// hbfriction — the tables (table.hpp): CSV columns with their meaning, the FRF, time-integration
// and analytic tables (the JSON summaries: summary.cpp).

#include "hbf/table.hpp"
#include "hbf/cyclic.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <iostream>
#include <limits>
#include <map>
#include <stdexcept>

#include "hbf/absorber.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"

namespace hbf::io {

std::string csv_field(const std::optional<double>& value) {
    return value ? format_number(*value) : std::string();
}

const std::vector<Column>& analytic_columns() {
    static const std::vector<Column> columns = {
        {"w", "excitation frequency omega = Omega / omega1 (nondimensional)"},
        {"y1_stick", "|Y1|, amplitude of y1 = x1 / x_s in full stick (law's stick model)"},
        {"y2_stick", "|Y2|, amplitude of y2 = x2 / x_s in full stick"},
        {"y1_slip", "|Y1| in full slip, equivalent viscous (one-harmonic) solution; empty if none exists"},
        {"y2_slip", "|Y2| in full slip; empty if no slipping solution exists"},
        {"mu_limit", "limit friction coefficient of the law: full stick (pre-sliding for dahl, lugre) iff "
                     "mu >= mu_limit; "
                     "also the minimum-displacement (Ricciardelli-Vickery) coefficient"},
        {"mu_opt_den_hartog", "mu whose equivalent viscous damping equals Den Hartog's optimum, "
                              "for the Den Hartog design wa = 1/(1+r)"},
    };
    return columns;
}

void Table::add_row(std::vector<Cell> row) {
    if (cells.empty()) cells.resize(columns.size());
    if (row.size() != columns.size())
        throw std::logic_error("Table::add_row: " + std::to_string(row.size()) + " cells for " +
                               std::to_string(columns.size()) + " columns");
    for (std::size_t j = 0; j < row.size(); ++j) cells[j].push_back(std::move(row[j]));
}

void write_csv(std::ostream& out, const Table& table) {
    for (std::size_t j = 0; j < table.columns.size(); ++j) out << (j ? "," : "") << table.columns[j].name;
    out << '\n';
    for (std::size_t k = 0; k < table.rows(); ++k) {
        for (std::size_t j = 0; j < table.columns.size(); ++j) {
            if (j) out << ',';
            const Cell& c = table.cells[j][k];
            if (const auto* d = std::get_if<double>(&c)) out << format_number(*d);
            else if (const auto* i = std::get_if<long long>(&c)) out << *i;
            else if (const auto* t = std::get_if<std::string>(&c)) out << *t;
        }
        out << '\n';
    }
}

namespace {
Cell cell(const std::optional<double>& value) { return value ? Cell(*value) : Cell(); }
}  // namespace

const std::vector<Column>& nodal_diameter_columns() {
    static const std::vector<Column> columns = {
        {"nodal_diameter", "nodal diameter d, 0..floor(N / 2): the wheel's modes of harmonic index d and N - d",
         ColumnType::integer},
        {"mode", "the mode's rank in its nodal diameter, 1-based (ascending frequency)", ColumnType::integer},
        {"released", "natural frequency with the contacts removed (slipping freely)"},
        {"stuck", "natural frequency with every contact stuck (its spring; a rigid contact as a constraint); empty "
                  "where the constraints leave fewer modes"},
        {"excited_by", "the harmonics k of an engine-order response that meet this nodal diameter (k EO mod N is d "
                       "or N - d), space separated; empty: none",
         ColumnType::text}};
    return columns;
}

Table nodal_diameter_table(const CyclicSymmetry& cyclic, const NodalDiameterFamily& released,
                           const NodalDiameterFamily& stuck, int harmonics) {
    const Eigen::Index diameters = released.frequencies.rows(), modes = released.frequencies.cols();
    std::vector<std::string> excited(static_cast<std::size_t>(diameters));
    for (int k = 1; k <= harmonics; ++k) {
        std::string& list = excited[static_cast<std::size_t>(nodal_diameter(cyclic, k))];
        list += (list.empty() ? "" : " ") + std::to_string(k);
    }
    Table table(nodal_diameter_columns());
    for (Eigen::Index d = 0; d < diameters; ++d)
        for (Eigen::Index j = 0; j < modes; ++j) {
            const double s = stuck.frequencies(d, j);
            table.add_row({static_cast<long long>(d), static_cast<long long>(j + 1), released.frequencies(d, j),
                           std::isfinite(s) ? Cell(s) : Cell(), excited[static_cast<std::size_t>(d)]});
        }
    return table;
}

Table analytic_table(const std::vector<analytic::Row>& rows) {
    Table table{analytic_columns()};
    for (const analytic::Row& row : rows)
        table.add_row({row.omega, cell(row.y1_stick), cell(row.y2_stick), cell(row.y1_slip), cell(row.y2_slip),
                       cell(row.mu_limit), cell(row.mu_opt_den_hartog)});
    return table;
}

void write_analytic_csv(std::ostream& out, const std::vector<analytic::Row>& rows) {
    write_csv(out, analytic_table(rows));
}

namespace {

std::vector<Output> all_dofs(int dofs) {
    std::vector<Output> all;
    for (int i = 0; i < dofs; ++i) all.push_back(Output::dof(i));
    return all;
}

/// "y3" for a DOF, else "tip(t) = 0.5 y3 - 0.5 y7" (a long row: "a combination of 200 DOFs").
std::string output_definition(const Output& o) {
    if (o.single_dof() >= 0) return o.name();
    if (o.terms().size() > 4)
        return o.name() + " = a combination of " + std::to_string(o.terms().size()) + " DOFs (the [[output]] row)";
    std::string text = o.name() + " =";
    bool first = true;
    for (const auto& [i, c] : o.terms()) {
        text += (first ? " " : c < 0 ? " - " : " + ") + format_number(first ? c : std::abs(c)) + " y" + std::to_string(i + 1);
        first = false;
    }
    return text;
}

std::vector<Column> output_columns(const std::vector<Output>& outputs, const std::string& over,
                                   const std::string& how) {
    std::vector<Column> columns;
    for (const Output& o : outputs)
        columns.push_back({o.name() + "_max", "max over " + over + " of |" + o.name() + "(t)|" + how +
                                                  (o.single_dof() >= 0 ? "" : "; " + output_definition(o))});
    for (const Output& o : outputs)
        columns.push_back({o.name() + "_amp1", "first-harmonic amplitude sqrt(c1^2 + s1^2) of " + o.name() +
                                                   (over == "one period" ? "" : " over " + over)});
    return columns;
}

/// The columns stick_fraction and regime for one contact; with several, one pair per contact
/// i, stick_fraction_c<i> and regime_c<i>, in place of them.
std::vector<Column> per_contact(int contacts, const Column& stick, const Column& regime) {
    if (contacts <= 1) {
        Column s = stick, r = regime;
        s.meaning += "; with several contacts one column per contact i: stick_fraction_c<i>";
        r.meaning += "; with several contacts one column per contact i: regime_c<i>";
        return {s, r};
    }
    std::vector<Column> columns;
    for (int c = 1; c <= contacts; ++c) {
        const std::string suffix = "_c" + std::to_string(c), of = " (contact " + std::to_string(c) + ")";
        columns.push_back({stick.name + suffix, stick.meaning + of, stick.type});
        columns.push_back({regime.name + suffix, regime.meaning + of, regime.type});
    }
    return columns;
}

/// The contacts a table reports: the most of its rows' (a failed row has none).
template <class Rows>
int contacts_of(const Rows& rows) {
    std::size_t n = 1;
    for (const auto& r : rows) n = std::max(n, r.contacts.size());
    return static_cast<int>(n);
}

/// The stick_fraction and regime cells of a row (per_contact's columns).
void add_regimes(std::vector<Cell>& row, int contacts, double stick_fraction, const std::string& regime,
                 const std::vector<ContactRegime>& per) {
    if (contacts <= 1) {
        row.insert(row.end(), {stick_fraction, regime.empty() ? std::string("none") : regime});
        return;
    }
    for (int c = 0; c < contacts; ++c) {
        const auto i = static_cast<std::size_t>(c);
        if (i < per.size()) row.insert(row.end(), {per[i].stick_fraction, per[i].regime});
        else row.insert(row.end(), {Cell(), std::string("none")});
    }
}

}  // namespace

namespace {
/// Column w of the FRF and time-integration tables.
Column frequency_column() {
    return {"w", "excitation frequency omega (nondimensional: Omega / omega1; with --config in the file's units); "
                 "with --excitation-harmonic h the fundamental of the response, the force acting at h w"};
}
}  // namespace

std::vector<Column> frf_columns(int dofs) { return frf_columns(all_dofs(dofs)); }

std::vector<int> normal_contacts(const System& system) {
    std::vector<int> out;
    for (std::size_t c = 0; c < system.contacts.size(); ++c)
        if (contact_law(system.contacts[c].law).friction() && system.contact_directions(system.contacts[c]).cols() > 1)
            out.push_back(static_cast<int>(c));
    return out;
}

namespace {
/// The contacts with a normal direction among a table's rows (ContactRegime::separated_fraction
/// is computed for them): normal_contacts of the rows' system.
template <class Rows>
std::vector<int> normal_contacts_of(const Rows& rows) {
    std::vector<int> out;
    for (const auto& r : rows)
        for (std::size_t c = 0; c < r.contacts.size(); ++c)
            if (!std::isnan(r.contacts[c].separated_fraction) &&
                std::find(out.begin(), out.end(), static_cast<int>(c)) == out.end())
                out.push_back(static_cast<int>(c));
    std::sort(out.begin(), out.end());
    return out;
}

/// The columns stuck_share_i<k>, slip_share_i<k>, open_share_i<k> of each interface (a group
/// without nodes: the --help's description of every interface k); `period`: "the period" or
/// "the final period".
void add_share_columns(std::vector<Column>& columns, const std::vector<InterfaceContacts>& interfaces,
                       const std::string& period) {
    for (std::size_t k = 0; k < interfaces.size(); ++k) {
        const InterfaceContacts& f = interfaces[k];
        const std::string suffix = "_i" + std::to_string(k + 1),
                          of = f.count == 0 ? " of [[interface]] k (columns _i<k>, one set per interface), averaged over its nodes"
                                            : " of interface " + std::to_string(k + 1) + " ('" + f.name + "', " +
                                                  std::to_string(f.count) + " nodes: contacts " + std::to_string(f.first + 1) +
                                                  ".." + std::to_string(f.first + f.count) + "), averaged over its nodes";
        columns.push_back({"stuck_share" + suffix, "share of " + period + " in stick" + of + " (mean of stick_fraction_c<i>)"});
        columns.push_back({"slip_share" + suffix, "share of " + period + " slipping" + of +
                                                      " (1 - stuck_share - open_share)"});
        columns.push_back({"open_share" + suffix, "share of " + period + " open, N = 0" + of +
                                                      " (mean of separated_fraction_c<i>; 0 for laws without a normal direction)"});
    }
}

/// The cells of add_share_columns for one row (empty where a share is unknown).
void add_share_cells(std::vector<Cell>& row, const std::vector<ContactRegime>& contacts,
                     const std::vector<InterfaceContacts>& interfaces) {
    for (const InterfaceContacts& f : interfaces) {
        const std::optional<InterfaceShares> shares = interface_shares(contacts, f);
        if (shares)
            row.insert(row.end(), {shares->stuck, shares->slipping, shares->open});
        else
            row.insert(row.end(), {Cell(), Cell(), Cell()});
    }
}
}  // namespace

std::vector<Column> frf_columns(const std::vector<Output>& outputs, int contacts, const std::vector<int>& normal,
                                const std::vector<InterfaceContacts>& interfaces) {
    std::vector<Column> columns = {frequency_column()};
    const auto mine = output_columns(outputs, "one period", "");
    columns.insert(columns.end(), mine.begin(), mine.end());
    const std::vector<Column> regimes = per_contact(
        contacts,
        {"stick_fraction", "share of the period in stick, by the law's own definition (AFT samples; "
                           "coulomb: |lambda + eps v| < mu; jenkins: slider at rest; dahl/lugre: |sigma0 z| < 0.95 g(v); "
                           "coulomb-reg: |f| < 0.95 mu; iwan: every slider at rest); stick phases shorter than 2 / (2H + 1) of the period are not resolved by H harmonics and count as slip; "
                           "with exact = yes: from the exact event times"},
        {"regime", "stick (every sample sticks), slip (no stick phase) or stick-slip; none for a structure without "
                   "contacts", ColumnType::text});
    columns.insert(columns.end(), regimes.begin(), regimes.end());
    for (int c : normal) {
        const std::string suffix = contacts > 1 ? "_c" + std::to_string(c + 1) : "",
                          of = contacts > 1 ? " (contact " + std::to_string(c + 1) + ")" : "";
        columns.push_back({"separated_fraction" + suffix,
                           "contacts with a normal direction only (laws elastic, unilateral): share of the period the contact "
                           "is open, normal force N = 0 (AFT samples; 1 - stick_fraction - separated_fraction "
                           "slips)" + of});
        columns.push_back({"normal_force_mean" + suffix,
                           "laws elastic, unilateral only: mean over the period of the normal force N(t) >= 0" + of});
        columns.push_back({"normal_force_amp" + suffix, "laws elastic, unilateral only: half the range of the normal force over "
                                                        "the period, (max N - min N) / 2" + of});
    }
    add_share_columns(columns, interfaces, "the period");
    columns.push_back({"energy", "friction energy dissipated per cycle (= input work per cycle at a solution)"});
    if (contacts > 1 && !normal.empty())
        for (int c = 1; c <= contacts; ++c)
            columns.push_back({"energy_c" + std::to_string(c), "friction energy contact " + std::to_string(c) +
                                                                   " dissipates per cycle"});
    const std::vector<Column> rest = {
        {"branch", "branch number: 1, 2 for the branch restarted from wmax after an amplitude cap, 3 for the branch between two capped resonances", ColumnType::integer},
        {"point", "regular, fold (located where the tangent's w-component is zero: dR/dX singular, a real turn of the branch in w), transition (located boundary between stick and stick-slip "
                  "or between stick-slip and slip; with the exact polish of contacts with a normal direction also "
                  "where a contact starts to open, the grazing orbit: the JSON's transitions name the contact and "
                  "the boundary), cap (the amplitude bound passed --max-amplitude here: "
                  "an unbounded resonance, the branch stops; its largest point; a cap exactly on an undamped resonance that no "
                  "contact sees has inf in the DOFs it moves and is not polished), sample (solved exactly at an --at "
                  "frequency), or with --stability the first point past a change of stability: branch-point (a real "
                  "Floquet multiplier through +1 without a turn), period-doubling (through -1), neimark-sacker (a "
                  "complex pair)", ColumnType::text},
        {"iterations", "corrector (Ceres) iterations of this point", ColumnType::integer},
        {"residual", "|R|_inf / force scale after correction"},
        {"step", "arclength step that led to this point"},
        {"exact", "yes: the row is the event-exact periodic orbit at w (Newton shooting with the contacts' "
                  "events located exactly), its metrics replace HB's; failed: the exact solver did not "
                  "converge here, the row keeps the HB values; off: plain harmonic balance (--exact off or another law)",
                  ColumnType::text},
        {"stable", "Floquet stability of the periodic solution: true (every |multiplier| <= 1 + 1e-6), false "
                   "(unstable: a small perturbation grows), uncertain (the two routes of --stability disagree, or "
                   "the exact solver did not reproduce the HB orbit, or the exact orbit's multipliers could not be "
                   "computed, or its largest one, from central differences of the period map, is above 1 by less than "
                   "their accuracy of " + format_number(difference_multiplier_accuracy) + ": a neutral direction they cannot place); from the exact orbit where exact = yes, from "
                   "--stability otherwise (empty without it)", ColumnType::text},
        {"hb_gap", "|y_max by HB - y_max exact| / y_max exact of the first reported output: harmonic balance's own "
                   "error at this point; empty unless exact = yes (and an HB solution exists at this w)"},
        {"hb_error", "harmonic balance's estimated truncation error of the first reported output's max |o(t)|: "
                     "2 |y(H) - y(2H)| / max y (max y: its largest on the FRF), the point solved again with twice the harmonics; at the branch's "
                     "maxima and points spread over it (--error-points), empty elsewhere and where exact = yes"},
        {"energy_error", "energy balance of the harmonic-balance solution: |input work - viscous energy - friction "
                         "energy| per cycle, relative to max(pi h |F| |Y_h|, input work, viscous + |friction|) (pi h "
                         "|F| |Y_h|: the work the force could do on the response's harmonic h); above max(1e-6, 100 "
                         "--tolerance) the point is suspect (a warning, exit code 3)"},
        {"stability_margin", "largest |Floquet multiplier| of the point (> 1: unstable; from the monodromy matrix, "
                             "else Hill's sorted exponents, else the exact orbit); empty where not computed"},
    };
    columns.insert(columns.end(), rest.begin(), rest.end());
    return columns;
}

std::optional<InterfaceShares> interface_shares(const PointMetrics& metrics, const InterfaceContacts& group) {
    return interface_shares(metrics.contacts, group);
}

std::optional<InterfaceShares> interface_shares(const std::vector<ContactRegime>& contacts, const InterfaceContacts& group) {
    if (group.count <= 0) return std::nullopt;
    double stuck = 0.0, open = 0.0;
    for (int c = group.first; c < group.first + group.count; ++c) {
        const auto i = static_cast<std::size_t>(c);
        if (c < 0 || i >= contacts.size() || !std::isfinite(contacts[i].stick_fraction)) return std::nullopt;
        stuck += contacts[i].stick_fraction;
        if (std::isfinite(contacts[i].separated_fraction)) open += contacts[i].separated_fraction;
    }
    InterfaceShares s;
    s.stuck = stuck / group.count;
    s.open = open / group.count;
    s.slipping = std::max(0.0, 1.0 - s.stuck - s.open);
    return s;
}

Table frf_table(const std::vector<SolutionPoint>& points, const std::vector<PointMetrics>& metrics,
                const std::vector<Output>& outputs, const std::vector<ExactPoint>& exact,
                const BranchStability* stability, const std::vector<InterfaceContacts>& interfaces) {
    const int contacts = contacts_of(metrics);
    const std::vector<int> normal = normal_contacts_of(metrics);
    Table table{frf_columns(outputs, contacts, normal, interfaces)};
    table.cells.resize(table.columns.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
        const SolutionPoint& p = points[k];
        const PointMetrics& m = metrics[k];
        std::vector<Cell> row = {p.omega};
        for (std::size_t j = 0; j < outputs.size(); ++j) row.emplace_back(m.output_max[j]);
        for (std::size_t j = 0; j < outputs.size(); ++j) row.emplace_back(m.output_amp1[j]);
        add_regimes(row, contacts, m.stick_fraction, m.regime, m.contacts);
        auto of = [&](int c, double ContactRegime::*field) {
            const auto i = static_cast<std::size_t>(c);
            return i < m.contacts.size() && std::isfinite(m.contacts[i].*field) ? Cell(m.contacts[i].*field) : Cell();
        };
        for (int c : normal)
            row.insert(row.end(), {of(c, &ContactRegime::separated_fraction), of(c, &ContactRegime::normal_mean),
                                   of(c, &ContactRegime::normal_amplitude)});
        add_share_cells(row, m.contacts, interfaces);
        row.emplace_back(m.energy);
        if (contacts > 1 && !normal.empty())
            for (int c = 0; c < contacts; ++c) row.push_back(of(c, &ContactRegime::energy));
        row.insert(row.end(), {static_cast<long long>(p.branch),
                               to_string(p.kind), static_cast<long long>(p.iterations), p.residual, p.step});
        const FloquetResult* floquet = stability && k < stability->points.size() ? &stability->points[k] : nullptr;
        const bool polished = k < exact.size() && exact[k].status == PolishStatus::exact;
        if (polished) {
            const ExactPoint& e = exact[k];
            row.insert(row.end(), {std::string("yes"),
                                   floquet                                ? to_string(floquet->stability)
                                   : !std::isfinite(e.max_multiplier) || e.stability_unresolved ? to_string(Stability::uncertain)
                                   : e.stable                         ? "true"
                                                                      : "false",
                                   std::isfinite(e.hb_gap) ? Cell(e.hb_gap) : Cell()});
        } else {
            row.insert(row.end(), {k < exact.size() ? to_string(exact[k].status) : std::string("off"),
                                   floquet ? Cell(to_string(floquet->stability)) : Cell(), Cell()});
        }
        row.push_back(std::isfinite(m.hb_error) ? Cell(m.hb_error) : Cell());
        row.emplace_back(m.energy_error);
        if (polished && !floquet && std::isfinite(exact[k].max_multiplier)) row.emplace_back(exact[k].max_multiplier);
        else if (floquet && std::isfinite(floquet->margin)) row.emplace_back(floquet->margin);
        else row.emplace_back();
        table.add_row(std::move(row));
    }
    return table;
}

void write_frf_csv(std::ostream& out, const std::vector<SolutionPoint>& points,
                   const std::vector<PointMetrics>& metrics, const std::vector<Output>& outputs,
                   const std::vector<ExactPoint>& exact, const BranchStability* stability,
                   const std::vector<InterfaceContacts>& interfaces) {
    write_csv(out, frf_table(points, metrics, outputs, exact, stability, interfaces));
}

std::vector<Column> timeint_columns(int dofs) { return timeint_columns(all_dofs(dofs)); }

std::vector<Column> timeint_columns(const std::vector<Output>& outputs, int contacts, const std::vector<int>& normal,
                                    const std::vector<InterfaceContacts>& interfaces) {
    std::vector<Column> columns = {frequency_column()};
    const auto mine = output_columns(outputs, "the final period", " (turning points by root finding)");
    columns.insert(columns.end(), mine.begin(), mine.end());
    const std::vector<Column> regimes = per_contact(
        contacts,
        {"stick_fraction", "share of the final period in stick (coulomb, jenkins, elastic: exact event times; "
                           "dahl, lugre: |sigma0 z| < 0.95 g(v); coulomb-reg: |tanh(v/eps)| < 0.95; iwan: every "
                           "slider stuck; unilateral: its steps, |T| < mu N; --method exact: exact event times)"},
        {"regime", "stick (never left stick in the final period), slip (never stuck) or stick-slip; none for a "
                   "structure without contacts; failed where not one period could be integrated (the row's "
                   "numbers are then empty)", ColumnType::text});
    columns.insert(columns.end(), regimes.begin(), regimes.end());
    for (int c : normal)
        columns.push_back({"separated_fraction" + (contacts > 1 ? "_c" + std::to_string(c + 1) : std::string()),
                           "laws elastic, unilateral only: share of the final period the contact is open (N = 0; elastic: "
                           "exact event times; unilateral: its steps; --method exact: exact event times)" + (contacts > 1 ? " (contact " + std::to_string(c + 1) + ")" : std::string())});
    add_share_columns(columns, interfaces, "the final period");
    const std::vector<Column> rest = {
        {"energy", "friction energy dissipated per cycle, integral of f q' over the final period (laws elastic, "
                   "unilateral: along the tangential directions)"},
        {"periods", "periods integrated (including the shooting-Jacobian periods)", ColumnType::integer},
        {"converged", "true if the state at the start of consecutive periods changed by <= steady-tol (relative) "
                      "and the final period passed its physics checks (energy balance; contacts stuck for the whole "
                      "period keep their relative displacement; permanent stick is the centred linear stuck "
                      "state); --method exact: Newton on the period map reached its tolerance (1e-12 of the "
                      "state) or, where no step lowers its residual, the flow's rounding below 1e-9 (a note "
                      "counts those); false: the row holds the last period integrated", ColumnType::text},
        {"stick_margin_min", "min over the final period of contact 1's stick indicator (< 0 in stick; laws elastic, unilateral: "
                             "|T| / (mu N) - 1 stuck, 0 slipping, 1 open, at every step)"},
        {"stick_margin_max", "max of the stick indicator (< 0: full stick; coulomb also at each velocity reversal)"},
        {"switches", "stick/slip mode changes of all contacts in the final period", ColumnType::integer},
        {"max_multiplier", "--method exact: the orbit's largest |Floquet multiplier| (above 1 + 1e-6: unstable, a "
                           "time integration there goes to another response; where the multipliers come from central "
                           "differences of the period map, up to 1 + " + format_number(difference_multiplier_accuracy) + " is their accuracy: stability uncertain); empty for time integration, and where the "
                           "orbit's multipliers could not be computed (its stability unknown: said on standard error)"},
    };
    columns.insert(columns.end(), rest.begin(), rest.end());
    return columns;
}

Table timeint_table(const std::vector<PeriodicResponse>& responses, const std::vector<Output>& outputs,
                    const std::vector<InterfaceContacts>& interfaces) {
    const int contacts = contacts_of(responses);
    const std::vector<int> normal = normal_contacts_of(responses);
    Table table{timeint_columns(outputs, contacts, normal, interfaces)};
    table.cells.resize(table.columns.size());
    for (const PeriodicResponse& r : responses) {
        std::vector<Cell> row = {r.omega};
        // A point where not even one period was integrated has no values: empty fields, regime
        // failed (never zeros that read as a response).
        if (r.output_max.size() < outputs.size()) {
            row.resize(1 + 2 * outputs.size());
            for (int c = 0; c < contacts; ++c) row.insert(row.end(), {Cell(), std::string("failed")});
            for (std::size_t c = 0; c < normal.size() + 3 * interfaces.size(); ++c) row.emplace_back();
            row.insert(row.end(), {Cell(), static_cast<long long>(r.periods), std::string("false"), Cell(), Cell(), Cell(), Cell()});
            table.add_row(std::move(row));
            continue;
        }
        for (std::size_t j = 0; j < outputs.size(); ++j) row.emplace_back(r.output_max[j]);
        for (std::size_t j = 0; j < outputs.size(); ++j) row.emplace_back(j < r.output_amp1.size() ? r.output_amp1[j] : 0.0);
        add_regimes(row, contacts, r.stick_fraction, r.regime, r.contacts);
        for (int c : normal) {
            const auto i = static_cast<std::size_t>(c);
            row.push_back(i < r.contacts.size() && std::isfinite(r.contacts[i].separated_fraction)
                              ? Cell(r.contacts[i].separated_fraction)
                              : Cell());
        }
        add_share_cells(row, r.contacts, interfaces);
        row.insert(row.end(), {r.energy, static_cast<long long>(r.periods), std::string(r.converged ? "true" : "false"),
                               r.stick_margin_min, r.stick_margin_max, static_cast<long long>(r.switches),
                               std::isfinite(r.max_multiplier) ? Cell(r.max_multiplier) : Cell()});
        table.add_row(std::move(row));
    }
    return table;
}

void write_timeint_csv(std::ostream& out, const std::vector<PeriodicResponse>& responses,
                       const std::vector<Output>& outputs, const std::vector<InterfaceContacts>& interfaces) {
    write_csv(out, timeint_table(responses, outputs, interfaces));
}

}  // namespace hbf::io
