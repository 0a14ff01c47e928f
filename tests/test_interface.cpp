// Meshed contact interfaces (interface.hpp, [[interface]] in system files): the frames and the
// per-area parameters of the expansion, a rigid patch of many nodes against one contact with the
// summed stiffnesses and preload, and the refusals.
#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <string>
#include <tuple>
#include <vector>

#include "cli_support.hpp"
#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/error.hpp"
#include "hbf/linear_limits.hpp"
#include "hbf/static_state.hpp"
#include "hbf/harmonic_balance.hpp"
#include "hbf/interface.hpp"
#include "hbf/model.hpp"
#include "hbf/time_integration.hpp"
#include "support.hpp"

using namespace hbf;
using ::test::TempDir;
using ::test::write_file;
namespace fs = std::filesystem;

namespace {

const FrictionLaw elastic = parse_friction_law("elastic");

/// A one-node interface on DOFs `dofs` with the normal n, tangent t (3D) and area a, law elastic
/// with per-area k_t = 3, k_n = 5, its own preload N_0 = 1 and mu = 0.3, pressed by a preload
/// pressure 0.1.
ContactInterface patch(const std::vector<int>& dofs, const Eigen::VectorXd& n, const Eigen::VectorXd& t, double a) {
    ContactInterface i;
    i.nodes = {dofs};
    i.normals = n.transpose();
    if (t.size() > 0) i.tangents = t.transpose();
    i.areas = Eigen::VectorXd::Constant(1, a);
    i.prototype.law = elastic;
    i.prototype.stiffness = 3.0;
    i.prototype.values["normal_stiffness"] = 5.0;
    i.prototype.values["preload"] = 1.0;
    i.prototype.values["friction_coefficient"] = 0.3;
    i.preload_pressure = 0.1;
    return i;
}

/// A 3-DOF body (x, y, z), the contact's node: its tangential motion moves the normal load
/// through K's coupling (liftoff3 in 3D), Rayleigh damping, forced along all three axes.
System body() {
    Eigen::Matrix3d k;
    k << 1.5, 0.2, 0.5, 0.2, 1.2, 0.3, 0.5, 0.3, 1.5;
    System s;
    s.mass = sparse(Eigen::Matrix3d::Identity());
    s.stiffness = sparse(k);
    s.damping = sparse(0.03 * k);
    s.excitation = Eigen::Vector3d(0.05, 0.03, 0.15);
    return s;
}

}  // namespace

TEST_CASE("Interface expansion: orthonormal frames, per-area stiffnesses and preload, the rest copied", "[interface]") {
    ContactInterface i = patch({3, 4, 5}, Eigen::Vector3d(0.0, 0.6, 0.8), Eigen::VectorXd(), 0.25);
    i.nodes.push_back({0, 1, 2});
    i.areas = Eigen::Vector2d(0.25, 0.5);
    const std::vector<Contact> c = interface_contacts(i, 6, 6, [](int d) { return d; });
    REQUIRE(c.size() == 2);
    const System s = [&] {
        System m = body();
        m.mass = sparse(Eigen::MatrixXd::Identity(6, 6));
        m.stiffness = sparse(Eigen::MatrixXd::Identity(6, 6));
        m.damping = SparseMatrix(6, 6);
        m.excitation = Eigen::VectorXd::Zero(6);
        m.contacts = c;
        return m;
    }();
    s.validate();
    for (int k = 0; k < 2; ++k) {
        const Eigen::MatrixXd w = s.contact_directions(c[static_cast<std::size_t>(k)]);  // t1, t2, n
        REQUIRE(w.cols() == 3);
        CHECK((w.transpose() * w - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-15);
        const int first = k == 0 ? 3 : 0;
        CHECK(w.col(2).segment(first, 3).isApprox(Eigen::Vector3d(0.0, 0.6, 0.8)));
        CHECK(w.col(1).segment(first, 3).isApprox(Eigen::Vector3d(w.col(2).segment(first, 3)).cross(Eigen::Vector3d(w.col(0).segment(first, 3)))));
        // the automatic t1: the axis least aligned with n (x), made orthogonal to it
        CHECK(w.col(0).segment(first, 3).isApprox(Eigen::Vector3d(1.0, 0.0, 0.0)));
        const double area = k == 0 ? 0.25 : 0.5;
        const Contact& ck = c[static_cast<std::size_t>(k)];
        CHECK(ck.stiffness == 3.0 * area);
        CHECK(ck.values.at("normal_stiffness") == 5.0 * area);
        CHECK(ck.values.at("preload") == 1.0 * area);
        CHECK(ck.values.at("friction_coefficient") == 0.3);
    }
    // 2D: t1 is n turned by -90 degrees.
    ContactInterface flat = patch({0, 1}, Eigen::Vector2d(0.0, 1.0), Eigen::VectorXd(), 1.0);
    const Contact c2 = interface_contacts(flat, 2, 2, [](int d) { return d; }).front();
    CHECK(c2.direction.isApprox(Eigen::Vector2d(1.0, 0.0)));
    CHECK(c2.lists.count("second_direction") == 0);
}

TEST_CASE("A rigid patch of four nodes is one contact with the summed stiffnesses and preloads (1e-8)", "[interface]") {
    // Four nodes that move with the same body (each node's DOFs are the body's), areas 0.1 to
    // 0.4, against one node of area 1: each node's forces are its area times the single
    // contact's (the same stick, slip and separation), so the responses are equal. Harmonic
    // balance at H = 10 over stick, stick-slip and lift-off, both solved to 1e-12.
    const Eigen::Vector3d n(0.0, 0.0, 1.0), t(1.0, 0.0, 0.0);
    System one = body(), four = body();
    one.static_load = four.static_load = Eigen::VectorXd::Zero(3);
    for (const Contact& c : interface_contacts(patch({0, 1, 2}, n, t, 1.0), 3, 3, [](int d) { return d; }))
        one.contacts.push_back(c);
    one.static_load += interface_load(patch({0, 1, 2}, n, t, 1.0), 3);
    for (double a : {0.1, 0.2, 0.3, 0.4}) {
        for (const Contact& c : interface_contacts(patch({0, 1, 2}, n, t, a), 3, 3, [](int d) { return d; }))
            four.contacts.push_back(c);
        four.static_load += interface_load(patch({0, 1, 2}, n, t, a), 3);
    }
    CHECK(one.static_load.isApprox(Eigen::Vector3d(0.0, 0.0, 0.1)));
    // The four-node system's unknowns are the single contact's repeated for each node (every
    // node sees the same motion): its residual there must vanish, and the DOFs it recovers must
    // be the single contact's. (Following the four-node branch itself would compare two
    // continuations, which turn differently at the kinks of a nonsmooth branch.)
    const std::vector<double> omegas = {1.1, 1.5, 2.2, 2.6, 2.9};
    HarmonicBalance hb1(one, {10, 0, Formulation::automatic}), hb4(four, {10, 0, Formulation::automatic});
    REQUIRE(hb4.unknowns() == 4 * hb1.unknowns());
    bool opened = false;
    for (const SolutionPoint& p : hbf::test::sampled_points(hb1, omegas, 1.0, 3.0, 1e-12)) {
        INFO("w = " << p.omega);
        Eigen::VectorXd x4(hb4.unknowns());
        for (int node = 0; node < 4; ++node) x4.segment(node * hb1.unknowns(), hb1.unknowns()) = p.x;
        Eigen::VectorXd r1, r4;
        hb1.evaluate(p.x, p.omega, r1);
        hb4.evaluate(x4, p.omega, r4);
        CHECK(r1.cwiseAbs().maxCoeff() < 1e-12 * hb1.force_scale());
        CHECK(r4.cwiseAbs().maxCoeff() < 1e-10 * hb4.force_scale());
        const Eigen::MatrixXd y1 = hb1.dofs(p.x, p.omega), y4 = hb4.dofs(x4, p.omega);
        CHECK((y1 - y4).cwiseAbs().maxCoeff() < 1e-8 * y1.cwiseAbs().maxCoeff());
        // The band passes through lift-off: the single contact separates somewhere.
        const Eigen::VectorXd normal = hb1.force_samples(p.x, p.omega, 0).tail(hb1.time_samples());
        opened = opened || normal.minCoeff() <= 0.0;
    }
    CHECK(opened);
}

TEST_CASE("[[interface]] in a system file: nodes, frames and areas, and bad ones name the key", "[interface][config]") {
    TempDir dir;
    const fs::path file = dir.path / "s.toml";
    const std::string structure =
        "[structure]\nmass = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0]\nstiffness = [2.0, 2.0, 2.0, 2.0, 2.0, 2.0]\n"
        "excitation = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n";
    const std::string good = "[[interface]]\nname = \"pad\"\nnodes = [[1, 2, 3], [4, 5, 6]]\nnormal = [0.0, 0.0, 1.0]\n"
                             "area = [0.5, 1.5]\nlaw = \"elastic\"\nstiffness = 2.0\nnormal_stiffness = 4.0\n"
                             "friction_coefficient = 0.2\npreload_pressure = 3.0\n";
    write_file(file, structure + good);
    const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
    REQUIRE(config.system.contacts.size() == 2);
    CHECK(config.system.contacts[1].stiffness == 3.0);
    CHECK(config.system.contacts[1].values.count("preload") == 0);  // the pressure is a static load
    CHECK(config.system.static_load == (Eigen::VectorXd(6) << 0.0, 0.0, 1.5, 0.0, 0.0, 4.5).finished());
    CHECK(config.system.contacts[1].lists.at("normal_direction")[5] == 1.0);
    struct Case {
        std::string table;
        std::vector<std::string> expected;
    };
    const std::vector<Case> cases = {
        {"[[interface]]\nnodes = [[1, 2, 3], [4, 5, 9]]\nnormal = [0.0, 0.0, 1.0]\nlaw = \"elastic\"\nstiffness = 1.0\n"
         "normal_stiffness = 1.0\nfriction_coefficient = 0.2\n",
         {"interface[1].nodes", "node 2 has DOF 9", "allowed 1..6"}},
        {"[[interface]]\nnodes = [[1, 2, 3], [4, 5, 3]]\nnormal = [0.0, 0.0, 1.0]\nlaw = \"elastic\"\nstiffness = 1.0\n"
         "normal_stiffness = 1.0\nfriction_coefficient = 0.2\n",
         {"interface[1].nodes", "DOF 3 of node 2 is used twice"}},
        {"[[interface]]\nnodes = [[1, 2, 3]]\nnormal = [0.0, 0.5, 1.0]\nlaw = \"elastic\"\nstiffness = 1.0\n"
         "normal_stiffness = 1.0\nfriction_coefficient = 0.2\n",
         {"interface[1].normal", "length 1.118", "unit"}},
        {"[[interface]]\nnodes = [[1, 2, 3]]\nnormal = [0.0, 0.0, 1.0]\ntangent = [0.6, 0.0, 0.8]\nlaw = \"elastic\"\n"
         "stiffness = 1.0\nnormal_stiffness = 1.0\nfriction_coefficient = 0.2\n",
         {"interface[1].tangent", "not orthogonal"}},
        {"[[interface]]\nnodes = [[1, 2, 3]]\nnormal = [0.0, 0.0, 1.0]\narea = -1.0\nlaw = \"elastic\"\nstiffness = 1.0\n"
         "normal_stiffness = 1.0\nfriction_coefficient = 0.2\n",
         {"interface[1].area", "allowed > 0"}},
        {"[[interface]]\nnodes = [[1, 2, 3]]\nnormal = [0.0, 0.0, 1.0]\nlaw = \"jenkins\"\nstiffness = 1.0\n",
         {"interface[1].law", "no normal direction", "elastic or unilateral"}},
        {"[[interface]]\nnodes = [[1, 2, 3]]\nnormal = [0.0, 0.0, 1.0]\nlaw = \"elastic\"\npreload = 1.0\n",
         {"interface[1].preload", "unknown key", "preload_pressure"}},
        {"[[interface]]\nnodes = [[1, 2, 3]]\nnormal = [0.0, 0.0, 1.0]\nlaw = \"elastic\"\nstiffness = 1.0\n"
         "normal_stiffness = 1.0\n",
         {"interface[1] node 1", "friction_coefficient"}},
    };
    for (const Case& c : cases) hbf::test::check_refused_config(file, structure + c.table, c.expected);
    ::test::check_bad_config(structure + cases.front().table, cases.front().expected, dir);  // hbf: exit 2
}

TEST_CASE("A node pressed only by the preload pressure sticks in the linear limits, and time integration starts on "
          "its stuck orbit", "[interface][time_integration]") {
    // The one-node patch without a preload of its own (N_0 = 0): the pressure's static load is
    // what presses it (as on a meshed interface). Stuck, the body carries the node's springs
    // k_t A along t1 and t2 and k_n A along n (area 1: 3 and 5), assembled here by hand:
    //   Y = (K + S - w^2 M + i w C)^-1 F,  S = 3 (t1 t1^T + t2 t2^T) + 5 n n^T,
    // and the stuck orbit is y(t) = y_s + Re(Y e^{i w t}), y_s = (K + 5 n n^T)^-1 F_s the static
    // state without a tangential force (harmonic balance's centred convention). Before the
    // linear limits took the static state, the node counted as unloaded: no tangential spring,
    // time integration started from the free-sliding response and stuck with its sliders there
    // (the 25-node block: y_max 24 % above harmonic balance's at a stuck frequency).
    const Eigen::Vector3d n(0.0, 0.0, 1.0), t(1.0, 0.0, 0.0), t2 = n.cross(t);
    ContactInterface node = patch({0, 1, 2}, n, t, 1.0);
    node.prototype.values["preload"] = 0.0;
    node.preload_pressure = 0.5;
    System s = body();
    s.excitation *= 0.01;  // stuck: |T| stays well inside mu N = 0.15
    s.contacts = interface_contacts(node, 3, 3, [](int d) { return d; });
    s.static_load = interface_load(node, 3);
    s.validate();
    const Eigen::Matrix3d springs = 3.0 * (t * t.transpose() + t2 * t2.transpose()) + 5.0 * n * n.transpose();
    const Eigen::Matrix3d k(s.stiffness), c(s.damping);
    const double omega = 1.0;
    const Eigen::Vector3cd y = (k + springs - omega * omega * Eigen::Matrix3d::Identity() +
                                std::complex<double>(0.0, omega) * c)
                                   .fullPivLu()
                                   .solve(s.excitation.cast<std::complex<double>>());
    const StuckResponse stuck = stuck_linear_response(s, omega);
    REQUIRE(stuck.ok);
    CHECK((stuck.amplitude - y).cwiseAbs().maxCoeff() < 1e-12 * y.cwiseAbs().maxCoeff());
    // the stuck resonances: sqrt of the eigenvalues of K + S (M = I)
    const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(k + springs).eigenvalues();
    std::vector<double> stuck_limits;
    for (const LinearResonance& r : linear_resonances(s, 0.1, 10.0))
        if (r.limit == LinearResonance::Limit::stuck) stuck_limits.push_back(r.omega);
    REQUIRE(stuck_limits.size() == 3);
    for (int i = 0; i < 3; ++i) CHECK(stuck_limits[static_cast<std::size_t>(i)] == Approx(std::sqrt(lambda(i))).epsilon(1e-10));
    // time integration from linear_stuck_state (as hbf timeint starts) stays on the stuck orbit
    const Eigen::Vector3d rest = (k + 5.0 * n * n.transpose()).fullPivLu().solve(s.static_load);
    const Eigen::VectorXd start = linear_stuck_state(s, omega);
    const PeriodicResponse ti = integrate_steady_state(s, omega, hbf::test::tight_time_integration(), &start);
    INFO(ti.message);
    REQUIRE(ti.converged);
    CHECK(ti.regime == "stick");
    for (int i = 0; i < 3; ++i) {
        double y_max = 0.0;
        for (int j = 0; j < 20000; ++j) {
            const double phase = 2.0 * M_PI * j / 20000.0;
            y_max = std::max(y_max, std::abs(rest(i) + (y(i) * std::polar(1.0, phase)).real()));
        }
        INFO("DOF " << i);
        CHECK(ti.y_amp1[static_cast<std::size_t>(i)] == Approx(std::abs(y(i))).epsilon(1e-8));
        CHECK(ti.y_max[static_cast<std::size_t>(i)] == Approx(y_max).epsilon(1e-6));
    }
}

namespace {
/// Two uncoupled nodes of an interface "pad" (normal z, law elastic): node 1 driven along x,
/// node 2 not driven; harmonic balance with H harmonics.
std::string pad_file(int harmonics) {
    return "[structure]\nmass = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0]\nstiffness = [2.0, 2.0, 2.0, 2.0, 2.0, 2.0]\n"
           "excitation = [0.5, 0.0, 0.0, 0.0, 0.0, 0.0]\ndamping = [0.05, 0.05, 0.05, 0.05, 0.05, 0.05]\n"
           "[[interface]]\nname = \"pad\"\nnodes = [[1, 2, 3], [4, 5, 6]]\nnormal = [0.0, 0.0, 1.0]\n"
           "area = [0.5, 1.5]\nlaw = \"elastic\"\nstiffness = 2.0\nnormal_stiffness = 4.0\n"
           "friction_coefficient = 0.2\npreload_pressure = 3.0\n[frequency]\nwmin = 0.5\nwmax = 3.0\n"
           "[solver]\nharmonics = " + std::to_string(harmonics) + "\n";
}

/// Column `name` of a CSV table's header.
std::size_t column_of(const std::vector<std::vector<std::string>>& table, const std::string& name) {
    const auto at = std::find(table[0].begin(), table[0].end(), name);
    REQUIRE(at != table[0].end());
    return static_cast<std::size_t>(at - table[0].begin());
}

/// Row k of the pad's CSV (hbf frf or hbf timeint): the interface's shares are the means of the
/// per-node columns and add up to 1, the undriven node sticks; returns the stuck share.
double check_pad_row(const std::vector<std::vector<std::string>>& table, std::size_t k) {
    auto v = [&](const std::string& name) { return std::stod(table[k][column_of(table, name)]); };
    const double stuck = v("stuck_share_i1");
    CHECK(stuck == Approx((v("stick_fraction_c1") + v("stick_fraction_c2")) / 2).epsilon(1e-13));
    CHECK(v("open_share_i1") == Approx((v("separated_fraction_c1") + v("separated_fraction_c2")) / 2).margin(1e-14));
    CHECK(stuck + v("slip_share_i1") + v("open_share_i1") == Approx(1.0).epsilon(1e-13));
    CHECK(v("stick_fraction_c2") == 1.0);  // the undriven node sticks
    return stuck;
}
}  // namespace

TEST_CASE("hbf frf: the interface's node-averaged shares stuck, slipping and open, and --plot-contacts",
          "[interface][cli]") {
    // Two uncoupled nodes of interface "pad" (normal z): node 1 driven along x (it slips near its
    // resonance), node 2 not driven (it sticks). Each row's shares must be the means of the
    // per-node columns, and the three must add up to 1.
    TempDir dir;
    const fs::path file = dir.path / "s.toml";
    write_file(file, pad_file(5));
    const hbf::io::SystemConfig config = hbf::io::read_system_config(file.string());
    REQUIRE(config.interfaces.size() == 1);
    CHECK(config.interfaces[0].name == "pad");
    CHECK((config.interfaces[0].first == 0 && config.interfaces[0].count == 2 && config.interfaces[0].dimension == 3));
    const fs::path plot = dir.path / "states.svg";
    const auto r = hbf::test::run_hbf("frf --quiet --config '" + file.string() + "' --plot-contacts '" + plot.string() + "'", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto rows = hbf::test::parse_csv(r.out);
    REQUIRE(rows.size() > 10);
    double least = 1.0;
    for (std::size_t k = 1; k < rows.size(); ++k) least = std::min(least, check_pad_row(rows, k));
    CHECK(least < 0.9);  // node 1 slips near its resonance
    CHECK(fs::file_size(plot) > 1000);
    CHECK(hbf::test::slurp(plot).find("slipping") != std::string::npos);
    // refusals, before any work and with no output
    for (const auto& [flag, expected] : std::vector<std::pair<std::string, std::string>>{
             {"--plot-contacts ''", "--plot-contacts is empty"},
             {"--plot-contacts states.pdf", "--plot-contacts"},
             {"--plot-contacts '" + file.string() + "'", "--plot-contacts"}}) {
        const auto bad = hbf::test::run_hbf("frf --quiet --config '" + file.string() + "' " + flag, dir);
        INFO(flag << ": " << bad.err);
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find(expected) != std::string::npos);
    }
}

TEST_CASE("hbf timeint: the interface's shares stuck, slipping and open, as hbf frf's", "[interface][cli]") {
    // The two-node pad above, integrated in time (law elastic: exact event times): each row's
    // shares are the means of the per-node columns and add up to 1, the undriven node sticks,
    // and near the resonance they agree with harmonic balance's (H = 40: at H = 15 it misses node 1's
    // short stick at w = 1.4) to its sampling.
    TempDir dir;
    const fs::path file = dir.path / "s.toml";
    write_file(file, pad_file(40));
    const auto ti = hbf::test::run_hbf("timeint --quiet --config '" + file.string() + "' --wmin 1.2 --wmax 1.6 --points 3", dir);
    INFO(ti.err);
    REQUIRE(ti.exit_code == 0);
    const auto rows = hbf::test::parse_csv(ti.out);
    REQUIRE(rows.size() == 4);
    const auto hb = hbf::test::run_hbf("frf --quiet --config '" + file.string() + "' --at 1.2,1.4,1.6 --error-points 0", dir);
    INFO(hb.err);
    REQUIRE(hb.exit_code == 0);
    const auto hb_rows = hbf::test::parse_csv(hb.out);
    const std::size_t hb_stuck = column_of(hb_rows, "stuck_share_i1"), hb_point = column_of(hb_rows, "point");
    double least = 1.0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double stuck = check_pad_row(rows, k), w = std::stod(rows[k][0]);
        least = std::min(least, stuck);
        for (const auto& h : hb_rows)
            if (h[hb_point] == "sample" && std::abs(std::stod(h[0]) - w) < 1e-9) {
                INFO("w = " << w);
                CHECK(std::abs(std::stod(h[hb_stuck]) - stuck) < 0.005);  // HB counts its N_t samples
            }
    }
    CHECK(least < 0.9);
    // The columns' help lists them.
    const auto help = hbf::test::run_hbf("timeint --columns", dir);
    CHECK_THAT(help.out, Catch::Contains("stuck_share_i1") && Catch::Contains("open_share_i1"));
}

TEST_CASE("The static state of a meshed interface is described by counts and force ranges", "[interface]") {
    // Above 8 contacts one line per node would bury the message: counts per state and the
    // smallest and largest normal force and the largest tangential one, from the given forces.
    StaticState state;
    state.ok = true;
    for (int c = 0; c < 10; ++c) {
        StaticContactState k;
        k.state = c < 3 ? "open" : "stuck";
        k.force = Eigen::Vector3d(0.1 * c, -0.05 * c, c < 3 ? 0.0 : 0.5 * c);
        state.contacts.push_back(k);
    }
    // N from 0 (open) to 4.5 (c = 9), |T| up to |(0.9, -0.45)| = 1.00623058987491
    CHECK(describe(state) == "10 contacts: 3 open, 7 stuck (N from 0 to 4.5, |T| up to 1.00623058987491)");
    state.contacts.resize(2);
    CHECK(describe(state) == "contact 1: open (N = 0, |T| = 0), contact 2: open (N = 0, |T| = 0.111803398874989)");
}
