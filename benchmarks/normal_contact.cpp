// Benchmark: one AFT evaluation of the elastic contact with a normal load (normal_contact.hpp,
// issue 31) against the Jenkins law's (contact_law.hpp: the constant-load element it generalises),
// in one process, with and without the Jacobian. The designs have hundreds of such
// contacts, so this is the cost per contact and per Newton step of harmonic balance.
//
// The signals: u = cos t + 0.3 sin t + 0.1 sin 2t (and in 3D a second tangential component
// -0.2 cos t + 0.7 sin t), v = -0.1 + 0.45 cos t - 0.3 sin t, k_n = 2, k_t = 3, mu = 0.4, n_0 = 1:
// gross slip with separation; Jenkins with F_c = 0.4 and k_t = 3 on the same u. Printed per H
// (N_t = the default samples): microseconds per evaluation of each, and the ratios to Jenkins.
// The last line is one JSON object with every case.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "hbf/contact_law.hpp"
#include "hbf/fourier.hpp"
#include "hbf/contact_force.hpp"
#include "hbf/normal_contact.hpp"

using namespace hbf;

namespace {

/// Seconds per call of fn, over enough repetitions for about 0.2 s (at least 5).
template <typename F>
double per_call(F&& fn) {
    using clock = std::chrono::steady_clock;
    int repetitions = 5;
    while (true) {
        const auto start = clock::now();
        for (int r = 0; r < repetitions; ++r) fn();
        const double seconds = std::chrono::duration<double>(clock::now() - start).count();
        if (seconds > 0.2) return seconds / repetitions;
        repetitions *= 4;
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"One AFT evaluation of the normal-load contact (2D, 3D) against Jenkins' (issue 31)"};
    std::vector<int> harmonics{10, 20, 40};
    app.add_option("--harmonics", harmonics, "H values");
    CLI11_PARSE(app, argc, argv);
    nlohmann::json all = nlohmann::json::array();
    std::printf("%5s %6s %12s %12s %12s %12s %12s %12s %9s %9s %9s %9s\n", "H", "N_t", "jenkins", "jenkins+J",
                "2D", "2D+J", "3D", "3D+J", "2D/jen", "2D+J/jen", "3D/jen", "3D+J/jen");
    for (const int h : harmonics) {
        const int nt = Fourier::default_time_samples(h), n = 2 * h + 1;
        Fourier fourier(h, nt);
        Eigen::VectorXd u = Eigen::VectorXd::Zero(n), u2 = u, v = u;
        u(1) = 1.0;
        u(2) = 0.3;
        u(4) = 0.1;
        u2(1) = -0.2;
        u2(2) = 0.7;
        v(0) = -0.1;
        v(1) = 0.45;
        v(2) = -0.3;
        Contact jenkins;
        jenkins.law = FrictionLaw::jenkins;
        jenkins.friction_limit = 0.4;
        jenkins.stiffness = 3.0;
        const auto model = make_friction_model(jenkins);
        FrictionEvaluation je;
        NormalContactEvaluation ne;
        Eigen::VectorXd q2(2 * n), q3(3 * n);
        q2 << u, v;
        q3 << u, u2, v;
        const ElasticContact flat{2.0, 3.0, 0.4, 1.0, 1}, spatial{2.0, 3.0, 0.4, 1.0, 2};
        const double j0 = per_call([&] { model->evaluate(fourier, 1.0, u, Eigen::VectorXd(), je, false); });
        const double j1 = per_call([&] { model->evaluate(fourier, 1.0, u, Eigen::VectorXd(), je, true); });
        const double a0 = per_call([&] { evaluate(flat, fourier, q2, ne, false); });
        const double a1 = per_call([&] { evaluate(flat, fourier, q2, ne, true); });
        const double b0 = per_call([&] { evaluate(spatial, fourier, q3, ne, false); });
        const double b1 = per_call([&] { evaluate(spatial, fourier, q3, ne, true); });
        std::printf("%5d %6d %12.1f %12.1f %12.1f %12.1f %12.1f %12.1f %9.2f %9.2f %9.2f %9.2f\n", h, nt, j0 * 1e6,
                    j1 * 1e6, a0 * 1e6, a1 * 1e6, b0 * 1e6, b1 * 1e6, a0 / j0, a1 / j1, b0 / j0, b1 / j1);
        all.push_back({{"harmonics", h},
                       {"time_samples", nt},
                       {"jenkins_us", j0 * 1e6},
                       {"jenkins_jacobian_us", j1 * 1e6},
                       {"flat_us", a0 * 1e6},
                       {"flat_jacobian_us", a1 * 1e6},
                       {"spatial_us", b0 * 1e6},
                       {"spatial_jacobian_us", b1 * 1e6}});
    }
    std::cout << all.dump() << "\n";
    return 0;
}
