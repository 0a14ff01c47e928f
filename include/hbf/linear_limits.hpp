// hbfriction — the linear limits of a structure with contacts: the steady state with every
// contact stuck, and where the structure resonates released, stuck or held rigid. They need
// each law's stuck element (contact_law.hpp: ContactLaw::stuck) about the static state
// (static_state.hpp), hence their place above the laws.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "hbf/model.hpp"

namespace hbf {

/// The linear steady state with every contact stuck, y = Re(amplitude e^{i h omega t}) (h the
/// system's excitation harmonic; the response is at the force's frequency h omega): exact
/// Coulomb contacts rigid (w_c^T y = 0, held by constraint forces), Jenkins and Dahl as their
/// spring k_t / sigma0, LuGre as sigma0 with the damper sigma1 + sigma2, regularised Coulomb as
/// the damper F_c / eps. No static part: the mean forces and displacements are zero.
struct StuckResponse {
    bool ok = false;            ///< false where the stuck structure is singular at omega
    Eigen::VectorXcd amplitude; ///< Y (N)
    Eigen::VectorXcd force;     ///< per contact: the complex amplitude of its force
};
StuckResponse stuck_linear_response(const System& system, double omega);

/// Where the linear structure resonates: an undamped natural frequency of one of its three
/// linear limits, as a fundamental frequency (the natural frequency divided by the excitation
/// harmonic h: the force at h omega meets it there).
///   released: M, K alone (every contact slipping freely: no friction force);
///   stuck: M, K + sum_c k_c w_c w_c^T, each contact's stuck spring k_c (Jenkins k_t, Dahl and
///          LuGre sigma0; none for coulomb and coulomb-reg); only with such a spring;
///   rigid: M, K on the subspace w_c^T y = 0 of every contact (exact Coulomb stuck, and the
///          limit of a stiff or strongly damped contact: LuGre with a large sigma1 or sigma2).
/// The damping C and the contacts' dampers are left out: damping moves a pole off the real
/// axis (a bounded resonance); an undamped limit is where an unbounded or very sharp one can
/// hide, which the continuation resolves (continuation.hpp).
struct LinearResonance {
    enum class Limit { released, stuck, rigid };
    double omega = 0;  ///< fundamental frequency of the resonance
    Limit limit = Limit::released;
};
/// "released", "stuck", "rigid".
std::string to_string(LinearResonance::Limit limit);
/// Largest model whose resonances are computed (dense generalized eigenproblems, QZ: O(N^3));
/// above it linear_resonances returns none.
constexpr int linear_resonance_dof_limit = 400;
/// The resonances of the three limits above with omega in [omega_low, omega_high], sorted by
/// omega (dense QZ of each pencil (K, M): M may be singular, whose infinite eigenvalues are
/// dropped). Empty for models above linear_resonance_dof_limit DOFs.
std::vector<LinearResonance> linear_resonances(const System& system, double omega_low, double omega_high);

}  // namespace hbf
