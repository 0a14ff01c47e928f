// hbfriction — the JSON summaries of the FRF and of its parameters (table.hpp:
// write_frf_summary, frf_parameters).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <iostream>
#include <limits>
#include <map>
#include <stdexcept>

#include "hbf/cyclic.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"
#include "hbf/table.hpp"

namespace hbf::io {

std::vector<std::pair<std::string, double>> frf_parameters(const System& system, const AbsorberParameters* preset,
                                                           const HarmonicBalance& hb,
                                                           const ContinuationOptions& co) {
    std::vector<std::pair<std::string, double>> parameters;
    if (preset) {
        const AbsorberParameters& p = *preset;
        parameters = {{"r", p.mass_ratio},
                      {"wa", p.tuning_ratio},
                      {"mu", p.friction_coefficient},
                      {"fe", p.excitation},
                      {"wb", p.contact_stiffness_ratio},
                      {"xi", p.contact_damping_ratio},
                      {"eps", p.regularization},
                      {"mu_static", p.static_friction_coefficient},
                      {"stribeck_velocity", p.stribeck_velocity},
                      {"viscous", p.viscous_coefficient}};
    } else {
        parameters = {{"dofs", system.dofs()}, {"contacts", static_cast<double>(system.contacts.size())}};
    }
    if (system.cyclic.active()) {  // a sector (cyclic.hpp): the wheel and the nodal diameter excited
        parameters.emplace_back("sectors", system.cyclic.sectors);
        parameters.emplace_back("engine_order", system.cyclic.engine_order);
        parameters.emplace_back("nodal_diameter", nodal_diameter(system.cyclic, 1));
    }
    const std::vector<std::pair<std::string, double>> solver = {
        {"wmin", co.omega_start},
        {"wmax", co.omega_end},
        {"harmonics", hb.harmonics()},
        {"excitation_harmonic", hb.load_harmonic()},
        {"odd_harmonics", hb.odd_harmonics() ? 1 : 0},
        {"time_samples", hb.time_samples()},
        {"condensed", hb.formulation() == Formulation::condensed ? 1 : 0},
        {"modes", hb.modes()},
        {"structured_jacobian", hb.structured() ? 1 : 0},
        {"max_amplitude", co.max_amplitude},
        {"tolerance", co.corrector.tolerance}};
    parameters.insert(parameters.end(), solver.begin(), solver.end());
    // The dynamic Lagrangian's penalty in use (the automatic one where none was given).
    const std::vector<Contact>& contacts = hb.system().contacts;
    for (std::size_t c = 0; c < contacts.size(); ++c)
        if (contacts[c].law == FrictionLaw::coulomb)
            parameters.emplace_back(contacts.size() == 1 ? std::string("lagrangian_penalty")
                                                         : "lagrangian_penalty_" + std::to_string(c + 1),
                                    contacts[c].lagrangian_penalty);
    return parameters;
}

void write_frf_summary(std::ostream& out, const std::string& law,
                       const std::vector<std::pair<std::string, double>>& parameters, const BranchResult& branch,
                       const std::vector<PointMetrics>& metrics_in, const std::vector<Peak>& peaks,
                       std::size_t samples, double wall_seconds, const std::vector<Output>& outputs,
                       const PolishedBranch* polish, const std::vector<std::string>& errors,
                       const std::vector<std::string>& warnings, const std::vector<std::string>& notes,
                       const BranchStability* stability, const StaticState* static_state) {
    using nlohmann::json;
    json j;
    j["parameters"] = {{"law", law}};
    for (const auto& [name, value] : parameters) {
        if (std::abs(value) < 1e15 && value == std::round(value))
            j["parameters"][name] = static_cast<long long>(value);
        else
            j["parameters"][name] = value;
    }
    const auto& points = polish ? polish->points : branch.points;
    const auto& metrics = polish ? polish->metrics : metrics_in;
    long long iterations = 0;
    for (const SolutionPoint& point : points) iterations += point.iterations;
    j["points"] = points.size() - (polish ? samples : 0);
    j["samples"] = samples;
    const EvaluationStatistics& e = branch.evaluation;
    j["solver"] = {{"corrections", branch.corrections},
                   {"failed_corrections", branch.failed_corrections},
                   {"noise_limited_corrections", branch.corrector.noise_limited},
                   {"krylov_iterations", branch.corrector.krylov_iterations},
                   {"preconditioner_factorizations", branch.corrector.factorizations},
                   {"rejected_jumps", branch.rejected_jumps},
                   {"crossed_corners", branch.crossed_corners},
                   {"unlocated_transitions", branch.unlocated_transitions},
                   {"iterations", iterations},
                   {"iterations_per_point", points.empty() ? 0.0 : double(iterations) / double(points.size())},
                   {"residual_evaluations", e.residuals},
                   {"jacobian_evaluations", e.jacobians},
                   {"continuation_seconds", branch.seconds},
                   {"aft_seconds", e.aft_seconds},
                   {"jacobian_seconds", e.jacobian_seconds + e.structure_seconds},
                   {"ceres_seconds", branch.corrector.seconds - branch.corrector.evaluation_seconds}};
    json peak_list = json::array(), folds = json::array();
    for (const Peak& peak : peaks) {
        json entry = {{"w", peak.omega}};
        if (peak.output >= 0 && static_cast<std::size_t>(peak.output) < outputs.size()) {
            const Output& o = outputs[static_cast<std::size_t>(peak.output)];
            entry["output"] = o.name();
            if (o.single_dof() >= 0) entry["dof"] = o.single_dof() + 1;
        }
        entry["y_max"] = peak.y_max;
        entry["branch"] = peak.branch;
        entry["refined"] = peak.refined;
        if (peak.within_error) entry["within_hb_error"] = true;
        if (!peak.refined) entry["why"] = peak.why;
        peak_list.push_back(entry);
    }
    // A fold or transition: w, and <name>_max of every reported output (as the CSV columns).
    auto located = [&](std::size_t k) {
        json entry = {{"w", points[k].omega}};
        for (std::size_t o = 0; o < outputs.size() && o < metrics[k].output_max.size(); ++o)
            entry[outputs[o].name() + "_max"] = metrics[k].output_max[o];
        entry["branch"] = points[k].branch;
        return entry;
    };
    for (std::size_t k = 0; k < points.size(); ++k)
        if (points[k].kind == PointKind::fold) folds.push_back(located(k));
    json transitions = json::array();
    for (std::size_t k = 0; k < points.size(); ++k)
        if (points[k].kind == PointKind::transition) {
            json entry = located(k);
            entry["between"] = to_string(points[k].boundary);
            entry["contact"] = points[k].contact + 1;
            transitions.push_back(entry);
        }
    if (polish) {
        j["exact"] = {{"enabled", true},
                      {"polished", polish->polished},
                      {"failed", polish->failed},
                      {"unstable", polish->unstable},
                      {"stability_unknown", polish->stability_unknown},
                      {"stability_uncertain", polish->stability_unresolved},
                      {"transitions", polish->transitions},
                      {"unlocated_transitions", polish->unlocated_transitions},
                      {"max_hb_gap", polish->max_hb_gap},
                      {"modes", polish->modes},
                      {"modal_truncation",
                       std::isfinite(polish->modal_truncation) ? json(polish->modal_truncation) : json()},
                      {"seconds", polish->seconds}};
    } else {
        j["exact"] = {{"enabled", false}};
        // Harmonic balance's estimated truncation error (PointMetrics::hb_error), where estimated.
        int estimated = 0;
        double largest = 0.0, at = 0.0;
        for (std::size_t k = 0; k < metrics.size() && k < points.size(); ++k)
            if (std::isfinite(metrics[k].hb_error)) {
                if (estimated++ == 0 || metrics[k].hb_error > largest) {
                    largest = metrics[k].hb_error;
                    at = points[k].omega;
                }
            }
        j["hb_error"] = estimated ? json{{"points", estimated}, {"largest", largest}, {"w", at}} : json{{"points", 0}};
    }
    if (stability) {
        json intervals = json::array(), bifurcations = json::array();
        for (const BranchStability::Interval& i : stability->unstable)
            intervals.push_back({{"w_from", i.omega_from}, {"w_to", i.omega_to}, {"branch", i.branch}});
        for (const BranchStability::Bifurcation& b : stability->bifurcations)
            bifurcations.push_back({{"kind", b.kind}, {"w", b.omega}, {"branch", b.branch}});
        j["stability"] = {{"enabled", true},
                          {"stable", stability->stable},
                          {"unstable", stability->unstable_points},
                          {"uncertain", stability->uncertain},
                          {"not_computed", stability->not_computed},
                          {"unstable_intervals", intervals},
                          {"bifurcations", bifurcations},
                          {"both_routes_confident", stability->both_confident},
                          {"sorting_disagreements", stability->sorting_disagreements},
                          {"seconds", stability->seconds}};
    } else {
        j["stability"] = {{"enabled", false}};
    }
    j["peaks"] = peak_list;
    j["folds"] = folds;
    j["transitions"] = transitions;
    // Every contact over the branch: the range of its stick fraction, and for a contact with a
    // normal direction the largest open share with where it is open, and its normal force.
    json contact_list = json::array();
    std::size_t contact_count = 0;
    for (const PointMetrics& m : metrics) contact_count = std::max(contact_count, m.contacts.size());
    for (std::size_t c = 0; c < contact_count; ++c) {
        double stick_min = 1.0, stick_max = 0.0, open_max = 0.0, open_from = 0.0, open_to = 0.0;
        double mean_min = std::numeric_limits<double>::infinity(), mean_max = -mean_min, amp_max = 0.0;
        bool normal = false, open = false;
        for (std::size_t k = 0; k < points.size() && k < metrics.size(); ++k) {
            if (c >= metrics[k].contacts.size()) continue;
            const ContactRegime& r = metrics[k].contacts[c];
            stick_min = std::min(stick_min, r.stick_fraction);
            stick_max = std::max(stick_max, r.stick_fraction);
            if (!std::isfinite(r.separated_fraction)) continue;
            normal = true;
            if (r.separated_fraction > 0.0) {
                const double w = points[k].omega;
                open_from = open ? std::min(open_from, w) : w;
                open_to = open ? std::max(open_to, w) : w;
                open = true;
            }
            open_max = std::max(open_max, r.separated_fraction);
            if (std::isfinite(r.normal_mean)) {
                mean_min = std::min(mean_min, r.normal_mean);
                mean_max = std::max(mean_max, r.normal_mean);
                amp_max = std::max(amp_max, r.normal_amplitude);
            }
        }
        json entry = {{"contact", c + 1}, {"stick_fraction_min", stick_min}, {"stick_fraction_max", stick_max}};
        if (normal) {
            entry["separated_fraction_max"] = open_max;
            entry["open_from_w"] = open ? json(open_from) : json();
            entry["open_to_w"] = open ? json(open_to) : json();
            if (std::isfinite(mean_min))
                entry["normal_force_mean_range"] = {mean_min, mean_max};
            entry["normal_force_amp_max"] = amp_max;
        }
        contact_list.push_back(entry);
    }
    j["contacts"] = contact_list;
    if (static_state) {  // static_state.hpp: each contact under the static load alone
        json rest = {{"solved", static_state->ok}};
        if (!static_state->ok) rest["message"] = static_state->message;
        json list = json::array();
        for (std::size_t c = 0; static_state->ok && c < static_state->contacts.size(); ++c) {
            const StaticContactState& k = static_state->contacts[c];
            json entry = {{"contact", c + 1}, {"state", k.state}};
            if (k.force.size() > 1) {  // a normal direction (the last)
                entry["normal_force"] = k.force(k.force.size() - 1);
                entry["tangential_force"] = k.force.head(k.force.size() - 1).norm();
            } else if (k.force.size() == 1) {
                entry["force"] = k.force(0);
            }
            list.push_back(entry);
        }
        rest["contacts"] = list;
        j["static_state"] = rest;
    }
    j["status"] = to_string(branch.status);
    j["coverage"] = branch.coverage;
    j["message"] = branch.message;
    // The command's verdict (hbf frf: exit 1 with errors, else 3 with warnings, else 0).
    j["outcome"] = !errors.empty() ? "failed" : !warnings.empty() ? "incomplete" : "completed";
    j["errors"] = errors;
    j["warnings"] = warnings;
    j["notes"] = notes;
    double worst = 0.0;
    for (const PointMetrics& m : metrics) worst = std::max(worst, m.energy_error);
    j["max_energy_error"] = worst;
    j["wall_time_seconds"] = wall_seconds;
    out << j.dump(2) << '\n';
}

}  // namespace hbf::io
