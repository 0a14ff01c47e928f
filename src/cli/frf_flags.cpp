// hbf command line — the flags of one FRF (frf_flags.hpp), mapped onto the library's FRF
// choices.
#include "frf_flags.hpp"

#include <algorithm>

#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/modal_exact.hpp"

namespace hbf::cli {

bool given(const CLI::App& command, const char* flag) { return command.count(flag) > 0; }

std::vector<double> parse_frequencies(const std::string& flag, const std::string& text) {
    std::vector<double> values;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        const double w = parse_double(flag, item);
        if (!(w > 0.0)) throw UsageError(flag + " = '" + item + "' is out of range: allowed frequencies > 0");
        if (std::find(values.begin(), values.end(), w) != values.end())
            throw UsageError(flag + " = '" + text + "' lists w = " + format_number(w) +
                             " more than once: allowed distinct frequencies (each is one solved row)");
        values.push_back(w);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return values;
}

namespace {
/// "20 for coulomb, 10 for dahl, ..." from the registry (contact_law.hpp: default_harmonics).
std::string law_harmonics() {
    std::string text;
    for (const ContactLaw* law : contact_laws())
        text += (text.empty() ? "" : ", ") + std::to_string(law->default_harmonics()) + " for " + law->name();
    return text;
}
}  // namespace

void add_discretisation_flags(CLI::App& command, std::string& harmonics, std::string& time_samples,
                              const std::string& automatic) {
    command.add_option("--harmonics", harmonics,
                       "number of harmonics H, 1..100; 0 = automatic (the laws' own)\nnumber of harmonics H, 1..100, or odd[:H] for the odd harmonics only; 0 = automatic\nnumber of harmonics H, 1.." + std::to_string(max_harmonics) + "; 0 = automatic: " + automatic +
                           ": " + law_harmonics() +
                           "; times h with --excitation-harmonic h. odd or odd:H balances the odd harmonics 1, 3, 5, ... <= H only "
                       "(automatic H with odd): the half-wave symmetric solutions y(t + T/2) = -y(t), which every "
                       "law here admits under a force at an odd harmonic, with half the unknowns; a solution that "
                       "breaks the symmetry is not found")
        ->capture_default_str()->type_name("INT|odd[:H]");
    command.add_option("--time-samples", time_samples,
                       "AFT time samples per period N_t > 2H; 0 = automatic\nAFT time samples per period N_t > 2H; 0 = automatic: the smallest power of two "
                       ">= max(64, 8 (2H + 1)), raised (up to 16384, a note says so, the branch computed again) "
                       "where a law needs more at the motion found: coulomb-reg 2 pi max|v| / eps, so that its tanh is "
                       "resolved (too few samples make the FRF wiggle with spurious peaks); a given N_t below that is a "
                       "warning")
        ->capture_default_str()->type_name("INT");
}

void FrfFlags::add_to(CLI::App& command) {
    command.add_option("--wmin", wmin, "first frequency w of the branch, > 0")->capture_default_str()->type_name("NUMBER");
    command.add_option("--wmax", wmax, "last frequency w of the branch, > wmin (= wmin: one point, from a cold start)\nlast frequency w of the branch, > wmin; "
                       "= wmin: one point at that w, solved from a cold start (the linear guesses, from H = 12 on the "
                       "solution with half the harmonics, then a ramp of the force from 1e-3 of it), no continuation")->capture_default_str()->type_name("NUMBER");
    add_discretisation_flags(command, harmonics, time_samples,
                             "10 with the exact polish (HB only supplies the branch and the starting guesses); "
                             "without it the largest of the contacts' laws' own, lowered where the unknowns would "
                             "exceed the dense Jacobian's bound (a note says so)");
    command.add_option("--modes", modes,
                       "condensed formulation: 0 solves the structure directly, m > 0 by its m lowest modes\ncondensed formulation: 0 solves the structure per harmonic and frequency by a sparse LU "
                       "(exact; cost linear in N); m > 0 uses its m lowest modes plus the static residual "
                       "flexibility (cost independent of N; truncation error ~ (k w / w_{m+1})^2 of the dynamic "
                       "part; needs M > 0, K > 0 and C diagonal in the modes, e.g. Rayleigh); m at least the model's DOFs "
                       "takes every mode, nothing truncated (on a reduced model's few hundred dense coordinates "
                       "several times faster than the direct solve). A --config file's "
                       "[solver] modes applies unless given")
        ->capture_default_str()->type_name("INT");
    command.add_option("--jacobian", jacobian,
                       "the corrector's Jacobian: dense, structured (GMRES, many contact nodes) or automatic\nhow the corrector holds dR/dX: dense (formed; Ceres' dense solvers; at most 6000 unknowns), "
                       "structured (condensed formulation with every harmonic: I + G Df and the internal states' blocks "
                       "kept in their block structure, Newton steps by GMRES preconditioned with the contacts' mean "
                       "tangents; interfaces of many nodes), automatic (structured where allowed above 1500 unknowns, "
                       "above 6000 for the other laws with internal states: coulomb, dahl, lugre). A "
                       "--config file's [solver] jacobian applies unless given")
        ->type_name("FORM");
    command.add_option("--formulation", formulation,
                       "how the structure enters harmonic balance: condensed, full or automatic\nhow the linear structure enters harmonic balance: condensed (the unknowns are the contacts' "
                       "relative displacements, the structure solved exactly per harmonic by a sparse LU: any model "
                       "size), full (every DOF's coefficients: a dense Jacobian, small models), automatic (condensed "
                       "for damped or larger than 16-DOF models with an invertible K, else full)")
        ->capture_default_str()->type_name("automatic|condensed|full");
    command.add_option("--start-harmonics", start_harmonics,
                       "harmonics of a first solve at each branch start, its solution the start at H; 0 = automatic\n"
                       "harmonics H0 of a first solve at each branch start (wmin; wmax or a gap's middle after an "
                       "amplitude cap): the start is searched with H0 harmonics, and that solution, padded with zero "
                       "harmonics, is Newton's start at H (where a cold start at H fails or crawls: a meshed "
                       "interface at H = 10 and above from its H = 5 solution); where it does not converge at H, the "
                       "usual search runs at H and the summary's message says so. The excitation's harmonic..H - 1; "
                       "0: automatic (from H = 12 on, H / 2 after the linear guesses fail)")
        ->capture_default_str()->type_name("H0");
    command.add_option("--max-amplitude", max_amplitude,
                       "amplitude cap (the system's displacement units): the branch stops beyond it\namplitude cap, in the system's displacement units (nondimensional for the preset): the "
                       "branch stops when a bound of max |y_i| exceeds it (unbounded resonance), then restarts "
                       "from wmax as branch 2")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--max-step", max_step,
                       "largest arclength step (dimensionless), 1e-05..10: smaller gives denser points\nlargest arclength step, in the continuation's dimensionless coordinates (w / wmax and the "
                       "coefficients relative to the current amplitude: the same for any units); smaller values "
                       "give denser points, e.g. smoother plots of linear stretches, " +
                           format_number(ContinuationOptions::smallest_max_step) + ".." +
                           format_number(ContinuationOptions::largest_max_step))
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--tolerance", tolerance,
                       "corrector acceptance: |R|_inf <= tolerance * |F|_inf (the excitation amplitude), " +
                           format_number(CorrectorOptions::smallest_tolerance) + ".." +
                           format_number(CorrectorOptions::largest_tolerance))
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--config", config,
                       "read the structure, contacts, frequency range and settings from a TOML system file\nread the structure (any N DOFs: M, C, K, excitation, friction contacts), frequency range, "
                       "solver settings and reported outputs (DOFs or combinations of DOFs) from a TOML file (format: "
                       "include/hbf/config.hpp, examples/systems/); --wmin, --wmax, --harmonics, --time-samples and "
                       "--law override the file; the preset's parameter flags (--r, --mu, ...) are then rejected")
        ->option_text("FILE.toml");
    command.add_option("--exact", exact,
                       "polish every point by the event-exact solver (exact Coulomb, Jenkins, rigid and elastic contacts): on or off\npolish every branch point, sample, transition and peak by the event-exact periodic solver "
                       "(exact Coulomb and Jenkins: Newton shooting on closed-form flows between stick/slip events, "
                       "Floquet stability; law unilateral on massless DOFs: the same with open, stuck and slipping "
                       "nodes, in 3D by Taylor series of the turning slip direction; law elastic: Newton shooting on "
                       "its event-driven flow at 1e-11 with the flow's derivative through the events), on or off "
                       "[default: off for 3D unilateral contacts (near a meshed interface's resonance one exact orbit "
                       "can take minutes: hbf timeint --method exact sweeps them) and for law elastic (harmonic balance "
                       "converges fast there and its error is estimated; the exact orbit is not found at HB's fold "
                       "points where the exact fold lies elsewhere); on for coulomb, jenkins and 2D unilateral contacts on models of at most "
                       "64 DOFs with mass (massless DOFs are condensed statically: a contact on them becomes a "
                       "Jenkins element), a force at harmonic 1 and a period at wmin of at most 50000 Taylor steps (fewer "
                       "on large models: 2e6 / the flow's state size) "
                       "(2 pi / wmin against the slow modes; modes far above w are flowed in closed form and count by "
                       "their samples while they ring: lightly damped stiff modes at a low wmin exceed it), off "
                       "otherwise (the exact solver is dense); larger models on their modal form (up to 62 modes). "
                       "By default it is also off for more than 32 exact elements (an Iwan joint's sliders count one "
                       "each), and declined before its work (a note says why) where the modal form's estimated "
                       "truncation exceeds 1e-6 or one exact orbit times the points would take more than max(2 s, 10 "
                       "times the harmonic-balance branch); on polishes anyway; on where it does not apply is an error "
                       "naming why]")
        ->type_name("on|off");
    command.add_option("--error-points", error_points,
                       "points at which harmonic balance's truncation error is estimated (with 2H), 0..1000; 0: none\nwhere the FRF is harmonic balance's (not polished), its truncation error is estimated at "
                       "the branch's largest maxima and at points spread over it (this many of each): each solved again with twice the "
                       "harmonics, the estimate 2 |y(H) - y(2H)| / max y of the first output's y = max |o(t)|, max y its largest on the FRF (column hb_error); "
                       "0..1000, 0: no estimate")
        ->capture_default_str()->type_name("N");
    command.add_option("--error-limit", error_limit,
                       "a larger estimated error (relative) is a warning and exit code 3: the FRF is doubtful; "
                       "> 0 (1e300: never)")
        ->capture_default_str()->type_name("NUMBER");
    command.add_option("--stability", stability,
                       "Floquet stability of every point: off, on, hill, monodromy or both\nFloquet stability of every point (columns stable, stability_margin; unstable intervals and "
                       "bifurcations in the --summary; unstable parts dashed on the --plot). dahl, lugre, "
                       "coulomb-reg: hill (Hill's matrix of the variational equation on the HB harmonics, the d "
                       "exponents with the smallest |Im| kept: the classical sorted selection), monodromy (the "
                       "variational equation integrated over one period by CVODE: no sorting), both or on (both; "
                       "uncertain where they disagree); coulomb, jenkins, unilateral: any value but off takes the event-exact "
                       "orbit's multipliers (the polish's, when it runs; else the exact orbit solved from each HB point, "
                       "uncertain where it is not that point's orbit); elastic: the multipliers of the periodic orbit "
                       "law elastic's own solver finds from each HB point (the flow's derivative through the events; "
                       "uncertain where it is not that point's orbit). "
                       "Needs M positive definite (unilateral: on the DOFs with mass). Off by default: on costs about 10 times the FRF for the "
                       "smooth laws (docs: Stability)")
        ->capture_default_str()->type_name("off|on|hill|monodromy|both");
}

FrfSettings FrfFlags::settings(const CLI::App& command, ChosenSystem& chosen, const FrfChoices& made) const {
    const System& system = chosen.system;
    if (given(command, "--exact") && exact.empty()) throw UsageError("--exact is empty: allowed on, off");
    if (!exact.empty() && exact != "on" && exact != "off")
        throw UsageError("--exact = '" + exact + "' is not allowed: allowed on, off");
    // The choices: the --config file's, the flags given over them; the library makes the
    // automatic ones (frf.hpp: frf_settings: the polish on the lowest frequency, H).
    FrfChoices choices = frf_choices(command, harmonics, time_samples, chosen);
    choices.peaks = made.peaks;  // the command's own (hbf frf: its --summary and --exact)
    choices.peaks_of_every_output = made.peaks_of_every_output.value_or(false);  // a study's objective: outputs[0]
    if (given(command, "--wmin")) choices.omega_start = parse_double("--wmin", wmin);
    if (given(command, "--wmax")) choices.omega_end = parse_double("--wmax", wmax);
    if (given(command, "--modes")) choices.modes = parse_int("--modes", modes);  // range: validate()
    if (given(command, "--jacobian")) choices.jacobian = parse_jacobian_form(jacobian);  // hbf names the flag
    choices.formulation = parse_formulation(formulation);  // hbf names the flag
    if (!exact.empty()) choices.exact = exact == "on";
    FrfSettings s = frf_settings(system, chosen.outputs, choices);
    if (s.exact && choices.exact) {
        // The lowest frequency (the settings' own: flag, file or default) sets the polish's
        // cost per period (exact_cost_refusal).
        const double lowest = s.continuation.omega_start;
        const std::string refusal = exact_polish_refusal(system, lowest > 0.0 ? lowest : 0.0);
        if (!refusal.empty()) throw UsageError("--exact on: " + refusal + " (use --exact off)");
    }
    ContinuationOptions& co = s.continuation;
    co.max_amplitude = parse_double("--max-amplitude", max_amplitude);
    co.max_step = parse_double("--max-step", max_step);
    co.initial_step = std::min(co.initial_step, co.max_step);
    co.corrector.tolerance = parse_double("--tolerance", tolerance);
    co.start_harmonics = parse_int("--start-harmonics", start_harmonics);  // range: validate()
    s.error_points = parse_int("--error-points", error_points);  // ranges: validate()
    s.error_limit = parse_double("--error-limit", error_limit);
    if (stability != "off") {
        try {
            s.stability_options.method = parse_stability_method(stability == "on" ? "both" : stability);
        } catch (const InvalidInput&) {
            throw UsageError("--stability = '" + stability + "' is not known: allowed off, on, hill, monodromy, both");
        }
        const std::string refusal = stability_refusal(system);
        if (!refusal.empty()) throw UsageError("--stability " + stability + ": " + refusal);
        s.stability = true;
    }
    // The library's ranges (frf.hpp); the message names the field: hbf prefixes its flag, or
    // names the --config file's line.
    check_naming_source([&s] { s.validate(); }, command, chosen, config);
    return s;
}

}  // namespace hbf::cli
