// Embedding hbfriction: the frequency response of the paper's friction absorber with exact
// Coulomb friction, by harmonic balance and pseudo-arclength continuation, checked against a
// closed form. Exit code 0 when the check passes, 1 otherwise.
#include <hbf/absorber.hpp>
#include <hbf/continuation.hpp>
#include <hbf/memory.hpp>
#include <hbf/post_processing.hpp>
#include <cmath>
#include <cstdio>
#include <vector>

int main() {
    // glibc keeps freed blocks for reuse: Ceres' per-solve blocks are then not faulted in again
    // on every correction (3.4 times faster at H = 49; process-wide, so the library leaves it
    // to the program).
    hbf::retain_freed_memory();
    const hbf::AbsorberParameters p;  // the paper's absorber: r = 0.1, wa = 1, mu = 0.2, fe = 0.5
    // H = 10 harmonics (time samples chosen automatically); 20 is the CLI's default for Coulomb.
    hbf::HarmonicBalance hb(hbf::friction_absorber(p, hbf::FrictionLaw::coulomb), hbf::HarmonicBalanceOptions{10, 0});
    const hbf::BranchResult branch = hbf::continue_branch(hb, hbf::ContinuationOptions{});  // w = 0.5 .. 1.6
    std::printf("%s\n", branch.summary().c_str());
    for (const hbf::Peak& peak : hbf::find_peaks(hb, branch, 0, hbf::CorrectorOptions{}))
        std::printf("peak: w = %.6f, y1_max = %.6f\n", peak.omega, peak.y_max);

    // Independent check. Stuck, both masses move as one, |y1| = fe / |1 - (1 + r) w^2|, and the
    // contact carries the absorber's inertia force r w^2 |y1|. Stick ends where that reaches mu:
    //   w^2 = mu / (r fe + mu (1 + r)) below the resonance, mu / (mu (1 + r) - r fe) above.
    // The continuation locates these stick|stick-slip transitions by bisection (to ~1e-10).
    const double r = p.mass_ratio, fe = p.excitation, mu = p.friction_coefficient;
    const double expected[] = {std::sqrt(mu / (r * fe + mu * (1 + r))), std::sqrt(mu / (mu * (1 + r) - r * fe))};
    std::vector<double> found;
    for (const hbf::SolutionPoint& point : branch.points)
        if (point.boundary == hbf::Boundary::stick_stick_slip) found.push_back(point.omega);
    bool ok = branch.status == hbf::ContinuationStatus::completed && found.size() == 2;
    for (std::size_t k = 0; k < found.size() && k < 2; ++k) {
        std::printf("stick ends at w = %.10f, closed form %.10f\n", found[k], expected[k]);
        ok = ok && std::abs(found[k] - expected[k]) <= 1e-8 * expected[k];
    }
    std::printf("%s\n", ok ? "check passed" : "CHECK FAILED");
    return ok ? 0 : 1;
}
