// hbfriction — what the event-exact solver takes: systems, states, options, and the cost
// bound of a period (event_exact.hpp).
#include "event_exact/validation.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "event_exact/engine.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/event_exact.hpp"

namespace hbf::detail::exact {

namespace {
/// The flows are dense: at most exact_solver_max_dofs DOFs with mass (those of the static
/// condensation when there are massless DOFs, model/massless.hpp).
void check_dense_size(const System& system, bool condensed) {
    if (system.dofs() > exact_solver_max_dofs)
        throw InvalidInput("the system has " + std::to_string(system.dofs()) + " DOFs" +
                           (condensed ? " with mass" : "") +
                           ": the exact solver is dense (cost ~ N^3 per step, steps as short as the fastest mode) and "
                           "allowed up to " + std::to_string(exact_solver_max_dofs) + " DOFs");
}
}  // namespace

std::unique_ptr<detail::MasslessCondensation> validate_system(const System& system, double omega) {
    system.validate();
    if (system.excitation_harmonic != 1)
        throw InvalidInput("excitation harmonic h = " + std::to_string(system.excitation_harmonic) +
                           ": the exact solver generates the force cos(w t) at the fundamental only (allowed h = 1)");
    require_positive(omega, "w", "excitation frequency");
    require_finite(omega, "w", "excitation frequency");
    for (std::size_t c = 0; c < system.contacts.size(); ++c) {
        const FrictionLaw law = system.contacts[c].law;
        if (!contact_law(law).exact_stick()) {
            std::vector<std::string> covered;
            for (const ContactLaw* l : contact_laws())
                if (l->exact_stick()) covered.emplace_back(l->name());
            std::string list, prose;  // "a, b" and "a and b"
            for (std::size_t i = 0; i < covered.size(); ++i) {
                list += (i == 0 ? "" : ", ") + covered[i];
                prose += (i == 0 ? "" : i + 1 == covered.size() ? " and " : ", ") + covered[i];
            }
            throw InvalidInput("contact " + std::to_string(c + 1) + " has law " + to_string(law) +
                               ": the exact solver covers " + prose + " only (allowed: " + list + ")");
        }
    }
    if (system.has_positive_definite_mass()) {
        check_dense_size(system, false);
        return nullptr;
    }
    try {
        auto condensation = std::make_unique<detail::MasslessCondensation>(system);
        check_dense_size(condensation->reduced(), true);
        return condensation;
    } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("the exact solver runs on the static condensation of the massless DOFs: ") +
                           e.what());
    }
}

void check_state_size(const System& system, const Eigen::VectorXd& state) {
    const int expected = 2 * system.dofs() + 2 * static_cast<int>(system.contacts.size());
    if (state.size() != expected)
        throw InvalidInput("state size = " + std::to_string(state.size()) + " is out of range: allowed " +
                           std::to_string(expected) + " (2 N + 2 n_c)");
}

}  // namespace hbf::detail::exact

namespace hbf {

using detail::exact::validate_system;

void ExactOptions::validate() const {
    if (!(tolerance >= 1e-15 && tolerance <= 1e-2))
        throw InvalidInput("exact tolerance = " + format_number(tolerance) + " is out of range: allowed 1e-15..1e-2");
    if (max_iterations < 1)
        throw InvalidInput("exact max_iterations = " + std::to_string(max_iterations) + " is out of range: allowed >= 1");
    if (warmup_periods < 1)
        throw InvalidInput("exact warmup_periods = " + std::to_string(warmup_periods) + " is out of range: allowed >= 1");
    if (restarts < 0)
        throw InvalidInput("exact restarts = " + std::to_string(restarts) + " is out of range: allowed >= 0");
    if (max_events_per_period < 4)
        throw InvalidInput("exact max_events_per_period = " + std::to_string(max_events_per_period) +
                           " is out of range: allowed >= 4");
    if (!(stability_tolerance >= 0.0 && stability_tolerance <= 1.0))
        throw InvalidInput("exact stability_tolerance = " + format_number(stability_tolerance) +
                           " is out of range: allowed 0..1");
    if (samples < 0 || samples > 10000000)
        throw InvalidInput("exact samples = " + std::to_string(samples) + " is out of range: allowed 0..1e7");
    check_exact_threads(threads, "exact threads");
}

void check_exact_threads(int threads, const std::string& name) {
    if (threads < 0 || threads > 2)
        throw InvalidInput(name + " = " + std::to_string(threads) +
                           " is out of range: allowed 0 (2 where the hardware has two cores or more), 1 or 2");
}

std::string exact_solver_refusal(const System& system) {
    try {
        system.validate();
        validate_system(TimeDomainView(system).system(), 1.0);
        return {};
    } catch (const InvalidInput& e) {
        return e.what();
    }
}

bool exact_solver_supports(const System& system) { return exact_solver_refusal(system).empty(); }

namespace {
/// A Taylor step costs about as much as this many samples of the fast modes.
constexpr double kSamplesPerStep = 16.0;
}  // namespace

namespace detail::exact {
double period_cost(Engine& e) {
    double steps = 0.0;
    for (int mode : {0, 1}) {  // every contact stuck, every contact slipping
        const ModeData& m = e.mode(Modes(static_cast<std::size_t>(e.contacts()), mode));
        // A fast mode is sampled 2 |lambda| times per unit time while it is above rounding:
        // after an event it decays by e^-37 within 37 / sigma (sigma = -Re lambda); 4 events.
        double samples = 0.0;
        for (Eigen::Index j = 0; j < m.fast.size(); ++j) {
            const double sigma = -m.fast.lambda(j).real();
            const double active = sigma > 0.0 ? std::min(e.period(), 4 * 37.0 / sigma) : e.period();
            samples = std::max(samples, 2.0 * std::abs(m.fast.lambda(j)) * active);
        }
        steps = std::max(steps, e.period() / m.h + samples / kSamplesPerStep);
    }
    return steps;
}
}  // namespace detail::exact

namespace {
/// Steps per period (exact_steps_per_period) and the size of the flows' state.
std::pair<double, int> steps_and_size(const System& given, double omega) {
    using namespace detail::exact;
    given.validate();
    const TimeDomainView view(given);  // the contacts as time-domain elements (contact_law.hpp)
    const System& system = view.system();
    const auto condensation = validate_system(system, omega);
    Engine e(condensation ? condensation->reduced() : system, omega);
    return {period_cost(e), e.n()};
}
}  // namespace

double exact_steps_per_period(const System& system, double omega) { return steps_and_size(system, omega).first; }

double exact_max_steps_per_period(int state_size) {
    return std::min(50000.0, 2e6 / std::max(state_size, 1));
}

std::string exact_cost_refusal(const System& system, double omega_min) {
    std::string why = exact_solver_refusal(system);
    if (!why.empty()) return why;
    require_positive(omega_min, "w", "lowest frequency of the exact solver");
    const auto [steps, size] = steps_and_size(system, omega_min);
    const double bound = exact_max_steps_per_period(size);
    if (steps > bound)
        return "at w = " + format_number(omega_min) + " one period takes " + format_number(std::round(steps)) +
               " Taylor steps (the period 2 pi / w against the slow modes of the structure, plus the samples "
               "of its fast modes / 16), above the bound " +
               format_number(std::round(bound)) + " that keeps the exact solver's time and memory bounded";
    return {};
}

}  // namespace hbf
