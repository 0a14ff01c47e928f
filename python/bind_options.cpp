// hbfriction._core — the options structs with their C++ names and defaults (bindings.hpp).
#include "bindings.hpp"

namespace hbf::python {

void bind_options(py::module_& m) {
    // ---- options (the C++ names and defaults) -------------------------------------------------
    py::class_<HarmonicBalanceOptions> hbo(m, "HarmonicBalanceOptions", "harmonic_balance.hpp");
    hbo.def(py::init<>())
        .def_readwrite("harmonics", &HarmonicBalanceOptions::harmonics, "H >= 1")
        .def_readwrite("time_samples", &HarmonicBalanceOptions::time_samples, "N_t > 2H; 0: automatic")
        .def_readwrite("modes", &HarmonicBalanceOptions::modes, "condensed: 0 direct, m > 0 modal receptance")
        .def_readwrite("odd_harmonics", &HarmonicBalanceOptions::odd_harmonics, "odd harmonics only");
    enum_property(hbo, "formulation", &HarmonicBalanceOptions::formulation, parse_formulation,
                  "automatic, full or condensed");
    enum_property(hbo, "jacobian", &HarmonicBalanceOptions::jacobian, parse_jacobian_form,
                  "automatic, dense or structured (dR/dX kept in its structure, GMRES: many contact nodes)");

    py::class_<CorrectorOptions> corr(m, "CorrectorOptions", "continuation.hpp");
    corr.def(py::init<>())
        .def_readwrite("max_iterations", &CorrectorOptions::max_iterations)
        .def_readwrite("tolerance", &CorrectorOptions::tolerance, "accept a correction where max abs(R) <= tolerance * max abs(F) (F the excitation)");
    enum_property(corr, "trust_region", &CorrectorOptions::trust_region, parse_trust_region,
                  "levenberg_marquardt or dogleg");
    enum_property(corr, "dense_solver", &CorrectorOptions::dense_solver, parse_dense_solver, "qr or normal_cholesky");
    enum_property(corr, "dense_library", &CorrectorOptions::dense_library, parse_dense_library, "eigen or lapack");

    py::class_<ContinuationOptions>(m, "ContinuationOptions", "continuation.hpp")
        .def(py::init<>())
        .def_readwrite("omega_start", &ContinuationOptions::omega_start)
        .def_readwrite("omega_end", &ContinuationOptions::omega_end)
        .def_readwrite("start_harmonics", &ContinuationOptions::start_harmonics,
                       "H of a first solve at each branch start, padded as the start at H (0: automatic)")
        .def_readwrite("omega_scale", &ContinuationOptions::omega_scale)
        .def_readwrite("initial_step", &ContinuationOptions::initial_step)
        .def_readwrite("min_step", &ContinuationOptions::min_step)
        .def_readwrite("max_step", &ContinuationOptions::max_step)
        .def_readwrite("max_turn", &ContinuationOptions::max_turn)
        .def_readwrite("max_points", &ContinuationOptions::max_points)
        .def_readwrite("max_amplitude", &ContinuationOptions::max_amplitude)
        .def_readwrite("locate_transitions", &ContinuationOptions::locate_transitions)
        .def_readwrite("locate_folds", &ContinuationOptions::locate_folds)
        .def_readwrite("restart_past_cap", &ContinuationOptions::restart_past_cap)
        .def_readwrite("corrector", &ContinuationOptions::corrector)
        .def("validate", [](const ContinuationOptions& o) { validate(o); });

    py::class_<StabilityOptions> sto(m, "StabilityOptions", "stability.hpp");
    sto.def(py::init<>())
        .def_readwrite("tolerance", &StabilityOptions::tolerance)
        .def_readwrite("confidence", &StabilityOptions::confidence)
        .def_readwrite("integration_tolerance", &StabilityOptions::integration_tolerance)
        .def_readwrite("max_hill_size", &StabilityOptions::max_hill_size)
        .def_readwrite("exact_gap", &StabilityOptions::exact_gap)
        .def_readwrite("exact_threads", &StabilityOptions::exact_threads,
                       "the exact solver's threads for rigid 3D contacts: 0 (two where the hardware has two cores), 1 or 2")
        .def("validate", &StabilityOptions::validate);
    sto.def_property(
        "method", [](const StabilityOptions& o) { return to_string(o.method); },
        [](StabilityOptions& o, const std::string& v) { o.method = parse_stability_method(v); }, "hill, monodromy or both");

    py::class_<FrfSettings>(m, "FrfSettings", "frf.hpp: how one FRF is computed")
        .def(py::init<>())
        .def_readwrite("harmonic_balance", &FrfSettings::harmonic_balance)
        .def_readwrite("continuation", &FrfSettings::continuation)
        .def_readwrite("exact", &FrfSettings::exact)
        .def_readwrite("outputs", &FrfSettings::outputs)
        .def_readwrite("at", &FrfSettings::at)
        .def_readwrite("peaks", &FrfSettings::peaks)
        .def_readwrite("peaks_of_every_output", &FrfSettings::peaks_of_every_output)
        .def_readwrite("stability", &FrfSettings::stability)
        .def_readwrite("stability_options", &FrfSettings::stability_options)
        .def_readwrite("error_points", &FrfSettings::error_points, "harmonic balance's error estimated at this many maxima and spread points (0: none)")
        .def_readwrite("error_limit", &FrfSettings::error_limit, "an estimated error above this is a warning")
        .def_readwrite("exact_threads", &FrfSettings::exact_threads,
                       "the exact solver's threads for rigid 3D contacts in the polish and the stability: 0 (two where the "
                       "hardware has two cores), 1 or 2")
        .def("validate", &FrfSettings::validate,
             "the library's ranges (frf.hpp: FrfSettings::validate): ValueError naming the field");
    m.def(
        "default_frf_settings",
        [](const PySystem& s) {
            // A TOML file's [frequency] and [solver] (hbf frf --config without flags).
            return frf_settings(s.system, s.reported(), s.choices);
        },
        py::arg("system"));
    m.def(
        "frf_settings",
        [](const PySystem& s, const FrfSettings& given, const std::vector<std::string>& names,
           const std::optional<bool>& exact) {
            // the file's choices, the keyword arguments `names` (their values in `given`) over
            // them, the automatic rest (frf.hpp: frf_settings)
            FrfChoices c = s.choices;
            for (const std::string& name : names) {
                if (name == "omega_start") c.omega_start = given.continuation.omega_start;
                else if (name == "omega_end") c.omega_end = given.continuation.omega_end;
                else if (name == "harmonics") c.harmonics = given.harmonic_balance.harmonics;
                else if (name == "time_samples") c.time_samples = given.harmonic_balance.time_samples;
                else if (name == "modes") c.modes = given.harmonic_balance.modes;
                else if (name == "odd_harmonics") c.odd_harmonics = given.harmonic_balance.odd_harmonics;
                else if (name == "jacobian") c.jacobian = given.harmonic_balance.jacobian;
                else if (name == "formulation") c.formulation = given.harmonic_balance.formulation;
                else bad("frf_settings: '" + name + "' is not a choice");
            }
            if (exact) c.exact = *exact;
            return frf_settings(s.system, s.reported(), c);
        },
        py::arg("system"), py::arg("given"), py::arg("names"), py::arg("exact") = py::none(),
        "hbf frf's settings for the system: its file's [frequency] and [solver], the choices `names` "
        "(values in `given`) over them, exact if not None, and the library's automatic choices (frf.hpp).");
    m.attr("max_harmonics") = hbf::max_harmonics;
    m.def(
        "contact_laws",
        [] {
            py::list out;
            for (const ContactLaw* law : contact_laws()) {
                py::dict d;
                d["name"] = law->name();
                d["definition"] = law->definition();
                py::list keys;
                for (const LawParameter& p : law->parameters()) keys.append(p.key);
                d["parameters"] = keys;
                d["preset_parameters"] = law->preset_parameters();
                d["default_harmonics"] = law->default_harmonics();
                d["smooth"] = law->smooth();
                d["exact_stick"] = law->exact_stick();
                d["preset"] = law->has_preset();
                out.append(d);
            }
            return out;
        },
        "The registry of contact laws (contact_law.hpp): name, definition, parameters (Contact keys), "
        "preset_parameters (symbols of preset_parameters()), default_harmonics, smooth, exact_stick, preset (the absorber preset can carry it).");
    m.def(
        "preset_parameters",
        [] {
            py::list out;
            for (const PresetParameter& p : preset_parameters()) {
                py::dict d;
                d["symbol"] = p.symbol;
                d["keyword"] = p.keyword;
                d["field"] = p.field_name;
                d["flag"] = p.flag;
                d["meaning"] = p.meaning;
                py::list laws;
                for (const ContactLaw* law : contact_laws())
                    if (law_reads(law->id(), p.symbol)) laws.append(law->name());
                d["laws"] = laws;
                out.append(d);
            }
            return out;
        },
        "The absorber preset's law-specific parameters (model.hpp): symbol, keyword (of absorber()), field "
        "(of AbsorberParameters), flag (of hbf), meaning, laws (that read it).");
    m.def("automatic_harmonics", [](const PySystem& s, bool exact) { return automatic_harmonics(s.system, exact); });

    py::class_<TimeIntegrationOptions> tio(m, "TimeIntegrationOptions", "time_integration.hpp");
    tio.def(py::init<>())
        .def_readwrite("relative_tolerance", &TimeIntegrationOptions::relative_tolerance)
        .def_readwrite("absolute_tolerance", &TimeIntegrationOptions::absolute_tolerance)
        .def_readwrite("displacement_scale", &TimeIntegrationOptions::displacement_scale)
        .def_readwrite("dense_newton_max_dofs", &TimeIntegrationOptions::dense_newton_max_dofs)
        .def_readwrite("steady_tolerance", &TimeIntegrationOptions::steady_tolerance)
        .def_readwrite("min_periods", &TimeIntegrationOptions::min_periods)
        .def_readwrite("max_periods", &TimeIntegrationOptions::max_periods)
        .def_readwrite("samples_per_period", &TimeIntegrationOptions::samples_per_period)
        .def_readwrite("max_events_per_period", &TimeIntegrationOptions::max_events_per_period)
        .def_readwrite("max_steps_per_period", &TimeIntegrationOptions::max_steps_per_period)
        .def_readwrite("stick_restart", &TimeIntegrationOptions::stick_restart)
        .def_readwrite("stick_restart_periods", &TimeIntegrationOptions::stick_restart_periods)
        .def_readwrite("shooting", &TimeIntegrationOptions::shooting)
        .def_readwrite("shooting_interval", &TimeIntegrationOptions::shooting_interval)
        .def_readwrite("shooting_dense_max_states", &TimeIntegrationOptions::shooting_dense_max_states)
        .def_readwrite("shooting_krylov_max", &TimeIntegrationOptions::shooting_krylov_max)
        .def_readwrite("outputs", &TimeIntegrationOptions::outputs)
        .def("validate", &TimeIntegrationOptions::validate);
    enum_property(tio, "method", &TimeIntegrationOptions::method, parse_integration_method, "adams or bdf");

    py::class_<OptimizeOptions>(m, "OptimizeOptions", "frf.hpp")
        .def(py::init<>())
        .def_readwrite("lower", &OptimizeOptions::lower)
        .def_readwrite("upper", &OptimizeOptions::upper)
        .def_readwrite("scan_points", &OptimizeOptions::scan_points)
        .def_readwrite("tolerance", &OptimizeOptions::tolerance)
        .def_readwrite("max_evaluations", &OptimizeOptions::max_evaluations)
        .def_readwrite("threads", &OptimizeOptions::threads);
}

}  // namespace hbf::python
