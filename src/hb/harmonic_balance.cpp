// hbfriction — harmonic balance (harmonic_balance.hpp): its options, the model checks, the
// layout of the unknowns (harmonics of the DOFs, or of the contacts' relative displacements, and
// the laws' states), and the signals of a solution.
#include "hbf/harmonic_balance.hpp"

#include <algorithm>
#include <set>
#include <cmath>
#include <complex>
#include <limits>

#include "hbf/contact_law.hpp"
#include "hbf/cyclic.hpp"
#include "hbf/error.hpp"
#include "base/enum_table.hpp"

namespace hbf {

namespace {
/// d^T A d from the nonzeros of d: a contact direction has a few, and a product A d costs the
/// whole matrix per direction (an interface of a thousand directions on a dense reduced model:
/// billions of operations).
double quadratic_form(const SparseMatrix& a, const Eigen::VectorXd& d) {
    std::vector<Eigen::Index> support;
    for (Eigen::Index i = 0; i < d.size(); ++i)
        if (d(i) != 0.0) support.push_back(i);
    const auto size = static_cast<double>(support.size());
    if (size * size > static_cast<double>(a.nonZeros())) return d.dot(a * d);
    double sum = 0.0;
    for (Eigen::Index i : support) {
        double row = 0.0;
        for (Eigen::Index j : support) row += a.coeff(i, j) * d(j);
        sum += d(i) * row;
    }
    return sum;
}
}  // namespace

EvaluationStatistics operator-(const EvaluationStatistics& later, const EvaluationStatistics& earlier) {
    return {later.residuals - earlier.residuals, later.jacobians - earlier.jacobians,
            later.aft_seconds - earlier.aft_seconds, later.jacobian_seconds - earlier.jacobian_seconds,
            later.structure_seconds - earlier.structure_seconds};
}

constexpr detail::EnumName<Formulation> formulation_names[] = {
    {Formulation::automatic, "automatic"}, {Formulation::full, "full"}, {Formulation::condensed, "condensed"}};

std::string to_string(Formulation formulation) {
    return detail::enum_name(formulation_names, formulation, "formulation");
}

constexpr detail::EnumName<JacobianForm> jacobian_form_names[] = {
    {JacobianForm::automatic, "automatic"}, {JacobianForm::dense, "dense"}, {JacobianForm::structured, "structured"}};

std::string to_string(JacobianForm form) { return detail::enum_name(jacobian_form_names, form, "jacobian form"); }

JacobianForm parse_jacobian_form(const std::string& name) {
    return detail::parse_enum(jacobian_form_names, name, "jacobian");
}

Formulation parse_formulation(const std::string& name) {
    return detail::parse_enum(formulation_names, name, "formulation");
}

HarmonicBalance::HarmonicBalance(System system, HarmonicBalanceOptions options)
    : HarmonicBalance(std::move(system), options, true) {}

void HarmonicBalanceOptions::validate() const {
    if (harmonics < 1 || harmonics > max_harmonics)
        throw InvalidInput("harmonics = " + std::to_string(harmonics) + " is out of range: allowed 1.." +
                           std::to_string(max_harmonics));
    if (time_samples != 0 && (time_samples <= 2 * harmonics || time_samples > max_time_samples))
        throw InvalidInput("time_samples = " + std::to_string(time_samples) + " is out of range: allowed 0 (automatic) or " +
                           std::to_string(2 * harmonics + 1) + ".." + std::to_string(max_time_samples));
    if (modes < 0 || modes > max_modes)
        throw InvalidInput("modes = " + std::to_string(modes) + " is out of range: allowed 0 (direct solve) or 1.." +
                           std::to_string(max_modes));
}

void HarmonicBalance::validate(System system, HarmonicBalanceOptions options) {
    const HarmonicBalance checked(std::move(system), options, false);
}

int HarmonicBalance::fitting_harmonics(const System& system, HarmonicBalanceOptions options, int wanted) {
    const int h = std::max(1, system.excitation_harmonic);
    const JacobianForm asked = options.jacobian;
    options.harmonics = h;
    options.time_samples = 0;
    options.jacobian = JacobianForm::dense;
    const HarmonicBalance probe(system, options, false);
    if (asked != JacobianForm::dense && probe.structurable_) return wanted;
    // all_unknowns_ = (unknowns per coefficient) x (2H + 1), before the odd-harmonic selection
    const int per_coefficient = probe.all_unknowns_ / (2 * h + 1);
    const int fits = (max_unknowns / std::max(per_coefficient, 1) - 1) / 2;
    return std::min(wanted, fits);
}

HarmonicBalance::HarmonicBalance(System system, const HarmonicBalanceOptions& options, bool build_fourier)
    : system_(std::move(system)),
      harmonics_(options.harmonics),
      time_samples_(options.time_samples > 0 ? options.time_samples : Fourier::default_time_samples(options.harmonics)) {
    if (options.harmonics < 1)
        throw InvalidInput("harmonics = " + std::to_string(options.harmonics) + " is out of range: allowed >= 1");
    if (options.time_samples < 0)
        throw InvalidInput("time_samples = " + std::to_string(options.time_samples) +
                           " is out of range: allowed 0 (automatic) or > 2 harmonics");
    Fourier::check(harmonics_, time_samples_);
    if (options.modes < 0)
        throw InvalidInput("modes = " + std::to_string(options.modes) + " is out of range: allowed 0 (direct) or >= 1");
    system_.validate();
    if (system_.excitation_harmonic > options.harmonics)
        throw InvalidInput("harmonics = " + std::to_string(options.harmonics) + " does not reach the excitation harmonic h = " +
                           std::to_string(system_.excitation_harmonic) + ": allowed harmonics >= h");
    const int n = coefficients(), nc = static_cast<int>(system_.contacts.size());
    const bool sector = system_.cyclic.active();
    cyclic_ = sector;  // until the formulation is chosen (below): the full formulation's map
    if (sector) {
        // A sector (cyclic.hpp): the full formulation on its independent DOFs (automatic), or
        // the condensed one with the receptance on them (the direct solve).
        if (options.formulation == Formulation::condensed && options.modes > 0)
            throw InvalidInput("modes = " + std::to_string(options.modes) + ": the modal receptance does not take a "
                               "sector model (cyclic symmetry); allowed: modes = 0 (the direct solve)");
        if (options.odd_harmonics)
            throw InvalidInput("odd harmonics only: not with cyclic symmetry (allowed: every harmonic)");
        if (options.jacobian == JacobianForm::structured)
            throw InvalidInput("jacobian = structured: the condensed formulation's, not a sector model's (allowed: "
                               "dense or automatic)");
        if (system_.has_static_load())
            throw InvalidInput("static_load: a sector model (cyclic symmetry) takes no static load; allowed: none "
                               "(preloads of the contacts' laws are allowed)");
    }
    force_scale_ = system_.excitation.cwiseAbs().maxCoeff();
    if (!(force_scale_ > 0.0)) throw InvalidInput("excitation vector is zero: allowed a non-zero force amplitude");
    for (std::size_t index = 0; index < system_.contacts.size(); ++index) {
        const Contact& c = system_.contacts[index];
        if (c.base_motion != 0.0)
            throw InvalidInput("contact " + std::to_string(index + 1) + ": base_motion = " + format_number(c.base_motion) +
                               " is a time-domain element's (the static condensation of massless DOFs): allowed 0 in "
                               "harmonic balance, which keeps the massless DOFs and their load");
        const Eigen::MatrixXd w = system_.contact_directions(c);
        signal_first_.push_back(signals_);
        signal_count_.push_back(static_cast<int>(w.cols()));
        for (Eigen::Index j = 0; j < w.cols(); ++j) directions_.push_back(w.col(j));
        signals_ += static_cast<int>(w.cols());
    }
    const int ns = signals_;
    // The static deflections u_a = K^-1 w_a of every signal a (one factorisation; not ok where
    // K is singular): the static flexibility w_a^T u_a and the structure's mass along u_a, which
    // set the automatic law parameters and the condensed formulation's shift below.
    // A sector: on the sector with every dependent DOF merged into its master (harmonic 0's
    // structure, phase 0: cyclic.hpp), M0 = T0^T M T0 and w0 = T0^T w.
    const SparseMatrix t0 = cyclic_ ? cyclic_merge(system_) : SparseMatrix();
    auto merged = [&](const SparseMatrix& a) -> SparseMatrix {
        return cyclic_ ? SparseMatrix(t0.transpose() * a * t0) : a;
    };
    const SparseMatrix static_m = merged(system_.mass), static_c = merged(system_.damping),
                       static_k = merged(system_.stiffness);
    auto direction = [&](int a) -> Eigen::VectorXd {
        const Eigen::VectorXd& d = directions_[static_cast<std::size_t>(a)];
        return cyclic_ ? Eigen::VectorXd(t0.transpose() * d) : d;
    };
    Eigen::MatrixXd w(static_k.rows(), ns);
    for (int a = 0; a < ns; ++a) w.col(a) = direction(a);
    const Eigen::VectorXd static_f = cyclic_ ? Eigen::VectorXd(t0.transpose() * system_.excitation) : system_.excitation;
    const Receptance::Harmonic unshifted =
        nc > 0 ? Receptance(static_m, static_c, static_k, w, static_f, Eigen::MatrixXd(0, static_k.rows())).solve(0, 1.0, false)
               : Receptance::Harmonic{};
    Eigen::VectorXd static_stiffness = Eigen::VectorXd::Zero(ns);  // 1 / (w_a^T u_a); 0 where K is singular
    Eigen::VectorXd static_mass = Eigen::VectorXd::Zero(ns);       // phi_a^T M phi_a, phi_a = u_a / (w_a^T u_a)
    std::vector<DirectionScale> scales;
    // The static deflections and M times them, all signals at once (phi_a = u_a / g_a).
    const Eigen::MatrixXd deflections = unshifted.ok ? Eigen::MatrixXd(unshifted.solution.leftCols(ns).real()) : Eigen::MatrixXd();
    const Eigen::MatrixXd mass_deflections = unshifted.ok ? Eigen::MatrixXd(static_m * deflections) : Eigen::MatrixXd();
    const double largest_mass = static_m.diagonal().maxCoeff();
    for (int a = 0; a < ns; ++a) {
        const Eigen::VectorXd d = direction(a);
        DirectionScale scale{quadratic_form(static_k, d), quadratic_form(static_m, d), largest_mass};
        const double g = unshifted.ok ? unshifted.contact(a, a).real() : 0.0;
        if (g > 0.0 && std::isfinite(g)) {
            static_stiffness(a) = scale.static_stiffness = 1.0 / g;
            static_mass(a) = scale.static_mass = deflections.col(a).dot(mass_deflections.col(a)) / (g * g);
        }
        scales.push_back(scale);
    }
    for (int c = 0; c < nc; ++c) {
        Contact& contact = system_.contacts[static_cast<std::size_t>(c)];
        // Automatic parameters (exact Coulomb's lagrangian_penalty) from the structure along w.
        const auto first = scales.begin() + signal_first_[static_cast<std::size_t>(c)];
        contact_law(contact.law)
            .complete(contact, std::vector<DirectionScale>(first, first + signal_count_[static_cast<std::size_t>(c)]),
                      contact_name(system_.contacts, static_cast<std::size_t>(c)) + ": ");
        models_.push_back(make_friction_model(contact));
        if (models_.back()->signals() != signal_count_[static_cast<std::size_t>(c)])
            throw InvalidInput("contact " + std::to_string(c + 1) + ": law " + to_string(contact.law) + " reads " +
                               std::to_string(models_.back()->signals()) + " directions, the contact has " +
                               std::to_string(signal_count_[static_cast<std::size_t>(c)]));
    }

    // The condensed formulation solves the structure with a spring kappa_c and a damper delta_c
    // added along each contact direction (and subtracted from its friction force, so that the
    // equations are unchanged): Z'_k = Z_k + sum_c (kappa_c + i k w delta_c) w_c w_c^T is then
    // regular wherever the contacts move, also at an undamped resonance of the free structure
    // hit exactly by a harmonic, and at k = 0 for a rigid-body mode the contacts hold.
    // kappa_c = the structure's static stiffness seen by the contact, 1 / (w^T K^-1 w) (w^T K w
    // where K is singular), and delta_c = sqrt(kappa_c m_c), m_c the larger of w^T M w and the
    // mass phi^T M phi of the static deflection shape phi = K^-1 w / (w^T K^-1 w): so that the
    // shift is of the size of the contact's own dynamics (measured on the 200-DOF beam: w^T K w,
    // 4e6 times stiffer, makes the linear limits crawl at the residual's rounding level; this
    // choice in turn weighs the high harmonics ~(k w)^2 and the exact-Coulomb start of that beam
    // fails at H = 20, not at H = 10).
    // The shifted structure has a resonance of its own (kappa_c about doubles the stiffness of
    // the contact's shape: 72.75 rad/s on the cantilever beam, whose first mode is at 52.5),
    // which delta_c must damp. With the contact node's own mass w^T M w alone (~1/N on a refined
    // mesh) it did not: delta = 0.70 N s/m on the 10,000-DOF beam against sqrt(kappa phi^T M phi)
    // = 39.4; Z'_1 was singular to working precision near that resonance, G_1 was noise (fourth
    // differences over steps of 1e-8 w: 74 % of it), the corrector converged to spurious
    // solutions 0.5 % apart and the continuation stalled (min_step at 72.84 rad/s after 50
    // minutes). phi^T M phi converges with refinement, so delta_c does too. w^T M w stays where
    // it is the larger (a relative direction between lumped masses: 1.1 against 0.1 on the
    // paper's absorber, where 0.1 failed an FRF of the coarse joint optimisation in mu and wa).
    if (options.formulation != Formulation::full && nc > 0 && (!sector || options.formulation == Formulation::condensed)) {
        shift_stiffness_.resize(ns);
        shift_damping_.resize(ns);
        SparseMatrix stiffness = system_.stiffness, damping = system_.damping;
        std::vector<Eigen::Triplet<double>> stiffness_shift, damping_shift;  // kappa_c w_c w_c^T, delta_c w_c w_c^T
        for (int c = 0; c < ns; ++c) {  // every signal
            const Eigen::VectorXd& d = directions_[static_cast<std::size_t>(c)];
            const double v = quadratic_form(system_.damping, d);
            const double k = static_stiffness(c) > 0.0 ? static_stiffness(c) : std::max(quadratic_form(system_.stiffness, d), 0.0);
            const double m = std::max(static_mass(c), quadratic_form(system_.mass, d));
            shift_stiffness_(c) = k;
            shift_damping_(c) = k > 0.0 && m > 0.0 ? std::sqrt(k * m) : std::max(v, 0.0);
            // w w^T from the nonzeros of w only (never an N x N dense product)
            std::vector<int> support;
            bool unit = true;
            for (int i = 0; i < d.size(); ++i)
                if (d(i) != 0.0) {
                    support.push_back(i);
                    unit = unit && std::abs(d(i)) == 1.0;
                }
            // The structure solved is K + kappa w w^T rounded, the force corrected by the exact
            // kappa: on a refined beam (K_tt = 8.4e12 N/m, kappa = 2100) the rounding, 1e-3 N/m,
            // left a smooth error of ~2e-8 of the force in the residual, above the corrector's
            // tolerance, and the continuation crawled. For directions of +-1 entries, kappa and
            // delta are rounded to a multiple of twice the ulp of the largest entry they touch:
            // the shifted large entries are then exact (unless the sum changes binade), and what
            // rounding is left is at the level of kappa's own ulp.
            if (unit) {
                auto exact_on = [&](const SparseMatrix& a, double value) {
                    double largest = 0.0;
                    for (int i : support)
                        for (int j : support) largest = std::max(largest, std::abs(a.coeff(i, j)));
                    if (!(largest > 0.0) || !(value > 0.0)) return value;
                    const double grain = std::ldexp(1.0, std::ilogb(largest) - 51);
                    const double rounded = std::round(value / grain) * grain;
                    return rounded > 0.0 ? rounded : value;
                };
                shift_stiffness_(c) = exact_on(stiffness, shift_stiffness_(c));
                shift_damping_(c) = exact_on(damping, shift_damping_(c));
            }
            for (int i : support)
                for (int j : support) {
                    stiffness_shift.emplace_back(i, j, shift_stiffness_(c) * (d(i) * d(j)));
                    damping_shift.emplace_back(i, j, shift_damping_(c) * (d(i) * d(j)));
                }
        }
        // Added once (per signal, each addition rewrote the whole matrix).
        SparseMatrix shift(system_.dofs(), system_.dofs());
        shift.setFromTriplets(stiffness_shift.begin(), stiffness_shift.end());
        stiffness += shift;
        shift.setFromTriplets(damping_shift.begin(), damping_shift.end());
        damping += shift;
        // The receptance's directions on every DOF (w above is a sector's merged one).
        Eigen::MatrixXd w_all = w;
        if (sector) {
            w_all.resize(system_.dofs(), ns);
            for (int a = 0; a < ns; ++a) w_all.col(a) = directions_[static_cast<std::size_t>(a)];
        }
        std::unique_ptr<Receptance> receptance;
        if (options.modes > 0) {
            // The modal basis of the unshifted structure; the contact springs and dampers enter
            // exactly through the contacts' small system (receptance.hpp).
            receptance = std::make_unique<Receptance>(system_.mass, system_.damping, system_.stiffness, w_all,
                                                      system_.excitation, Eigen::MatrixXd(0, system_.dofs()));
            receptance->use_modes(options.modes, shift_stiffness_, shift_damping_);
            modes_ = receptance->modes();
        } else {
            receptance = std::make_unique<Receptance>(system_.mass, damping, stiffness, w_all, system_.excitation,
                                                      Eigen::MatrixXd(0, system_.dofs()));
            if (sector) receptance->set_cyclic(system_.cyclic.neighbours, system_.cyclic.phase());
        }
        // The N-long solution only where the direct solve gives it anyway (dofs() applies the
        // modal receptance to the forces instead).
        Receptance::Harmonic h0 = receptance->solve(0, 1.0, false, options.modes == 0);
        // Each signal's static flexibility G_0,cc (its rows' scale). A sector's contact between a
        // DOF and its own image in the next sector does not move at harmonic 0 (nor where k EO =
        // 0 mod N: G_0,cc = 0, its rows Q = 0): its scale is then 1 / (w^T K' w) of the sector.
        Eigen::VectorXd flexibility = h0.ok ? Eigen::VectorXd(h0.contact.real().diagonal()) : Eigen::VectorXd();
        if (h0.ok && sector)
            for (int a = 0; a < ns; ++a) {
                const double k = quadratic_form(stiffness, directions_[static_cast<std::size_t>(a)]);
                if (!(flexibility(a) > 1e-12 * (k > 0.0 ? 1.0 / k : 0.0)) && k > 0.0) flexibility(a) = 1.0 / k;
            }
        const bool usable = h0.ok && (flexibility.array() > 0.0).all();
        if (usable && system_.has_static_load()) {
            // Harmonic 0 of the static load on the shifted structure: one more sparse solve of K'.
            Receptance loaded(system_.mass, damping, stiffness, w_all, system_.static_load, Eigen::MatrixXd(0, system_.dofs()));
            const Receptance::Harmonic s0 = loaded.solve(0, 1.0, true, true);
            if (s0.ok) {
                static_contact_ = s0.contact_load.real();
                static_deflection_ = s0.solution.col(ns).real();
            } else if (options.formulation == Formulation::condensed) {
                throw InvalidInput("formulation = condensed: the static load meets a singular static problem (" +
                                   s0.message + "); allowed: formulation = full");
            }
        }
        if (usable && (!system_.has_static_load() || static_contact_.size() > 0)) {
            condensed_ = true;
            receptance_ = std::move(receptance);
            static_flexibility_ = flexibility;
            harmonic_ = std::make_shared<std::vector<Receptance::Harmonic>>(static_cast<std::size_t>(harmonics() + 1));
            (*harmonic_)[0] = std::move(h0);
        } else if (options.formulation == Formulation::condensed) {
            throw InvalidInput("formulation = condensed needs a regular static problem (harmonic 0): " +
                               (h0.ok ? std::string("a contact direction has no static flexibility")
                                      : h0.message) +
                               "; allowed: formulation = full");
        }
    } else if (options.formulation == Formulation::condensed && nc == 0) {
        throw InvalidInput("formulation = condensed needs at least one contact: allowed full for a linear system");
    }
    cyclic_ = sector && !condensed_;  // a condensed sector's unknowns are its contacts' signals, as any model's
    if (options.modes > 0 && !condensed_)
        throw InvalidInput("modes = " + std::to_string(options.modes) +
                           ": the modal receptance belongs to the condensed formulation, which this system does not "
                           "use (allowed: modes = 0)");
    all_unknowns_ = (condensed_ ? ns : system_.dofs()) * n;
    // A displacement floor for the full formulation's unknowns: the force over the stiffest
    // diagonal entry (a displacement in the system's units; the force scale itself is for
    // nondimensional K ~ 1).
    const double k_max = system_.stiffness.diagonal().cwiseAbs().maxCoeff();
    full_displacement_scale_ = k_max > 0.0 ? force_scale_ / k_max : force_scale_;
    for (const auto& model : models_) {
        state_offset_.push_back(model->state_signals() > 0 ? all_unknowns_ : -1);
        state_count_.push_back(model->state_signals());
        all_unknowns_ += model->state_signals() * n;
    }
    // The Jacobian's form: structured only for the condensed formulation with every harmonic
    // (structured_jacobian.hpp). Automatic: above structured_threshold unknowns for memoryless
    // laws; where contacts carry internal states (Lagrange multipliers, bristles) whose law
    // prefers the dense form (ContactLaw::states_prefer_dense), only where the dense form is not
    // allowed (its trust-region corrector is the more robust on their nonsmooth residuals).
    const bool memoryless =
        std::all_of(state_count_.begin(), state_count_.end(), [](int states) { return states == 0; });
    bool structured_early = true;  // structured from structured_threshold unknowns on
    for (std::size_t c = 0; c < state_count_.size(); ++c)
        if (state_count_[c] > 0 && contact_law(system_.contacts[c].law).states_prefer_dense()) structured_early = false;
    const bool structurable = condensed_ && !options.odd_harmonics;
    structurable_ = structurable;
    if (options.jacobian == JacobianForm::structured && !structurable)
        throw InvalidInput(std::string("jacobian = structured needs ") +
                           (!condensed_ ? "the condensed formulation, which this system does not use"
                                        : "every harmonic (odd_harmonics = false)") +
                           ": allowed jacobian = dense or automatic");
    structured_ = options.jacobian == JacobianForm::structured ||
                  (options.jacobian == JacobianForm::automatic && structurable &&
                   all_unknowns_ > (structured_early ? structured_threshold : max_unknowns));
    if (structured_) {
        // The receptances (G_k and dG_k/domega, or G_B, G_B' and an LU: up to 48 bytes per
        // entry), held twice (this evaluation's and the preconditioner's older one), the
        // preconditioner's LU and the products' temporaries: measured 150 to 180 (H + 1) n_s^2
        // bytes of peak memory (benchmarks/interface_nodes: 534 MB at n_s = 600, H = 7); with
        // internal states the preconditioner's blocks take n_s + n_z rows (counted as n_s).
        const double nu = static_cast<double>(all_unknowns_ / n);
        const double bytes = 160.0 * (harmonics_ + 1) * nu * nu;
        if (bytes > max_structured_bytes)
            throw InvalidInput("harmonics = " + std::to_string(harmonics_) + " with " + std::to_string(all_unknowns_ / n) +
                               (memoryless ? " contact directions" : " contact directions and internal states") + " needs " + format_number(std::round(bytes / 1048576.0)) +
                               " MB for the receptances and the preconditioner (about 160 (H + 1) n^2 bytes): allowed at most " +
                               format_number(std::floor(max_structured_bytes / 1048576.0)) +
                               " MB (fewer harmonics, fewer contact nodes)");
    }
    // The dense Jacobian (all_unknowns_^2 doubles, held by the corrector, Ceres and the
    // tangent: about four copies) is bounded so that every allowed input runs in bounded
    // memory (6000 unknowns: about 1 GB in all).
    if (!structured_ && all_unknowns_ > max_unknowns) {
        const int signals = all_unknowns_ / n;
        const int fits = (max_unknowns / signals - 1) / 2;  // the largest H with signals x (2H + 1) <= the bound
        throw InvalidInput(
            "harmonics = " + std::to_string(harmonics_) + " with " + std::to_string(nc) + " contact(s)" +
            (ns > nc ? " (" + std::to_string(ns) + " directions)" : std::string()) +
            (condensed_ ? std::string() : " on " + std::to_string(system_.dofs()) + " DOFs (full formulation)") +
            " makes " + std::to_string(all_unknowns_) + " harmonic-balance unknowns (" + std::to_string(signals) +
            " signals x " + std::to_string(n) + " coefficients), whose dense Jacobian would take " +
            format_number(std::round(8.0 * all_unknowns_ * static_cast<double>(all_unknowns_) / 1048576.0)) +
            " MB per copy: allowed at most " + std::to_string(max_unknowns) +
            " unknowns (" + (fits >= std::max(1, system_.excitation_harmonic) ? "fewer harmonics: at most H = " + std::to_string(fits) + " fits; " : std::string()) +
            "fewer contacts" + (condensed_ ? std::string() : ", the condensed formulation") +
            (structurable ? ", jacobian = structured" : "") + ")");
    }
    // The balanced harmonics: all, or the odd ones only (c_k, s_k for odd k).
    odd_ = options.odd_harmonics;
    if (odd_ && system_.has_static_load())
        throw InvalidInput("odd harmonics only: a static load is carried by harmonic 0, which the half-wave symmetry "
                           "drops (allowed: every harmonic with static_load, or no static load)");
    if (odd_ && system_.excitation_harmonic % 2 == 0)
        throw InvalidInput("odd harmonics only: the excitation harmonic h = " + std::to_string(system_.excitation_harmonic) +
                           " is even, so the solution is not half-wave symmetric (allowed: an odd h, or every harmonic)");
    for (int row = 0; row < n; ++row)
        if (!odd_ || (row > 0 && ((row + 1) / 2) % 2 == 1)) balanced_.push_back(row);
    std::vector<bool> dependent(static_cast<std::size_t>(all_unknowns_ / n), false);
    if (cyclic_)
        for (const auto& pair : system_.cyclic.neighbours) dependent[static_cast<std::size_t>(pair.first)] = true;
    std::vector<int> first_unknown(dependent.size(), -1);  // of each independent signal
    for (int signal = 0; signal < all_unknowns_ / n; ++signal) {
        if (dependent[static_cast<std::size_t>(signal)]) continue;
        first_unknown[static_cast<std::size_t>(signal)] = static_cast<int>(balanced_index_.size());
        for (int row : balanced_) balanced_index_.push_back(signal * n + row);
    }
    unknowns_ = static_cast<int>(balanced_index_.size());
    if (cyclic_) {
        // X = P U: the independent signals copied, each dependent DOF's harmonic k its master's
        // turned by k phi (a delay of phi / omega: cyclic.hpp).
        std::vector<Eigen::Triplet<double>> entries;
        for (int i = 0; i < unknowns_; ++i) entries.emplace_back(balanced_index_[static_cast<std::size_t>(i)], i, 1.0);
        const double phi = system_.cyclic.phase();
        for (const auto& [d, m] : system_.cyclic.neighbours) {
            const int u = first_unknown[static_cast<std::size_t>(m)];
            entries.emplace_back(d * n, u, 1.0);
            for (int k = 1; k <= harmonics_; ++k) {
                const double c = std::cos(k * phi), sn = std::sin(k * phi);
                entries.emplace_back(d * n + 2 * k - 1, u + 2 * k - 1, c);
                entries.emplace_back(d * n + 2 * k - 1, u + 2 * k, -sn);
                entries.emplace_back(d * n + 2 * k, u + 2 * k - 1, sn);
                entries.emplace_back(d * n + 2 * k, u + 2 * k, c);
            }
        }
        cyclic_map_.resize(all_unknowns_, unknowns_);
        cyclic_map_.setFromTriplets(entries.begin(), entries.end());
    }
    if (build_fourier) fourier_ = std::make_unique<Fourier>(harmonics_, time_samples_);
    if (build_fourier && has_static_problem(system_)) rest_ = static_state(system_);
}

Eigen::VectorXd HarmonicBalance::all_harmonics(const Eigen::VectorXd& x) const {
    if (!odd_ && !cyclic_) return x;
    if (x.size() != unknowns_)
        throw InvalidInput("harmonic balance: " + std::to_string(x.size()) + " unknowns given, allowed " +
                           std::to_string(unknowns_));
    if (cyclic_) return cyclic_map_ * x;
    Eigen::VectorXd all = Eigen::VectorXd::Zero(all_unknowns_);
    for (int i = 0; i < unknowns_; ++i) all(balanced_index_[static_cast<std::size_t>(i)]) = x(i);
    return all;
}

double HarmonicBalance::unknown_scale(const Eigen::VectorXd& x) const {
    const double size = x.size() > 0 ? x.cwiseAbs().maxCoeff() : 0.0;
    if (!condensed_) return std::max(full_displacement_scale_, size);
    return std::max(1e-3 * force_scale_ * static_flexibility_.maxCoeff(), size);
}

void HarmonicBalance::set_time_samples(int time_samples) {
    Fourier::check(harmonics_, time_samples);
    time_samples_ = time_samples;
    fourier_ = std::make_unique<Fourier>(harmonics_, time_samples_);
}

double HarmonicBalance::time_samples_needed(const Eigen::VectorXd& x, double omega, std::string* reason) {
    const Eigen::VectorXd all = all_harmonics(x);
    double needed = 0.0;
    for (std::size_t c = 0; c < models_.size(); ++c) {
        const double n = models_[c]->time_samples_needed(*fourier_, omega, relative_all(all, static_cast<int>(c)));
        if (n <= needed) continue;
        needed = n;
        if (reason) *reason = contact_name(system_.contacts, c) + " (law " + to_string(system_.contacts[c].law) + ") " +
                              models_[c]->time_samples_reason();
    }
    return needed;
}

Eigen::VectorXd HarmonicBalance::relative(const Eigen::VectorXd& x, int contact) const {
    return relative_all(all_harmonics(x), contact);
}

Eigen::VectorXd HarmonicBalance::state(const Eigen::VectorXd& x, int contact) const {
    return state_all(all_harmonics(x), contact);
}

Eigen::VectorXd HarmonicBalance::relative_all(const Eigen::VectorXd& x, int contact) const {
    const int n = coefficients(), first = signal_first_[static_cast<std::size_t>(contact)],
              count = signal_count_[static_cast<std::size_t>(contact)];
    if (condensed_) return x.segment(first * n, count * n);
    const Eigen::Map<const Eigen::MatrixXd> y(x.data(), n, system_.dofs());
    Eigen::VectorXd q(count * n);
    for (int j = 0; j < count; ++j) q.segment(j * n, n) = y * directions_[static_cast<std::size_t>(first + j)];
    return q;
}

Eigen::VectorXd HarmonicBalance::embed_harmonics(const Eigen::VectorXd& low, int low_harmonics) const {
    // The low layout per signal: the balanced positions of this set below 2 low_harmonics + 1.
    std::vector<int> low_rows;
    for (int row : balanced_)
        if (row < 2 * low_harmonics + 1) low_rows.push_back(row);
    const auto m = static_cast<Eigen::Index>(low_rows.size());
    const int balanced = balanced_coefficients();
    if (low_harmonics < 0 || low_harmonics > harmonics() || m == 0 || low.size() % m != 0 ||
        low.size() / m * balanced != unknowns_)
        throw InvalidInput("embed_harmonics: " + std::to_string(low.size()) + " unknowns with " +
                           std::to_string(low_harmonics) + " harmonics do not match this layout (" +
                           std::to_string(unknowns_) + " unknowns, " + std::to_string(harmonics()) + " harmonics)");
    // low_rows are the first m balanced positions, so the low signal fills the head of each.
    Eigen::VectorXd x = Eigen::VectorXd::Zero(unknowns_);
    for (Eigen::Index s = 0; s < low.size() / m; ++s) x.segment(s * balanced, m) = low.segment(s * m, m);
    return x;
}

Eigen::VectorXd HarmonicBalance::state_all(const Eigen::VectorXd& x, int contact) const {
    const auto c = static_cast<std::size_t>(contact);
    const int offset = state_offset_[c];
    return offset < 0 ? Eigen::VectorXd() : Eigen::VectorXd(x.segment(offset, state_count_[c] * coefficients()));
}

Eigen::VectorXd HarmonicBalance::force_samples(const Eigen::VectorXd& x, double omega, int contact) {
    const Eigen::VectorXd all = all_harmonics(x);
    return models_[static_cast<std::size_t>(contact)]->force_samples(*fourier_, omega, relative_all(all, contact),
                                                                     state_all(all, contact));
}

Eigen::VectorXd HarmonicBalance::stick_indicator(const Eigen::VectorXd& x, double omega, int contact) {
    const Eigen::VectorXd all = all_harmonics(x);
    return models_[static_cast<std::size_t>(contact)]->stick_indicator(*fourier_, omega, relative_all(all, contact),
                                                                       state_all(all, contact));
}

}  // namespace hbf
