// hbfriction._core — the computations: FRF, solve_at, time integration, maps, optimisation,
// tracking, modes, closed forms (bindings.hpp).
#include "bindings.hpp"

#include <chrono>

namespace hbf::python {

namespace {
/// A stop asked at every continuation step: the time limit (seconds, 0: none), or an interrupt
/// (Ctrl-C, seen by Python's signal handler): the points so far are the result (status stopped).
std::function<std::string()> python_stop(double time_limit) {
    if (!(time_limit >= 0.0 && time_limit <= 1e9))
        throw InvalidInput("time_limit = " + format_number(time_limit) + " is out of range: allowed 0 (none) .. 1e9 seconds");
    const auto start = std::chrono::steady_clock::now();
    return [start, time_limit]() -> std::string {
        if (time_limit > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= time_limit)
            return "the time limit of " + format_number(time_limit) + " s (time_limit) is reached";
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) {
            PyErr_Clear();
            return "interrupted (KeyboardInterrupt)";
        }
        return "";
    };
}

/// Per steady state of a sweep or branch: converged, message, state and the sampled period.
py::list response_details(const std::vector<PeriodicResponse>& responses) {
    py::list details;
    for (const PeriodicResponse& r : responses) {
        py::dict d;
        d["converged"] = r.converged;
        d["message"] = r.message;
        d["summary"] = r.summary();
        d["state"] = to_list(r.state);
        d["t"] = to_list(r.time);
        d["y"] = matrix(r.displacement);
        d["velocity"] = matrix(r.velocity);
        d["friction_force"] = matrix(r.friction_force);
        d["input_energy"] = r.input_energy;
        d["viscous_energy"] = r.viscous_energy;
        d["seconds"] = r.seconds;
        d["max_multiplier"] = r.max_multiplier;
        d["multiplier_accuracy"] = r.multiplier_accuracy;
        details.append(d);
    }
    return details;
}
}  // namespace

void bind_studies(py::module_& m) {
    // ---- computations -------------------------------------------------------------------------
    py::class_<FrfRun, std::shared_ptr<FrfRun>>(m, "FrfRun", "A computed FRF (hbfriction.Branch wraps it)")
        .def_property_readonly("columns", [](const FrfRun& r) { return table_columns(r.table); })
        .def_property_readonly("summary", [](const FrfRun& r) { return r.summary; })
        .def_property_readonly("errors", [](const FrfRun& r) { return r.verdict.errors; })
        .def_property_readonly("warnings", [](const FrfRun& r) { return r.verdict.warnings; })
        .def_property_readonly("notes", [](const FrfRun& r) { return r.verdict.notes; })
        .def_property_readonly("status", [](const FrfRun& r) { return r.verdict.status(); })
        .def_property_readonly("seconds", [](const FrfRun& r) { return r.result.seconds; })
        .def_property_readonly("peak", [](const FrfRun& r) { return peak_dict(r.result.peak); })
        .def_property_readonly("coefficients",
                               [](const FrfRun& r) {
                                   py::list out;
                                   for (const SolutionPoint& p : r.result.points) out.append(to_list(p.x));
                                   return out;
                               })
        .def("csv", [](const FrfRun& r) {
            std::ostringstream out;
            io::write_csv(out, r.table);
            return out.str();
        });

    m.def(
        "compute_frf",
        [](const PySystem& s, FrfSettings settings, double time_limit) {
            settings.continuation.stop = python_stop(time_limit);
            return without_gil([&] { return run_frf(s, settings); });
        },
        py::arg("system"), py::arg("settings"), py::arg("time_limit") = 0.0);
    m.def(
        "compute_frfs",
        [](const std::vector<PySystem>& systems, const FrfSettings& settings, int threads) {
            return without_gil([&] {
                // compute_frfs' own scheduling (and its InvalidInput per task: that FRF
                // start_failed), with each run's table and summary made as for one FRF.
                std::vector<std::shared_ptr<FrfRun>> runs(systems.size());
                const auto results = compute_frfs(
                    static_cast<int>(systems.size()), [&](int k) { return systems[static_cast<std::size_t>(k)].system; },
                    settings, threads);
                for (std::size_t k = 0; k < systems.size(); ++k) {
                    auto run = std::make_shared<FrfRun>();
                    run->result = results[k];
                    FrfSettings used = settings;
                    if (used.outputs.empty()) used.outputs = systems[k].reported();
                    std::unique_ptr<HarmonicBalance> hb;
                    try {  // the solver's parameters for the summary (no FRF is computed)
                        hb = std::make_unique<HarmonicBalance>(systems[k].system, used.harmonic_balance);
                    } catch (const InvalidInput&) {
                    }
                    finish_run(*run, systems[k], used, hb.get());
                    runs[k] = run;
                }
                return runs;
            });
        },
        py::arg("systems"), py::arg("settings"), py::arg("threads"));

    m.def(
        "solve_at",
        [](const PySystem& s, double omega, double omega_from, const HarmonicBalanceOptions& options,
           const ContinuationOptions& continuation, int contact) {
            if (contact < 0 || contact >= static_cast<int>(s.system.contacts.size()))
                bad("contact = " + std::to_string(contact) + " is out of range: allowed 0.." +
                    std::to_string(static_cast<int>(s.system.contacts.size()) - 1));
            py::dict d;
            std::optional<SolutionAt> at;
            PointMetrics metrics;
            PointSignals signals;
            Eigen::MatrixXd coefficients;
            int harmonics = 0;
            without_gil([&] {
                HarmonicBalance hb(s.system, options);
                harmonics = hb.harmonics();
                at = solve_at(hb, omega, omega_from, continuation);
                if (!at->found) return 0;
                Analyser analyse(hb, {}, s.reported());
                metrics = analyse(at->point);
                signals = point_signals(hb, at->point, contact);
                coefficients = hb.dofs(at->point.x, omega);
                return 0;
            });
            d["found"] = at->found;
            d["message"] = at->branch.summary();
            d["harmonics"] = harmonics;
            if (!at->found) return d;
            const SolutionPoint& p = at->point;
            d["omega"] = p.omega;
            d["x"] = to_list(p.x);
            d["iterations"] = p.iterations;
            d["residual"] = p.residual;
            d["coefficients"] = matrix(coefficients);
            d["y_max"] = metrics.y_max;
            d["y_amp1"] = metrics.y_amp1;
            d["output_max"] = metrics.output_max;
            d["output_amp1"] = metrics.output_amp1;
            d["stick_fraction"] = metrics.stick_fraction;
            d["regime"] = metrics.regime;
            py::list stick_fractions, regimes;
            for (const ContactRegime& r : metrics.contacts) {
                stick_fractions.append(r.stick_fraction);
                regimes.append(r.regime);
            }
            d["stick_fractions"] = stick_fractions;
            d["regimes"] = regimes;
            d["energy"] = metrics.energy;
            d["input_energy"] = metrics.input_energy;
            d["viscous_energy"] = metrics.viscous_energy;
            d["energy_error"] = metrics.energy_error;
            d["energy_limit"] = energy_balance_limit(continuation.corrector.tolerance);
            py::dict sig;
            sig["t"] = to_list(signals.time);
            sig["y"] = matrix(signals.y);
            sig["q"] = to_list(signals.q);
            sig["v"] = to_list(signals.v);
            sig["f"] = to_list(signals.f);
            sig["phi"] = to_list(signals.phi);
            sig["f_series"] = to_list(signals.f_series);
            d["signals"] = sig;
            return d;
        },
        py::arg("system"), py::arg("omega"), py::arg("omega_from"), py::arg("options"), py::arg("continuation"),
        py::arg("contact"));

    m.def(
        "timeint",
        [](const PySystem& s, const std::vector<double>& omegas, TimeIntegrationOptions options, bool exact,
           double exact_tolerance, bool symmetric, double time_limit) {
            if (omegas.empty()) bad("w: no frequency given: allowed one or more frequencies > 0");
            for (double w : omegas)
                if (!(std::isfinite(w) && w > 0.0))
                    bad("w = " + format_number(w) + " is out of range: allowed frequencies > 0");
            if (options.outputs.empty()) options.outputs = s.reported();
            options.validate();
            s.system.validate();
            ExactOptions eo;
            eo.outputs = options.outputs;
            eo.tolerance = exact_tolerance;
            eo.mirror_symmetric = symmetric;
            // as hbf timeint's --time-limit: asked before each frequency and after every period
            const std::function<std::string()> stop = python_stop(time_limit);
            options.stop = stop;
            eo.stop = stop;
            if (symmetric && !exact) bad("symmetric = True applies to method = 'exact': allowed False here");
            if (exact) {
                const std::string refusal = exact_sweep_refusal(s.system, *std::min_element(omegas.begin(), omegas.end()));
                if (!refusal.empty()) bad("method = 'exact': " + refusal + " (use adams or bdf)");
                if (symmetric)
                    if (const std::string why = mirror_symmetric_refusal(s.system); !why.empty())
                        bad("symmetric = True: " + why + ": allowed False here");
                eo.validate();
            }
            std::vector<PeriodicResponse> responses;
            io::Table table;
            Verdict verdict;
            std::string stopped;  // why the sweep ended early (time_limit, an interrupt)
            without_gil([&] {
                // The sweep of hbf timeint: from the stuck linear state at the first frequency,
                // each point from the previous one's final state.
                MessageCollector messages;  // what CVODE reports during the sweep
                SteadySweep sweep = sweep_steady_states(s.system, omegas, options, exact ? &eo : nullptr, stop);
                responses = std::move(sweep.responses);
                stopped = std::move(sweep.stopped);
                table = io::timeint_table(responses, options.outputs);
                verdict = judge_sweep(s.system, responses, options, exact ? &eo : nullptr);
                verdict.add(messages.messages());
                if (!stopped.empty())
                    verdict.warning(stopped + " (" + std::to_string(responses.size()) + " of " + std::to_string(omegas.size()) +
                                    " frequencies computed)");
                return 0;
            });
            const py::list details = response_details(responses);
            py::dict v;
            v["status"] = verdict.status();
            v["stopped"] = !stopped.empty();
            v["errors"] = verdict.errors;
            v["warnings"] = verdict.warnings;
            v["notes"] = verdict.notes;
            return py::make_tuple(table_columns(table), details, v);
        },
        py::arg("system"), py::arg("omegas"), py::arg("options"), py::arg("exact"), py::arg("exact_tolerance"),
        py::arg("symmetric"), py::arg("time_limit"));

    m.def(
        "exact_branch",
        [](const PySystem& s, double wmin, double wmax, long long points, std::vector<Output> outputs, double tolerance,
           double time_limit) {
            ExactBranchOptions o = exact_branch_options(wmin, wmax, points);
            o.exact.outputs = outputs.empty() ? s.reported() : outputs;
            o.exact.tolerance = tolerance;
            o.exact.stop = python_stop(time_limit);
            o.validate();
            s.system.validate();
            if (const std::string why = exact_sweep_refusal(s.system, wmin); !why.empty()) bad(why);
            ExactBranch b;
            io::Table table;
            Verdict verdict;
            without_gil([&] {
                // as hbf timeint --method exact --sweep branch: from the stuck linear state at wmin
                b = exact_branch(s.system, o, linear_stuck_state(s.system, wmin));
                table = io::timeint_table(b.points, o.exact.outputs);
                verdict = judge_sweep(s.system, b.points, TimeIntegrationOptions{}, &o.exact);
                return 0;
            });
            py::list folds;
            for (const ExactFold& f : b.folds) {
                py::dict d;
                d["w"] = f.omega;
                d["point"] = f.point;
                folds.append(d);
            }
            py::dict v;
            v["status"] = b.status;
            v["message"] = b.message;
            v["errors"] = verdict.errors;
            v["warnings"] = verdict.warnings;
            v["notes"] = verdict.notes;
            v["folds"] = folds;
            v["corners"] = b.corners;
            v["rejected"] = b.rejected;
            return py::make_tuple(table_columns(table), response_details(b.points), v);
        },
        py::arg("system"), py::arg("wmin"), py::arg("wmax"), py::arg("points"), py::arg("outputs"), py::arg("tolerance"),
        py::arg("time_limit"));

    m.def("mode_defaults", [] {
        const ModeOptions o;
        py::dict d;
        d["mode"] = o.mode;
        d["tolerance"] = o.tolerance;
        d["max_step"] = o.max_step;
        d["max_points"] = o.max_points;
        return d;
    });
    m.def(
        "modes",
        [](const PySystem& s, HarmonicBalanceOptions hbo, int mode, double near, double amplitude_min,
           double amplitude_max, double tolerance, double max_step, int max_points, std::vector<Output> outputs,
           bool synthesis, bool exact_check, double start_frequency, double time_limit) {
            ModeOptions mo;
            mo.mode = mode;
            mo.near_frequency = near;
            mo.start_frequency = start_frequency;
            mo.amplitude_min = amplitude_min;
            mo.amplitude_max = amplitude_max;
            mo.tolerance = tolerance;
            mo.max_step = max_step;
            mo.initial_step = std::min(mo.initial_step, max_step);
            mo.min_step = std::min(mo.min_step, mo.initial_step);
            mo.max_points = max_points;
            if (outputs.empty()) outputs = s.reported();
            // No range given (both 0): a tenth to a hundred times the stuck mode's slip onset.
            SlipOnset onset;
            if (amplitude_min == 0.0 && amplitude_max == 0.0) {
                onset = slip_onset(s.system, hbo, mo);
                if (!onset.found)
                    bad("amplitude_min and amplitude_max are required here: no default range of the modal amplitude (" +
                        onset.why + ")");
                mo.amplitude_min = onset.amplitude_min;
                mo.amplitude_max = onset.amplitude_max;
            }
            mo.stop = python_stop(time_limit);
            ModeRun run;
            without_gil([&] {
                run = compute_mode(s.system, hbo, mo, outputs, synthesis, exact_check);
                return 0;
            });
            const Backbone& b = run.backbone;
            py::dict d;
            d["mode"] = b.linear.index;
            d["omega"] = b.linear.omega;
            d["zeta"] = b.linear.zeta;
            d["shape"] = to_list(b.linear.shape);
            if (b.linear.shape_imag.size()) d["shape_imag"] = to_list(b.linear.shape_imag);
            d["start"] = b.start;
            d["linear_omega"] = b.linear_omega;
            d["linear_xi"] = b.linear_xi;
            d["harmonics"] = run.harmonics;
            d["formulation"] = to_string(run.formulation);
            d["modes_used"] = run.modes;
            d["message"] = b.message;
            d["seconds"] = b.seconds;
            d["evaluations"] = b.evaluations;
            d["amplitude_min"] = mo.amplitude_min;
            d["amplitude_max"] = mo.amplitude_max;
            d["slip_onset"] = onset.found ? py::object(py::float_(onset.amplitude)) : py::object(py::none());
            d["slip_contact"] = onset.found ? py::object(py::int_(onset.contact)) : py::object(py::none());
            d["slip_opens"] = onset.found ? py::object(py::bool_(onset.opens)) : py::object(py::none());
            d["slip_onset_static"] = onset.found ? py::object(py::float_(onset.static_amplitude)) : py::object(py::none());
            d["slip_contact_static"] = onset.found ? py::object(py::int_(onset.static_contact)) : py::object(py::none());
            py::dict v;
            v["status"] = run.verdict.status();
            v["errors"] = run.verdict.errors;
            v["warnings"] = run.verdict.warnings;
            v["notes"] = run.verdict.notes;
            d["synthesis"] = synthesis ? py::object(table_columns(io::synthesis_table(run.synthesis, outputs)))
                                       : py::object(py::none());
            return py::make_tuple(table_columns(run.table), d, v);
        },
        py::arg("system"), py::arg("options"), py::arg("mode"), py::arg("near"), py::arg("amplitude_min"),
        py::arg("amplitude_max"), py::arg("tolerance"), py::arg("max_step"), py::arg("max_points"), py::arg("outputs"),
        py::arg("synthesis"), py::arg("exact_check"), py::arg("start_frequency"), py::arg("time_limit") = 0.0);

    m.def(
        "analytic",
        [](const AbsorberParameters& p, const std::string& law, const std::vector<double>& omegas) {
            const FrictionLaw l = parse_friction_law(law);
            p.validate(l);
            for (double w : omegas)
                if (!(std::isfinite(w) && w > 0.0))
                    bad("w = " + format_number(w) + " is out of range: allowed frequencies > 0");
            return table_columns(io::analytic_table(analytic::table(p, l, omegas)));
        },
        py::arg("parameters"), py::arg("law"), py::arg("omegas"));
    m.def(
        "nodal_diameters",
        [](const PySystem& s, int harmonics) {
            if (harmonics < 1 || harmonics > 100)
                bad("harmonics = " + std::to_string(harmonics) + " is out of range: allowed 1..100");
            return table_columns(io::nodal_diameter_table(s.system.cyclic, nodal_diameter_family(s.system, false),
                                                          nodal_diameter_family(s.system, true), harmonics));
        },
        py::arg("system"), py::arg("harmonics"));
    m.def("den_hartog_tuning", &analytic::den_hartog_tuning, py::arg("mass_ratio"));
    m.def("den_hartog_friction", &analytic::den_hartog_friction, py::arg("parameters"), py::arg("omega"));

    m.def(
        "optimize",
        [](const py::function& system, const FrfSettings& settings, const OptimizeOptions& options) {
            const auto of = system_of(system);
            const OptimizeResult r = without_gil([&] { return optimize_parameter(of, settings, options); });
            return optimize_dict(r);
        },
        py::arg("system"), py::arg("settings"), py::arg("options"));

    m.def(
        "track",
        [](const py::function& system, FrfSettings settings, const std::string& feature, double p_start,
           double p_end, double omega, const std::vector<double>& at, double max_step, double min_step, int max_points,
           int contact, double time_limit) {
            if (feature != "peak" && feature != "boundary" && feature != "fold")
                bad("feature = '" + feature + "' is not known: allowed peak, boundary or fold");
            TrackOptions o;
            o.feature = feature == "peak" ? TrackFeature::peak
                        : feature == "boundary" ? TrackFeature::boundary
                                                : TrackFeature::fold;
            o.p_start = p_start;
            o.p_end = p_end;
            o.omega = omega;
            o.at = at;
            o.max_step = max_step;
            o.min_step = min_step;
            o.max_points = max_points;
            o.contact = contact;
            o.stop = python_stop(time_limit);
            settings.continuation.stop = o.stop;
            const auto of = system_of(system);
            const TrackResult r = without_gil([&] { return track(of, settings, o); });
            return track_dict(r);
        },
        py::arg("system"), py::arg("settings"), py::arg("feature"), py::arg("p_start"), py::arg("p_end"), py::arg("omega"),
        py::arg("at"), py::arg("max_step"), py::arg("min_step"), py::arg("max_points"), py::arg("contact"),
        py::arg("time_limit") = 0.0);
    m.def(
        "optimize_tracking",
        [](const py::function& system, const FrfSettings& settings, const OptimizeOptions& options) {
            const auto of = system_of(system);
            const TrackOptimum t = without_gil([&] { return optimize_by_tracking(of, settings, options); });
            py::dict d;
            d["status"] = to_string(t.status);
            d["parameter"] = t.parameter;
            PeakValue peak;
            peak.value = t.value;
            peak.omega = t.omega;
            peak.state = std::isfinite(t.value) ? PeakState::bounded : PeakState::failed;
            d["peak"] = peak_dict(peak);
            std::vector<Peak> peaks;
            if (std::isfinite(t.value)) {
                peaks.push_back({t.omega, t.value, 1, true, 0, {}});
                if (std::isfinite(t.other_omega)) peaks.push_back({t.other_omega, t.value, 1, true, 0, {}});
            }
            d["peaks"] = peaks_list(peaks);
            d["bracket"] = py::make_tuple(t.parameter, t.parameter);
            d["kind"] = t.kind;
            d["check_peak"] = t.check_value;
            d["restarts"] = t.restarts;
            d["solves"] = t.solves;
            d["frfs"] = t.frfs;
            py::list tracks;
            for (const TrackResult& r : t.tracks) tracks.append(track_dict(r));
            d["tracks"] = tracks;
            d["message"] = t.message;
            d["seconds"] = t.seconds;
            d["summary"] = t.summary();
            const Verdict v = t.verdict();
            d["outcome"] = v.status();
            d["errors"] = v.errors;
            d["warnings"] = v.warnings;
            d["notes"] = v.notes;
            return d;
        },
        py::arg("system"), py::arg("settings"), py::arg("options"));

    m.def("retain_freed_memory", &retain_freed_memory,
          "glibc keeps freed memory for reuse (memory.hpp), as the hbf command does at start");
    m.def("format_number", &format_number, py::arg("value"), "15 significant digits, as in the CSV files");
    m.def("check_output", [](const std::string& path) { io::check_outputs({{"path", path, true}}); }, py::arg("path"),
          "the output policy of the hbf commands (output_file.hpp: check_outputs); ValueError naming the problem");
    m.def(
        "write_text",
        [](const std::string& path, const std::string& text) {
            io::check_outputs({{"path", path, true}});
            io::OutputFile out(path);
            out.stream() << text;
            out.commit();
        },
        py::arg("path"), py::arg("text"), "writes a whole file atomically under the output policy");
}

}  // namespace hbf::python
