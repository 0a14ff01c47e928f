// The event-exact solver on the modal form of a structure (modal_exact.hpp): checked against the
// exact solver on the structure itself, on chains small enough for it (<= 64 DOFs).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "../benchmarks/chain.hpp"
#include "hbf/event_exact.hpp"
#include "hbf/exact_polish.hpp"
#include "hbf/frf.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/modal_exact.hpp"
#include "hbf/stability.hpp"

using namespace hbf;

namespace {

/// bench::chain with the force moved to DOF `force_dof`, Rayleigh damping a M + b K (b: 1 % at
/// w1 as in bench::chain, a: 0.5 % at w1) and its `contacts` exact Coulomb contacts near the
/// free end: the force and the contacts apart, so that the load has its own residual.
System rayleigh_chain(int n, int contacts, int force_dof) {
    System s = bench::chain(n, contacts);
    const double w1 = M_PI / 2.0;
    s.damping = (2.0 * 0.005 * w1) * s.mass + (2.0 * 0.01 / w1) * s.stiffness;
    s.excitation.setZero();
    s.excitation(force_dof) = 1.0;
    return s;
}

/// The orbit of `system` at w from rest (Newton on the period map) with the outputs given.
ExactOrbit orbit_of(const System& system, double omega, const std::vector<Output>& outputs,
                    const Eigen::VectorXd* start = nullptr) {
    ExactOptions o;
    o.outputs = outputs;
    const Eigen::VectorXd rest = Eigen::VectorXd::Zero(2 * system.dofs() + 2 * static_cast<int>(system.contacts.size()));
    return exact_periodic_orbit(system, omega, start ? *start : rest, o);
}

double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

/// The largest relative change of the outputs' maxima (against the largest of them: an output
/// held at rest by a stuck contact is rounding) and of the friction energy (against the
/// excitation's work: zero friction energy in permanent stick).
double orbit_change(const ExactOrbit& a, const ExactOrbit& b) {
    double scale = 0.0, change = 0.0;
    for (double v : b.output_max) scale = std::max(scale, v);
    for (std::size_t k = 0; k < b.output_max.size(); ++k)
        change = std::max(change, std::abs(a.output_max[k] - b.output_max[k]) / scale);
    return std::max(change, std::abs(a.energy - b.energy) / b.input_energy);
}

}  // namespace

TEST_CASE("Modal exact form with every mode kept: the exact orbit of the structure itself") {
    // All 12 modes: no residual (R = 0), no attachment mode, the contacts act on q along
    // Phi^T w_c. The modal form is then an exact change of coordinates: same orbit to rounding.
    const System s = rayleigh_chain(12, 2, 5);
    const ModalExactModel model(s, 12);
    REQUIRE(model.modes() == 12);
    CHECK(model.system().dofs() == 12);  // no Ritz vector added
    const std::vector<Output> outputs{Output::dof(5), Output::dof(11), Output("relative", {{11, 1.0}, {5, -1.0}})};
    std::vector<Output> modal_outputs;
    for (const Output& o : outputs) modal_outputs.push_back(model.output(o));
    for (double w : {1.2, 1.6, 4.0}) {
        const ExactOrbit direct = orbit_of(s, w, outputs);
        REQUIRE(direct.converged);
        const Eigen::VectorXd start = model.reduce_state(direct.state);
        const ExactOrbit modal = orbit_of(model.system(), w, modal_outputs, &start);
        REQUIRE(modal.converged);
        INFO("w = " << w << ": " << direct.summary() << " | " << modal.summary());
        CHECK(orbit_change(modal, direct) < 1e-9);
        for (std::size_t k = 0; k < outputs.size(); ++k)
            CHECK(std::abs(modal.output_amp1[k] - direct.output_amp1[k]) <= 1e-9 * direct.output_max[0]);
        CHECK(modal.switches == direct.switches);
        CHECK(std::abs(modal.max_multiplier - direct.max_multiplier) < 1e-8);
        for (std::size_t c = 0; c < s.contacts.size(); ++c)
            CHECK(std::abs(modal.contacts[c].stick_fraction - direct.contacts[c].stick_fraction) < 1e-9);
    }
}

TEST_CASE("Modal exact form: the truncation error against the structure's exact orbit falls with the modes kept") {
    // A 60-DOF chain (within the direct exact solver's reach), two contacts near the free end,
    // the force at DOF 30: the exact orbit of the modal form with m modes and the Ritz vectors
    // against the structure's. The Ritz vectors carry the truncated modes exactly at w = 0 and
    // to second order in k w; what is left is the truncated modes' dynamics under the contact
    // forces' harmonics near them. The chain's modes are evenly spaced (w_j ~ (2 j - 1) pi / 2):
    // at w = 3, harmonics 10..40 of the Coulomb forces meet modes 10..40, and the error falls
    // slowly (measured, outputs and energy: 5e-3, 2e-4, 4e-6, 2e-8 at m = 5, 10, 20, 40; 1e-12
    // with all 60 modes).
    // At w = 1.2 both contacts stick the whole period: the response is smooth and the error
    // 1e-10 from m = 10 on.
    const System s = rayleigh_chain(60, 2, 29);
    const std::vector<Output> outputs{Output::dof(29), Output::dof(59)};
    for (double w : {1.2, 3.0}) {
        const ExactOrbit direct = orbit_of(s, w, outputs);
        REQUIRE(direct.converged);
        std::vector<double> errors;
        for (int m : {5, 10, 20, 40}) {
            const ModalExactModel model(s, m);
            CHECK(model.system().dofs() == m + 3);  // two attachment modes and the load's Ritz vector
            std::vector<Output> modal_outputs;
            for (const Output& o : outputs) modal_outputs.push_back(model.output(o));
            const Eigen::VectorXd start = model.reduce_state(direct.state);
            const ExactOrbit modal = orbit_of(model.system(), w, modal_outputs, &start);
            REQUIRE(modal.converged);
            CHECK(modal.switches == direct.switches);
            errors.push_back(orbit_change(modal, direct));
        }
        INFO("w = " << w << ": errors " << errors[0] << ", " << errors[1] << ", " << errors[2] << ", " << errors[3]);
        CHECK(errors[1] < 0.2 * errors[0]);
        CHECK(errors[2] < 0.2 * errors[1]);
        CHECK(errors[3] < 1e-7);
    }
}

TEST_CASE("Modal exact form: the polish of a model beyond the exact solver's size runs on it (asked for, while by default "
          "its cost declines it)") {
    // A 100-DOF chain: the structure itself is refused by the exact solver (size), its modal
    // form is not. The polish chooses the modes at the branch's highest frequency (10, 20, 40,
    // 62 until two agree to 1e-9) and says so; the refined peak is checked on a 62-mode form.
    const System s = rayleigh_chain(100, 1, 49);
    CHECK_FALSE(exact_solver_supports(s));
    CHECK(exact_solver_modes(s) == automatic_exact_modes);
    CHECK(largest_exact_modes(s) == 62);
    CHECK(exact_polish_refusal(s, 1.0).empty());
    FrfChoices choices;
    choices.omega_start = 1.5;
    choices.omega_end = 1.65;
    // By default the polish is declined before its work: one exact orbit on the modal form
    // costs about 0.7 s, some 25 s for the branch, against about 0.1 s of harmonic balance.
    const FrfSettings automatic = frf_settings(s, {Output::dof(99)}, choices);
    REQUIRE(automatic.exact_automatic);
    {
        const FrfResult declined = compute_frf(s, automatic);
        CHECK_FALSE(declined.polish);
        CHECK(declined.status() == "completed");
    }
    choices.exact = true;
    const FrfSettings settings = frf_settings(s, {Output::dof(99)}, choices);
    REQUIRE(settings.exact);
    HarmonicBalance hb(s, settings.harmonic_balance);
    const FrfResult frf = compute_frf(hb, settings);
    INFO(frf.summary() << " " << (frf.verdict.notes.empty() ? "" : frf.verdict.notes.back()));
    REQUIRE(frf.polish);
    const PolishedBranch& p = *frf.polish;
    INFO(p.summary());
    CHECK(p.modes >= 10);
    CHECK(p.truncation_omega == Approx(1.65));
    REQUIRE(std::isfinite(p.modal_truncation));
    CHECK(p.failed == 0);
    CHECK(p.polished > 10);
    CHECK_THAT(p.summary(), Catch::Contains(std::to_string(p.modes) + " modes"));
    REQUIRE_FALSE(frf.peaks.empty());
    const Peak& peak = frf.peaks.front();
    CHECK(peak.refined);
    const ModalExactModel fine(s, 62);
    const ExactOrbit check = orbit_of(fine.system(), peak.omega, {fine.output(Output::dof(99))});
    REQUIRE(check.converged);
    // within the estimated truncation (an estimate: the change to the next count), with margin
    CHECK(relative(peak.y_max, check.output_max.front()) < std::max(1e-9, 10.0 * p.modal_truncation));
}

TEST_CASE("Modal exact form: refusals name the reason") {
    System s = rayleigh_chain(100, 1, 49);
    CHECK_THROWS_WITH(ModalExactModel(s, 0), Catch::Contains("modes = 0") && Catch::Contains("1..62"));
    CHECK_THROWS_WITH(ModalExactModel(s, 63), Catch::Contains("allowed 1..62") && Catch::Contains("at most 64 DOFs"));
    System massless = s;  // a massless DOF: the modal basis needs M positive definite
    massless.mass.coeffRef(10, 10) = 0.0;
    massless.mass.prune(0.0);
    CHECK_THAT(exact_polish_refusal(massless), Catch::Contains("DOFs"));
    System dahl = s;
    dahl.contacts.front().law = FrictionLaw::dahl;
    dahl.contacts.front().stiffness = 10.0;
    CHECK(exact_solver_modes(dahl) == 0);
    CHECK_THAT(exact_polish_refusal(dahl), Catch::Contains("dahl"));
}

TEST_CASE("Modal exact form: stability verdicts of a large model come from its polish, and say so without it") {
    // The 100-DOF chain: with the polish every point has the exact multipliers of the modal
    // form; with exact off the verdict is not computed (the structure is beyond the exact
    // solver) and the message says where it would come from.
    const System s = rayleigh_chain(100, 1, 49);
    FrfChoices choices;
    choices.omega_start = 1.5;
    choices.omega_end = 1.6;
    for (bool exact : {true, false}) {
        choices.exact = exact;
        FrfSettings settings = frf_settings(s, {Output::dof(99)}, choices);
        settings.stability = true;
        HarmonicBalance hb(s, settings.harmonic_balance);
        const FrfResult frf = compute_frf(hb, settings);
        REQUIRE(frf.stability);
        const BranchStability& b = *frf.stability;
        INFO("exact " << exact << ": " << b.summary());
        if (exact) {
            CHECK(b.stable == static_cast<int>(frf.points.size()));  // a passive structure
            CHECK(b.not_computed == 0);
        } else {
            CHECK(b.not_computed == static_cast<int>(frf.points.size()));
            CHECK_THAT(b.points.front().message, Catch::Contains("modal form"));
        }
    }
}
