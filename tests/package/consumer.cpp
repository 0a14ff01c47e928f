// Uses the installed library: the Coulomb full-stick amplitude of the paper's absorber at
// omega = 0.5 must be fe / (1 - (1 + r) omega^2) = 0.5 / 0.725 (derived by hand).
#include <hbf/analytic.hpp>
#include <cmath>
#include <cstdio>

int main() {
    const hbf::AbsorberParameters p;  // r = 0.1, fe = 0.5
    const double y = std::abs(hbf::analytic::coulomb_stick(p, 0.5).y1);
    const double expected = 0.5 / 0.725;
    std::printf("consumer: |Y1| = %.15g, expected %.15g\n", y, expected);
    return std::abs(y - expected) < 1e-14 ? 0 : 1;
}
