// Honest statuses (issue 13): a truncated, capped or doubtful result is a status, a warning and
// exit code 3, never "completed"; the energy balance of every point is checked; the library
// messages are counted, not printed; inputs that are indeterminate or out of the measured range
// are refused.
#include "glog_catch.hpp"
#include <chrono>
#include <cmath>
#include <csignal>
#include <thread>
#include <algorithm>
#include <complex>
#include <cstdlib>
#include <sstream>
#include <nlohmann/json.hpp>

#include "arguments.hpp"  // src/cli: Verdict
#include "stop_request.hpp"  // src/cli
#include "cli_support.hpp"
#include "hbf/absorber.hpp"
#include "hbf/continuation.hpp"
#include "hbf/diagnostics.hpp"
#include "hbf/frf.hpp"
#include "hbf/post_processing.hpp"
#include "support.hpp"

using namespace hbf;

TEST_CASE("Point budget: the branch is truncated, its coverage measured, and the status says so", "[status]") {
    AbsorberParameters p;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::dahl), HarmonicBalanceOptions{6, 0});
    ContinuationOptions o;
    o.max_points = 12;
    const BranchResult b = continue_branch(hb, o);
    CHECK(b.status == ContinuationStatus::point_budget);
    REQUIRE(b.points.size() >= 2);
    // Coverage: the span of the points over the range, by hand.
    const double reached = b.points.back().omega;
    CHECK(b.coverage == Approx((reached - o.omega_start) / (o.omega_end - o.omega_start)).epsilon(1e-12));
    CHECK(b.coverage < 0.5);
    ContinuationOptions full;
    const BranchResult whole = continue_branch(hb, full);
    CHECK(whole.status == ContinuationStatus::completed);
    CHECK(whole.coverage == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("hbf frf: a truncated branch is exit 3, a warning and outcome incomplete in the JSON", "[status][cli]") {
    ::test::TempDir dir;
    const auto json = dir.path / "s.json";
    const ::test::Result r = ::test::run_hbf(
        "frf --quiet --law dahl --harmonics 5 --max-step 1e-5 --out - --summary '" + json.string() + "'", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("warning: point_budget") && Catch::Contains("% of [wmin, wmax]"));
    const nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    CHECK(s["status"] == "point_budget");
    CHECK(s["outcome"] == "incomplete");
    CHECK(s["coverage"].get<double>() < 0.1);
    CHECK(s["warnings"].size() == 1);
    // The points computed are written.
    CHECK(::test::parse_csv(r.out).size() > 1000);
}

TEST_CASE("hbf frf: an unbounded resonance is capped: exit 3, status amplitude_cap, both flanks written",
          "[status][cli]") {
    // SDOF, undamped, Dahl: the friction dissipates at most 4 mu |y| per cycle against the
    // input pi F |y|, so with pi F > 4 mu the resonance grows without bound (F = 1, mu = 0.2).
    ::test::TempDir dir;
    const auto file = dir.path / "sdof.toml";
    ::test::write_file(file, "[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [1.0]\n"
                             "[[contact]]\ndof = 1\nlaw = \"dahl\"\nfriction_limit = 0.2\nstiffness = 2.0\n");
    const auto json = dir.path / "s.json";
    const ::test::Result r = ::test::run_hbf(
        "frf --quiet --harmonics 7 --config '" + file.string() + "' --summary '" + json.string() + "'", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("amplitude_cap"));
    const nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    CHECK(s["status"] == "amplitude_cap");
    CHECK(s["outcome"] == "incomplete");
    // Both flanks: the gap is the capped peak around w = 1, a fraction of a percent.
    CHECK(s["coverage"].get<double>() > 0.99);
    CHECK(s["coverage"].get<double>() < 1.0);
    // The last point of each flank is marked point = cap, one below and one above w = 1.
    const auto rows = ::test::parse_csv(r.out);
    REQUIRE(!rows.empty());
    const auto point = std::find(rows[0].begin(), rows[0].end(), "point") - rows[0].begin();
    REQUIRE(point < static_cast<long>(rows[0].size()));
    std::vector<double> caps;
    for (std::size_t k = 1; k < rows.size(); ++k)
        if (rows[k][static_cast<std::size_t>(point)] == "cap") caps.push_back(std::stod(rows[k][0]));
    REQUIRE(caps.size() == 2);
    CHECK(std::min(caps[0], caps[1]) < 1.0);
    CHECK(std::max(caps[0], caps[1]) > 1.0);
    // Bounded (pi F < 4 mu): completed, exit 0.
    ::test::write_file(file, "[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [0.2]\n"
                             "[[contact]]\ndof = 1\nlaw = \"dahl\"\nfriction_limit = 0.2\nstiffness = 2.0\n");
    const ::test::Result bounded = ::test::run_hbf("frf --quiet --harmonics 7 --config '" + file.string() + "'", dir);
    CHECK(bounded.exit_code == 0);
    // Only the note of harmonic balance's estimated error (Dahl at H = 7: about 1e-3).
    CHECK(bounded.err.rfind("hbf frf: note: harmonic balance's estimated error is ", 0) == 0);
    CHECK(std::count(bounded.err.begin(), bounded.err.end(), '\n') <= 1);
}

TEST_CASE("Energy balance: viscous dissipation by hand, and a non-solution fails the check", "[status]") {
    // A damped SDOF without contacts: y = Re(Y e^{i w t}) = Re(Y) cos - Im(Y) sin with
    // Y = F / (k - m w^2 + i c w); the input work per cycle pi F s1 = pi F (-Im Y) = pi c w |Y|^2
    // is all viscous.
    System s;
    s.mass = sparse(Eigen::MatrixXd::Constant(1, 1, 2.0));
    s.stiffness = sparse(Eigen::MatrixXd::Constant(1, 1, 3.0));
    s.damping = sparse(Eigen::MatrixXd::Constant(1, 1, 0.3));
    s.excitation = Eigen::VectorXd::Constant(1, 0.7);
    HarmonicBalance linear(s, HarmonicBalanceOptions{3, 0});
    ContinuationOptions o;
    o.omega_start = 0.5;
    o.omega_end = 2.0;
    const BranchResult b = continue_branch(linear, o);
    REQUIRE(b.status == ContinuationStatus::completed);
    Analyser analyse(linear);
    for (const SolutionPoint& point : b.points) {
        const std::complex<double> Y = 0.7 / std::complex<double>(3.0 - 2.0 * point.omega * point.omega, 0.3 * point.omega);
        const PointMetrics m = analyse(point);
        CHECK(m.viscous_energy == Approx(M_PI * 0.3 * point.omega * std::norm(Y)).epsilon(1e-8));
        CHECK(m.energy_error <= 1e-8);
    }
    // The paper's absorber with LuGre: every branch point balances; the same point moved by 1 %
    // of its amplitude in one coefficient does not.
    AbsorberParameters p;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::lugre), HarmonicBalanceOptions{8, 0});
    const BranchResult branch = continue_branch(hb, ContinuationOptions{});
    REQUIRE(branch.status == ContinuationStatus::completed);
    Analyser check(hb);
    int flagged = 0;
    for (const SolutionPoint& point : branch.points) {
        CHECK(check(point).energy_error <= energy_balance_limit(1e-9));
        SolutionPoint moved = point;
        moved.x(2) += 0.01 * hb.unknown_scale(point.x);  // s1 of y1: the input work's own coefficient
        if (check(moved).energy_error > energy_balance_limit(1e-9)) ++flagged;
    }
    CHECK(flagged == static_cast<int>(branch.points.size()));
}

TEST_CASE("Library messages: glog warnings are counted, not printed", "[status]") {
    capture_library_messages();
    MessageCollector collector;
    CHECK(collector.messages().count == 0);
    LOG(WARNING) << "a test warning";
    LOG(INFO) << "progress, not counted";
    const LibraryMessages m = collector.messages();
    CHECK(m.count == 1);
    CHECK_THAT(m.first, Catch::StartsWith("ceres: a test warning"));
}

TEST_CASE("hbf loop writes the law's own force: |f| <= mu for exact Coulomb, the series separately",
          "[status][cli][loop]") {
    ::test::TempDir dir;
    const ::test::Result r = ::test::run_hbf("loop --w 1.0", dir);  // stick-slip at w = 1
    REQUIRE(r.exit_code == 0);
    const auto rows = ::test::parse_csv(r.out);
    double f_max = 0, series_max = 0, f_mean = 0, series_mean = 0;
    int slipping = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double f = ::test::column(rows, rows[k], "f"), g = ::test::column(rows, rows[k], "f_series");
        f_max = std::max(f_max, std::abs(f));
        series_max = std::max(series_max, std::abs(g));
        f_mean += f;
        series_mean += g;
        if (::test::column(rows, rows[k], "stick") == 0.0) {
            ++slipping;
            CHECK(std::abs(f) == Approx(0.2).epsilon(1e-12));  // sliding: |f| = mu exactly
        }
    }
    CHECK(slipping > 10);
    CHECK(f_max <= 0.2 * (1 + 1e-12));
    CHECK(series_max > 0.21);  // Gibbs overshoot of the truncated series
    CHECK(series_mean == Approx(f_mean).margin(1e-9 * static_cast<double>(rows.size())));
}

TEST_CASE("Refused: parallel exact Coulomb contacts, an unmeasured --dlft-eps, an asymmetric matrix",
          "[status][cli]") {
    ::test::TempDir dir;
    const std::string absorber = "[structure]\nmass = [1.0, 0.1]\nstiffness = [[1.1, -0.1], [-0.1, 0.1]]\n"
                                 "excitation = [0.5, 0.0]\n";
    const std::string contact = "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"coulomb\"\nfriction_limit = 0.2\n";
    ::test::check_bad_config(absorber + contact + contact,
                             {"contact[2]", "same direction as contact 1", "friction_limit = 0.2 + 0.2 = 0.4"}, dir);
    const std::string reversed = "[[contact]]\ndof = 2\nother_dof = 1\nlaw = \"coulomb\"\nfriction_limit = 0.1\n";
    ::test::check_bad_config(absorber + contact + reversed, {"contact[2]", "same direction"}, dir);
    // Three exact Coulomb contacts with dependent directions (1-ground, 2-ground, 1-2: w3 = w1 -
    // w2) on a 2-DOF system: refused up front, naming the three (issue 28: the start failed with
    // a residual). hbf timeint reads the same config and refuses the same way; one of them made
    // compliant (Jenkins) is determinate and computed.
    const std::string chain = "[structure]\nmass = [1.0, 1.0]\nstiffness = [[2.0, -1.0], [-1.0, 2.0]]\n"
                              "damping = [[0.02, 0.0], [0.0, 0.02]]\nexcitation = [1.0, 0.0]\n";
    auto to_ground = [](int dof) {
        return "[[contact]]\ndof = " + std::to_string(dof) + "\nlaw = \"coulomb\"\nfriction_limit = 0.3\n";
    };
    const std::string between = "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"coulomb\"\nfriction_limit = 0.3\n";
    const std::vector<std::string> dependent = {"contact[3]", "depends linearly on those of exact Coulomb contacts 1, 2",
                                                "(w3 = w1 - w2", "rank 2"};
    ::test::check_bad_config(chain + to_ground(1) + to_ground(2) + between, dependent, dir);
    ::test::write_file(dir.path / "dependent.toml", chain + to_ground(1) + to_ground(2) + between);
    ::test::check_bad_input("timeint --w 1 --config '" + (dir.path / "dependent.toml").string() + "'", dependent, dir);
    ::test::check_bad_config(chain + between + to_ground(2) + to_ground(1),
                             {"contact[3]", "contacts 1, 2", "(w3 = w1 + w2"}, dir);
    const std::string compliant =
        "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"jenkins\"\nfriction_limit = 0.3\nstiffness = 1.0\n";
    ::test::write_file(dir.path / "compliant.toml", chain + to_ground(1) + to_ground(2) + compliant);
    CHECK(::test::run_hbf("frf --quiet --exact off --harmonics 3 --error-points 0 --wmin 0.5 --wmax 0.6 --config '" +
                              (dir.path / "compliant.toml").string() + "' --out /dev/null",
                          dir)
              .exit_code == 0);
    // Coulomb beside a Jenkins element on the same pair is determinate: accepted.
    const std::string jenkins =
        "[[contact]]\ndof = 1\nother_dof = 2\nlaw = \"jenkins\"\nfriction_limit = 0.1\nstiffness = 0.5\n";
    ::test::write_file(dir.path / "mixed.toml", absorber + contact + jenkins);
    CHECK(::test::run_hbf("frf --quiet --exact off --harmonics 5 --error-points 0 --config '" + (dir.path / "mixed.toml").string() +
                              "' --out /dev/null",
                          dir)
              .exit_code == 0);
    // --dlft-eps: along w = (1, -1), k = w'Kw = 1.4 and m = w'Mw = 1.1: automatic sqrt(k m) = 1.241,
    // allowed 1/30 to 4 times it.
    ::test::check_bad_input("frf --quiet --dlft-eps 1e-12", {"--dlft-eps", "allowed 0.0413", "4.96"}, dir);
    ::test::check_bad_input("frf --quiet --dlft-eps 10", {"--dlft-eps", "out of range"}, dir);
    CHECK(::test::run_hbf("frf --quiet --exact off --dlft-eps 0.5 --error-points 0 --out /dev/null", dir).exit_code == 0);
    ::test::check_bad_config("[structure]\nmass = [1.0, 0.1]\nstiffness = [[1.1, -0.1], [-0.2, 0.1]]\n"
                             "excitation = [0.5, 0.0]\n",
                             {"structure.stiffness", "not symmetric", "(1, 2) = -0.1", "(2, 1) = -0.2"}, dir);
}

TEST_CASE("An indefinite stiffness is accepted with a warning before the work", "[status][cli]") {
    ::test::TempDir dir;
    const ::test::Result r = ::test::run_hbf(
        "frf --quiet --config '" + std::string(HBF_SOURCE_DIR) + "/examples/systems/jenkins_negative_stiffness.toml' --out /dev/null",
        dir);
    CHECK(r.exit_code == 0);
    CHECK_THAT(r.err, Catch::Contains("warning") && Catch::Contains("stiffness matrix K is indefinite"));
}

TEST_CASE("Transitions are located with a weak corrector too: the bisection retries with more iterations",
          "[status]") {
    // One iteration per correction: the continuation moves on by its retry (100 iterations),
    // and the bisection between a stick and a stick-slip point retries likewise, so every
    // transition is still located, where the normal corrector finds it.
    AbsorberParameters p;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::jenkins), HarmonicBalanceOptions{6, 0});
    ContinuationOptions o;
    o.corrector.max_iterations = 1;
    const BranchResult weak = continue_branch(hb, o);
    const BranchResult normal = continue_branch(hb, ContinuationOptions{});
    REQUIRE(normal.transitions > 0);
    CHECK(normal.unlocated_transitions == 0);
    CHECK(weak.unlocated_transitions == 0);
    REQUIRE(weak.transitions == normal.transitions);
    std::vector<double> a, b;
    for (const SolutionPoint& q : weak.points)
        if (q.kind == PointKind::transition) a.push_back(q.omega);
    for (const SolutionPoint& q : normal.points)
        if (q.kind == PointKind::transition) b.push_back(q.omega);
    for (std::size_t k = 0; k < a.size(); ++k) CHECK(a[k] == Approx(b[k]).epsilon(1e-6));
}

TEST_CASE("The cases of issue 13: stuck undamped resonance, tiny and small excitations", "[status][cli]") {
    ::test::TempDir dir;
    // Stuck for ever (mu = 1e9) at the undamped resonance of the stuck structure, w^2 = 1/(1 + r):
    // no steady state exists; timeint says so (exit 1, converged = false), never converged.
    std::ostringstream resonance;
    resonance.precision(17);
    resonance << std::sqrt(1.0 / 1.1);
    const ::test::Result stuck = ::test::run_hbf("timeint --mu 1e9 --w " + resonance.str(), dir);
    CHECK(stuck.exit_code == 1);
    const auto rows = ::test::parse_csv(stuck.out);
    REQUIRE(rows.size() == 2);
    CHECK(std::find(rows[1].begin(), rows[1].end(), "false") != rows[1].end());
    CHECK_THAT(stuck.err, Catch::Contains("not converged"));
    // fe = 1e-6: the branch crawls along the stuck resonance and hits the point budget. It is
    // said in a few lines (no dump of library warnings) and exit 3.
    const ::test::Result tiny = ::test::run_hbf("frf --quiet --exact off --fe 1e-6 --out /dev/null", dir);
    CHECK(tiny.exit_code == 3);
    CHECK(std::count(tiny.err.begin(), tiny.err.end(), '\n') <= 4);
    CHECK_THAT(tiny.err, Catch::Contains("point_budget"));
    // fe = 1e-3: both stick|stick-slip transitions, where the stuck closed form reaches the
    // limit: r w^2 fe / |1 - (1 + r) w^2| = mu (test_cli), w^2 = mu / (r fe + mu (1 + r)) and
    // mu / (mu (1 + r) - r fe).
    const auto json = dir.path / "s.json";
    const ::test::Result small = ::test::run_hbf("frf --quiet --fe 1e-3 --out /dev/null --summary '" + json.string() + "'", dir);
    CHECK(small.exit_code == 0);
    const nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    const double r = 0.1, fe = 1e-3, mu = 0.2;
    const double expected[] = {std::sqrt(mu / (r * fe + mu * (1 + r))), std::sqrt(mu / (mu * (1 + r) - r * fe))};
    std::vector<double> found;
    for (const auto& t : s.at("transitions"))
        if (t.at("between") == "stick|stick-slip") found.push_back(t.at("w"));
    REQUIRE(found.size() == 2);
    CHECK(found[0] == Approx(expected[0]).epsilon(1e-8));
    CHECK(found[1] == Approx(expected[1]).epsilon(1e-8));
}

TEST_CASE("Output /dev/stdout is standard output: written in place, also into a pipe", "[status][cli][output]") {
    ::test::TempDir dir;
    const ::test::Result file = ::test::run_hbf("analytic --points 11 --out /dev/stdout", dir);
    CHECK(file.exit_code == 0);
    CHECK(::test::parse_csv(file.out).size() == 12);
    // Into a pipe: /dev/stdout is then a link to "pipe:[N]", which resolves to no file.
    const auto piped = dir.path / "piped.csv";
    const std::string command = std::string("'") + HBF_EXECUTABLE + "' analytic --points 11 --out /dev/stdout | cat > '" +
                                piped.string() + "'";
    CHECK(std::system(command.c_str()) == 0);
    CHECK(::test::parse_csv(::test::slurp(piped)).size() == 12);
    const ::test::Result both = ::test::run_hbf("frf --quiet --law dahl --out /dev/stdout --summary -", dir);
    CHECK(both.exit_code == 2);
    CHECK_THAT(both.err, Catch::Contains("--summary and --out both go to standard output"));
    CHECK(both.out.empty());
    // (A high number: a test runner may hold low descriptors open, e.g. 7 under CTest.)
    const ::test::Result closed = ::test::run_hbf("analytic --out /dev/fd/987", dir);
    CHECK(closed.exit_code == 2);
    CHECK_THAT(closed.err, Catch::Contains("--out") && Catch::Contains("not an open descriptor"));
}

TEST_CASE("hbf timeint checks the energy balance of every converged point: the absorber balances to 1e-6",
          "[status][cli][timeint]") {
    ::test::TempDir dir;
    for (const std::string law : {"coulomb", "jenkins", "dahl", "lugre", "coulomb-reg"}) {
        // Stick, stick-slip and slip along the sweep; a point out of balance would be exit 3.
        const ::test::Result r =
            ::test::run_hbf("timeint --quiet --law " + law + " --wmin 0.6 --wmax 1.4 --points 5 --out /dev/null", dir);
        INFO(law << ": " << r.err);
        CHECK(r.exit_code == 0);
        CHECK(r.err.empty());
    }
}

TEST_CASE("A branch's outcome sets the verdict: unlocated transitions and truncations are incomplete (exit 3) and stalls failed (exit 1)",
          "[status][cli]") {
    // No input is known that leaves a transition unlocated since the bisection's patient retry
    // (a weak corrector on the 200-DOF beam used to): the mapping is checked on branch results.
    auto judged = [](ContinuationStatus status, int unlocated, double coverage) {
        BranchResult branch;
        branch.status = status;
        branch.unlocated_transitions = unlocated;
        branch.coverage = coverage;
        branch.message = unlocated > 0 ? std::to_string(unlocated) + " transition(s) not located near w = 1.2" : "";
        FrfResult frf;
        frf.branch = branch;
        return judge_frf(frf, FrfSettings{});
    };
    const auto clean = judged(ContinuationStatus::completed, 0, 1.0);
    CHECK(clean.status() == "completed");
    CHECK(clean.warnings.empty());
    const auto unlocated = judged(ContinuationStatus::completed, 2, 1.0);
    CHECK(unlocated.status() == "incomplete");
    REQUIRE(unlocated.warnings.size() == 1);
    CHECK_THAT(unlocated.warnings[0], Catch::Contains("2 transition(s) not located") &&
                                            Catch::Contains("lacks those transition rows"));
    for (ContinuationStatus s : {ContinuationStatus::amplitude_cap, ContinuationStatus::left_range,
                                 ContinuationStatus::point_budget}) {
        const auto truncated = judged(s, 0, 0.25);
        INFO(to_string(s));
        CHECK(truncated.status() == "incomplete");
        REQUIRE(truncated.warnings.size() == 1);
        CHECK_THAT(truncated.warnings[0], Catch::Contains("spans 25 %"));
    }
    for (ContinuationStatus s :
         {ContinuationStatus::min_step, ContinuationStatus::solver_error, ContinuationStatus::start_failed}) {
        const auto stalled = judged(s, 1, 0.5);
        INFO(to_string(s));
        CHECK(stalled.status() == "failed");
        CHECK(stalled.errors.size() == 1);
    }
    // A fold's location ended by the solver: the branch is whole, a fold is unmarked.
    BranchResult lost;
    lost.coverage = 1.0;
    lost.location_errors = 1;
    lost.message = "a fold's location failed in the solver: the contact solve broke down";
    FrfResult frf;
    frf.branch = lost;
    const auto unmarked = judge_frf(frf, FrfSettings{});
    CHECK(unmarked.status() == "incomplete");
    REQUIRE(unmarked.warnings.size() == 1);
    CHECK_THAT(unmarked.warnings[0], Catch::Contains("1 fold or transition location(s) ended by the solver") &&
                                         Catch::Contains("the contact solve broke down"));
    // The exact polish's own: its transitions replace the branch's, so one it could not locate
    // is missing from the CSV as well.
    FrfResult polished;
    polished.branch.coverage = 1.0;
    polished.polish = PolishedBranch{};
    polished.polish->unlocated_transitions = 1;
    const auto missing = judge_frf(polished, FrfSettings{});
    CHECK(missing.status() == "incomplete");
    REQUIRE(missing.warnings.size() == 1);
    CHECK_THAT(missing.warnings[0],
               Catch::Contains("1 exact transition(s) not located") && Catch::Contains("lacks those transition rows"));
}

TEST_CASE("The exact polish's rows carry the exact orbit's energy balance: no false alarm at a transition",
          "[status][cli][exact]") {
    // An exact transition whose HB correction failed used to be judged by that HB solution
    // (energy_error 3e-5 at w = 1.089 on the Den Hartog design of the paper's Fig. 16, exit 3).
    // For an undamped structure each polished row now has the exact orbit's own balance.
    ::test::TempDir dir;
    const auto summary = dir.path / "s.json";
    for (const std::string args :
         {"--law coulomb --r 0.1 --wa 0.909090909090909 --mu 0.0374399556 --fe 0.12", "--law coulomb",
          "--law jenkins --wb 2"}) {
        const ::test::Result r =
            ::test::run_hbf("frf " + args + " --quiet --out /dev/null --summary '" + summary.string() + "'", dir);
        INFO(args << ": " << r.err);
        CHECK(r.exit_code == 0);
        const auto j = nlohmann::json::parse(::test::slurp(summary));
        CHECK(j["max_energy_error"].get<double>() < 1e-8);
        CHECK(j["warnings"].empty());
    }
}

TEST_CASE("A response held at exactly zero has no peaks and no energy-balance alarm (issue 28)", "[status][cli][exact]") {
    // examples/systems/den_hartog.toml with friction_limit = 1e3: the single mass sticks to the
    // ground at every w (the load |F| = 1 never reaches 1e3), so y1(t) = 0 exactly. Rounding
    // (1e-16) used to give a "peak" and a relative energy imbalance of 0.026 (exit 3).
    ::test::TempDir dir;
    const auto config = dir.path / "dh.toml", summary = dir.path / "s.json";
    ::test::write_file(config, "[structure]\nmass = [1.0]\nstiffness = [1.0]\nexcitation = [1.0]\n[[contact]]\ndof = 1\n"
                               "law = \"coulomb\"\nfriction_limit = 1e3\n[frequency]\nwmin = 0.55\nwmax = 0.75\n");
    for (const std::string exact : {"on", "off"}) {
        const ::test::Result r = ::test::run_hbf("frf --quiet --exact " + exact + " --config '" + config.string() +
                                                     "' --summary '" + summary.string() + "'",
                                                 dir);
        INFO(exact << ": " << r.err);
        CHECK(r.exit_code == 0);
        const auto rows = ::test::parse_csv(r.out);
        REQUIRE(rows.size() > 5);
        for (std::size_t k = 1; k < rows.size(); ++k) CHECK(std::abs(std::stod(rows[k][1])) < 1e-12);  // y1_max
        const auto j = nlohmann::json::parse(::test::slurp(summary));
        CHECK(j["peaks"].empty());
        CHECK(j["warnings"].empty());
        CHECK(j["max_energy_error"].get<double>() < 1e-6);
    }
    // The floor is 1e-9 of the quasi-static response |F| / k, or of the mass line |F| / (w^2 m).
    System s;
    s.mass = sparse(Eigen::MatrixXd::Identity(1, 1));
    s.stiffness = sparse(Eigen::MatrixXd::Identity(1, 1) * 4.0);
    s.excitation = Eigen::VectorXd::Constant(1, 2.0);
    CHECK(response_floor(s, 1.0) == Approx(1e-9 * 2.0 / 4.0).epsilon(1e-15));
    CHECK(response_floor(s, 10.0) == Approx(1e-9 * 2.0 / 100.0).epsilon(1e-15));  // the mass line w^2 m
}

TEST_CASE("hbf frf: the unbounded stuck resonance is capped, not stepped over (exit 3, amplitude_cap)",
          "[status][cli][resonances]") {
    // Each used to give 10 points, exit 0 and a finite "peak" across the resonance (issue 28).
    // The stuck (rigid-contact) structure is one mass 1 + r on the spring 1: the resonance at
    // w_r = 1 / sqrt(1 + r), unbounded for r = 1e-12 (exact Coulomb holds the tiny absorber),
    // and for LuGre with an enormous bristle damping sigma1 = 2 xi r wb or viscous term sigma2
    // (the contact is rigid: it dissipates ~ (r w^2 |Y|)^2 / sigma per cycle, nothing).
    ::test::TempDir dir;
    const auto json = dir.path / "s.json";
    for (const auto& [args, r] : std::vector<std::pair<std::string, double>>{
             {"--r 1e-12", 1e-12}, {"--law lugre --xi 1e12", 0.1}, {"--law lugre --viscous 1e12", 0.1}}) {
        const ::test::Result run = ::test::run_hbf("frf --quiet " + args + " --summary '" + json.string() + "'", dir);
        INFO(args << ": " << run.err);
        CHECK(run.exit_code == 3);
        CHECK_THAT(run.err, Catch::Contains("warning: amplitude_cap"));
        const nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
        CHECK(s["status"] == "amplitude_cap");
        // The two caps, one on each flank, within 0.1 % of w_r; each row above the cap.
        const double w_r = 1.0 / std::sqrt(1.0 + r);
        const auto rows = ::test::parse_csv(run.out);
        REQUIRE(rows.size() > 2);
        std::vector<double> caps;
        for (std::size_t k = 1; k < rows.size(); ++k)
            if (rows[k][static_cast<std::size_t>(std::find(rows[0].begin(), rows[0].end(), "point") - rows[0].begin())] ==
                "cap") {
                caps.push_back(std::stod(rows[k][0]));
                CHECK(::test::column(rows, rows[k], "y1_max") > 1000.0);
            }
        REQUIRE(caps.size() == 2);
        CHECK(caps[0] < w_r);
        CHECK(caps[1] > w_r);
        CHECK(caps[1] - caps[0] < 1e-3 * w_r);
    }
}

TEST_CASE("A refined peak above the amplitude cap, or a sample above every peak, is not completed",
          "[status][resonances]") {
    // The continuation without the resonance guard steps across the unbounded stuck resonance
    // of the absorber with r = 1e-12 (exact Coulomb: the rigid structure's y1 = fe / |1 - (1 + r)
    // w^2|); the peak refined between the two points across it lies far above the cap.
    AbsorberParameters p;
    p.mass_ratio = 1e-12;
    const System system = friction_absorber(p, FrictionLaw::coulomb);
    FrfSettings settings = default_frf_settings(system, {});
    settings.continuation.resolve_resonances = false;
    const FrfResult blind = compute_frf(system, settings);
    REQUIRE(blind.branch.status == ContinuationStatus::completed);
    REQUIRE(!blind.peaks.empty());
    const double cap = settings.continuation.max_amplitude;
    CHECK(std::max_element(blind.peaks.begin(), blind.peaks.end(), [](const Peak& a, const Peak& b) {
              return a.y_max < b.y_max;
          })->y_max > cap);
    CHECK(blind.peak.state == PeakState::unbounded);
    const Verdict verdict = judge_frf(blind, settings);
    CHECK(verdict.status() == "incomplete");
    CHECK_THAT(verdict.warnings.front(), Catch::Contains("above the amplitude cap 1000"));
    // With the guard: capped.
    settings.continuation.resolve_resonances = true;
    const FrfResult guarded = compute_frf(system, settings);
    CHECK(guarded.branch.status == ContinuationStatus::amplitude_cap);
    CHECK(guarded.peak.state == PeakState::unbounded);

    // r = 1e-4: samples at 0.99 and 0.999 on the rigid structure's flank (25.25 and 263.27 by
    // the closed form) above every point of the blind branch, whose largest peak was 16.77.
    p.mass_ratio = 1e-4;
    const System light = friction_absorber(p, FrictionLaw::coulomb);
    FrfSettings sampled = default_frf_settings(light, {});
    sampled.continuation.resolve_resonances = false;
    sampled.at = {0.99, 0.999};
    const FrfResult stepped = compute_frf(light, sampled);
    REQUIRE(stepped.branch.status == ContinuationStatus::completed);
    int checked = 0;
    for (std::size_t k = 0; k < stepped.points.size(); ++k)
        if (stepped.points[k].kind == PointKind::sample) {
            const double w = stepped.points[k].omega;
            CHECK(stepped.metrics[k].output_max.front() ==
                  Approx(p.excitation / std::abs(1.0 - (1.0 + p.mass_ratio) * w * w)).epsilon(1e-6));
            ++checked;
        }
    CHECK(checked == 2);
    const Verdict missed = judge_frf(stepped, sampled);
    CHECK(missed.status() == "incomplete");
    REQUIRE(!missed.warnings.empty());
    CHECK_THAT(missed.warnings.front(), Catch::Contains("--at sample at w = 0.99 ") &&
                                            Catch::Contains("above every branch point and peak"));
}

TEST_CASE("A stop (interrupt, time limit) ends the branch with status stopped and keeps its points", "[status]") {
    AbsorberParameters p;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::dahl), HarmonicBalanceOptions{6, 0});
    ContinuationOptions whole;
    const BranchResult full = continue_branch(hb, whole);
    REQUIRE(full.status == ContinuationStatus::completed);
    REQUIRE(full.points.size() > 40);
    // Asked at every step and every corrector iteration: stop at the 80th question.
    ContinuationOptions o;
    int asked = 0;
    o.stop = [&asked] { return ++asked >= 80 ? std::string("test stop") : std::string(); };
    const BranchResult b = continue_branch(hb, o);
    CHECK(b.status == ContinuationStatus::stopped);
    CHECK_THAT(b.message, Catch::Contains("test stop"));
    REQUIRE(b.points.size() >= 10);
    REQUIRE(b.points.size() < full.points.size());
    // The points kept are the full branch's (same steps), and the coverage measures them.
    for (std::size_t k = 0; k < b.points.size(); ++k) {
        CHECK(b.points[k].omega == Approx(full.points[k].omega).epsilon(1e-12));
        CHECK((b.points[k].x - full.points[k].x).cwiseAbs().maxCoeff() <= 1e-12 * full.points[k].x.cwiseAbs().maxCoeff());
    }
    CHECK(b.coverage == Approx((b.points.back().omega - o.omega_start) / (o.omega_end - o.omega_start)).epsilon(1e-12));
}

TEST_CASE("A stop during the search for the starting point (one point from a cold start) ends it with status stopped",
          "[status]") {
    AbsorberParameters p;
    HarmonicBalance hb(friction_absorber(p, FrictionLaw::dahl), HarmonicBalanceOptions{6, 0});
    ContinuationOptions o;
    o.omega_start = o.omega_end = 1.0;
    const BranchResult one = continue_branch(hb, o);
    REQUIRE(one.status == ContinuationStatus::completed);
    REQUIRE(one.points.size() == 1);
    int asked = 0;
    o.stop = [&asked] { return ++asked >= 1 ? std::string("test stop") : std::string(); };
    const BranchResult b = continue_branch(hb, o);
    CHECK(asked == 1);
    CHECK(b.status == ContinuationStatus::stopped);
    CHECK_THAT(b.message, Catch::Contains("searching the starting point") && Catch::Contains("test stop"));
    CHECK(b.points.empty());
    CHECK(b.coverage == 0.0);
}

TEST_CASE("compute_frf after a stop: the phases after the branch are skipped and named, the peak incomplete",
          "[status]") {
    AbsorberParameters p;
    const System system = friction_absorber(p, FrictionLaw::dahl);
    FrfSettings settings = default_frf_settings(system, {Output::dof(0)});
    settings.harmonic_balance.harmonics = 6;
    // Count the questions of a whole run, then stop at the last one: the branch is complete and
    // only the last phase (the error estimate) is skipped.
    int asked = 0;
    settings.continuation.stop = [&asked] {
        ++asked;
        return std::string();
    };
    const FrfResult whole = compute_frf(system, settings);
    REQUIRE(whole.branch.status == ContinuationStatus::completed);
    REQUIRE(whole.error_harmonics > 0);
    const int total = asked;
    asked = 0;
    settings.continuation.stop = [&asked, total] { return ++asked >= total ? std::string("late stop") : std::string(); };
    const FrfResult late = compute_frf(system, settings);
    CHECK(late.branch.status == ContinuationStatus::stopped);
    CHECK(late.peak.state == PeakState::incomplete);
    CHECK(late.error_harmonics == 0);
    CHECK(late.points.size() == whole.points.size());
    bool named = false;
    for (const std::string& n : late.verdict.notes) named = named || n.find("not done after the stop: the estimate") == 0;
    CHECK(named);
    CHECK_FALSE(late.verdict.warnings.empty());
    // A stop early in the branch: the peaks and the estimate are skipped, the rows are the branch's.
    asked = 0;
    settings.continuation.stop = [&asked] { return ++asked >= 10 ? std::string("early stop") : std::string(); };
    const FrfResult early = compute_frf(system, settings);
    CHECK(early.branch.status == ContinuationStatus::stopped);
    CHECK(early.peaks.empty());
    CHECK(early.points.size() < whole.points.size());
    CHECK(early.metrics.size() == early.points.size());
    for (std::size_t k = 0; k < early.points.size(); ++k)
        CHECK(early.metrics[k].output_max.front() ==
              Approx(whole.metrics[k].output_max.front()).epsilon(1e-10));
}

namespace {
/// `hbf <run>` sent SIGTERM after `seconds` (a shell's background job ignores SIGINT; SIGTERM
/// takes the same path): its exit code and standard error.
std::pair<int, std::string> terminated(const ::test::TempDir& dir, const std::string& run, int seconds) {
    const auto script = dir.path / "run.sh";
    ::test::write_file(script, "'" + std::string(HBF_EXECUTABLE) + "' " + run + " 2>'" + (dir.path / "err").string() +
                                   "' &\npid=$!\nsleep " + std::to_string(seconds) + "\nkill -TERM $pid\nwait $pid\necho $? > '" +
                                   (dir.path / "code").string() + "'\n");
    REQUIRE(std::system(("bash '" + script.string() + "'").c_str()) == 0);
    return {std::stoi(::test::slurp(dir.path / "code")), ::test::slurp(dir.path / "err")};
}

/// The same for a run writing `csv` and the JSON summary `json` (removed first): exit 3, the
/// signal named, status stopped, more than `rows` rows written.
void check_terminated(const ::test::TempDir& dir, const std::string& run, const std::filesystem::path& csv,
                      const std::filesystem::path& json, std::size_t rows) {
    std::filesystem::remove(csv);
    std::filesystem::remove(json);
    const auto [code, err] = terminated(dir, run, 2);
    CHECK(code == 3);
    CHECK_THAT(err, Catch::Contains("interrupted (SIGTERM)"));
    CHECK(nlohmann::json::parse(::test::slurp(json))["status"] == "stopped");
    CHECK(::test::parse_csv(::test::slurp(csv)).size() > rows);
}
}  // namespace

TEST_CASE("hbf frf --time-limit and SIGTERM: the points so far are written, status stopped, exit 3",
          "[status][cli]") {
    ::test::TempDir dir;
    const auto csv = dir.path / "f.csv", json = dir.path / "s.json";
    // 5000 points at --max-step 1e-5 and H = 60 take about 10 s (3 s with --time-limit 2).
    const std::string run = "frf --law dahl --harmonics 60 --max-step 1e-5 --out '" + csv.string() + "' --summary '" +
                            json.string() + "'";
    ::test::Result r = ::test::run_hbf(run + " --time-limit 2", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("time limit of 2 s (--time-limit) is reached"));
    nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    CHECK(s["status"] == "stopped");
    CHECK(s["outcome"] == "incomplete");
    auto rows = ::test::parse_csv(::test::slurp(csv));
    CHECK(rows.size() > 10);
    CHECK(rows.size() < 5000);
    CHECK(std::stod(rows[1][0]) == Approx(0.5));
    check_terminated(dir, run, csv, json, 10);
    // Bad values are refused before any work.
    r = ::test::run_hbf("frf --time-limit -1 --out '" + csv.string() + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--time-limit = -1 is out of range"));
}

TEST_CASE("hbf frf --overlay-timeint under --time-limit: the checks so far are written, the stop said, exit 3",
          "[status][cli]") {
    // The absorber's FRF on [0.5, 0.8] takes a fraction of a second; 10,000 time-integration
    // checks take minutes, so the time limit of 2 s stops them (or, on a slow machine, the FRF).
    ::test::TempDir dir;
    const auto csv = dir.path / "f.csv", json = dir.path / "s.json", checks = dir.path / "c.csv";
    const ::test::Result r = ::test::run_hbf(
        "frf --wmin 0.5 --wmax 0.8 --error-points 0 --overlay-timeint 10000 --time-limit 2 --out '" + csv.string() +
            "' --summary '" + json.string() + "' --plot '" + (dir.path / "f.svg").string() + "' --overlay-out '" +
            checks.string() + "'",
        dir);
    INFO(r.err);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("--overlay-timeint was stopped (the time limit of 2 s") &&
                          Catch::Contains("of 10000 check frequencies"));
    CHECK(nlohmann::json::parse(::test::slurp(json))["outcome"] == "incomplete");
    const auto rows = ::test::parse_csv(::test::slurp(checks));
    CHECK(rows.size() >= 2);  // the header and at least the stopped check
    CHECK(rows.size() < 10001);
    CHECK(::test::parse_csv(::test::slurp(csv)).size() > 2);
}

TEST_CASE("hbf modes --time-limit and SIGTERM: the backbone's points so far are written, status stopped, exit 3",
          "[status][cli]") {
    ::test::TempDir dir;
    const auto csv = dir.path / "m.csv", json = dir.path / "s.json";
    // The Dahl absorber's backbone at H = 60 over 9 decades in steps of at most 1e-4 (about
    // 90,000 points): far more than 2 s.
    const std::string run = "modes --law dahl --harmonics 60 --amin 1e-6 --amax 1e3 --max-step 1e-4 --max-points 100000 "
                            "--out '" + csv.string() + "' --summary '" + json.string() + "'";
    ::test::Result r = ::test::run_hbf(run + " --time-limit 2", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("time limit of 2 s (--time-limit) is reached") && Catch::Contains("stopped at a = "));
    nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    CHECK(s["status"] == "stopped");
    auto rows = ::test::parse_csv(::test::slurp(csv));
    REQUIRE(rows.size() > 3);
    CHECK(static_cast<int>(rows.size()) == s["points"].get<int>() + 1);
    CHECK(std::stod(rows[1][0]) == Approx(1e-6));
    check_terminated(dir, run, csv, json, 3);
    r = ::test::run_hbf("modes --time-limit 1e10 --out '" + csv.string() + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--time-limit = 1e10 is out of range"));
}

TEST_CASE("hbf track --time-limit: the curves so far are written, each stopped, exit 3", "[status][cli]") {
    ::test::TempDir dir;
    const auto csv = dir.path / "t.csv", json = dir.path / "s.json";
    // The Dahl absorber's two peaks over fe in steps of at most 1e-4 of the range (2000 steps of
    // several solves each): far more than 2 s.
    const ::test::Result r = ::test::run_hbf("track --law dahl --mu 0.5 --param fe --range 0.8:1 --max-step-p 1e-4 --out '" +
                                                 csv.string() + "' --summary '" + json.string() + "' --time-limit 2",
                                             dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("time limit of 2 s (--time-limit) is reached") &&
                          Catch::Contains("not done after the stop: the check FRF"));
    const nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    CHECK(s["outcome"] == "incomplete");
    REQUIRE(s["curves"].size() == 2);
    // Each curve has its points so far (how many depends on the machine's load), and the CSV
    // holds every one of them.
    std::size_t points = 0;
    for (const auto& c : s["curves"]) {
        CHECK(c["status"] == "stopped");
        CHECK(c["points"].get<std::size_t>() >= 1);
        points += c["points"].get<std::size_t>();
    }
    const auto rows = ::test::parse_csv(::test::slurp(csv));
    CHECK(rows.size() == points + 1);
}

TEST_CASE("hbf map --time-limit: the FRFs done and the one running are written, the others not computed, exit 3",
          "[status][cli]") {
    ::test::TempDir dir;
    const auto csv = dir.path / "m.csv", json = dir.path / "s.json";
    // 40 Dahl FRFs at H = 60 in steps of at most 1e-4 on one thread: minutes; stopped after 2 s.
    const ::test::Result r = ::test::run_hbf("map --law dahl --param mu --values 0.1:2:40 --harmonics 60 --max-step 1e-4 "
                                                 "--threads 1 --out '" + csv.string() + "' --summary '" + json.string() +
                                                 "' --time-limit 2",
                                             dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("FRFs are incomplete"));
    const nlohmann::json s = nlohmann::json::parse(::test::slurp(json));
    REQUIRE(s["frfs"].size() == 40);
    int stopped = 0, empty = 0;
    for (const auto& f : s["frfs"]) {
        if (f["status"] == "stopped") ++stopped;
        if (f["status"] == "stopped" && f["message"].get<std::string>().find("not computed") != std::string::npos) ++empty;
    }
    CHECK(stopped >= 39);  // the first FRF may finish within the 2 s
    CHECK(empty >= 38);
    CHECK(::test::parse_csv(::test::slurp(csv)).size() > 2);
}

TEST_CASE("StopRequest: the time limit, a caught signal and the crawl watch, paused while the run works elsewhere", "[status][cli]") {
    {
        hbf::cli::StopRequest stop("test", 0.05);
        CHECK(stop.why().empty());
        std::this_thread::sleep_for(std::chrono::milliseconds(80));
        CHECK_THAT(stop.why(), Catch::Contains("time limit of 0.05 s"));
    }
    {
        hbf::cli::StopRequest stop("test", 0.0);
        const auto ask = stop.function();
        stop.watch_crawl(1.0, 1e-3, 0.05);
        stop.reached(0.5);
        std::this_thread::sleep_for(std::chrono::milliseconds(80));
        CHECK(ask().empty());  // no time limit, no signal
        REQUIRE(stop.crawls().size() == 1);  // w moved by 0 < 1e-3 of the band in 50 ms
        CHECK_THAT(stop.crawls()[0], Catch::Contains("crawled near w = 0.5"));
        stop.reached(0.6);  // moved on: no second report
        std::this_thread::sleep_for(std::chrono::milliseconds(80));
        ask();
        CHECK(stop.crawls().size() == 1);
        // Paused (the folds located, the polish): no crawl until w is reported again, then the
        // window restarts there.
        stop.pause_crawl();
        std::this_thread::sleep_for(std::chrono::milliseconds(80));
        ask();
        CHECK(stop.crawls().size() == 1);
        stop.reached(0.6);
        ask();
        CHECK(stop.crawls().size() == 1);
        std::this_thread::sleep_for(std::chrono::milliseconds(80));
        ask();
        CHECK(stop.crawls().size() == 2);  // stuck at 0.6 for a window after the pause
        // A signal the process receives is caught once and said.
        std::raise(SIGTERM);
        CHECK(stop.why() == "interrupted (SIGTERM)");
    }
    // Destroyed: the previous handler is back (the test runner's); a new request starts clean.
    hbf::cli::StopRequest again("test", 0.0);
    CHECK(again.why().empty());
}
