// hbf command line — strict parsing of flag values, the paper's preset flags, the chosen system
// (preset or --config), and the verdict printed with its exit code (arguments.hpp).
#include "arguments.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <map>

#include "hbf/contact_law.hpp"
#include "hbf/absorber.hpp"
#include "hbf/error.hpp"

namespace hbf::cli {

namespace {
[[noreturn]] void bad_value(const std::string& flag, const std::string& text, const std::string& why) {
    throw UsageError(flag + " = '" + text + "' " + why);
}
}  // namespace

int finish(const std::string& command, const Verdict& verdict) {
    for (const std::string& e : verdict.errors) std::cerr << "hbf " << command << ": error: " << e << "\n";
    for (const std::string& w : verdict.warnings) std::cerr << "hbf " << command << ": warning: " << w << "\n";
    for (const std::string& n : verdict.notes) std::cerr << "hbf " << command << ": note: " << n << "\n";
    return verdict.exit_code();
}

double parse_double(const std::string& flag, const std::string& text) {
    double value = 0.0;
    std::string why;
    if (!parse_decimal(text, value, why)) bad_value(flag, text, why);
    return value;
}

long long parse_integer(const std::string& flag, const std::string& text) {
    long long value = 0;
    std::string why;
    if (!parse_whole_number(text, value, why)) bad_value(flag, text, why);
    return value;
}

std::string AbsorberFlags::laws_help() {
    std::string help = "friction law of the paper's absorber:";
    std::vector<const ContactLaw*> laws;  // those the absorber can carry (the others: --config)
    for (const ContactLaw* law : contact_laws())
        if (law->has_preset()) laws.push_back(law);
    for (std::size_t i = 0; i < laws.size(); ++i)
        help += std::string(i == 0 ? " " : i + 1 == laws.size() ? " or " : ", ") + laws[i]->name() + " (" +
                laws[i]->definition() + ")";
    std::string names;
    for (std::size_t i = 0; i < laws.size(); ++i)
        names += std::string(i == 0 ? " " : i + 1 == laws.size() ? " or " : ", ") + laws[i]->name();
    return "friction law of the paper's absorber:" + names + "\n" + help;
}

void AbsorberFlags::add_system_flags(CLI::App& command) {
    add_to(command, "", "coulomb", true);
    add_excitation_harmonic(command);
    command
        .add_option("--force-scale", force_scale,
                    "--config: a factor > 0 on the file's excitation vector [default 1]\n--config: a factor > 0 on the file's excitation vector (structure.excitation; not on its "
                    "static load or preloads), for the same structure under another force level [default 1]")
        ->type_name("NUMBER");
}

void AbsorberFlags::add_to(CLI::App& command, const std::string& laws_help_text, const std::string& law_default,
                           bool with_smooth_options) {
    const AbsorberParameters d;  // documented defaults
    auto def = [](double v) { return " [default " + format_number(v) + "]"; };
    law = law_default;
    command.add_option("--law", law, laws_help_text.empty() ? laws_help() : laws_help_text)
        ->capture_default_str()
        ->type_name("LAW");
    command.add_option("--r", r, "mass ratio r = m2/m1, > 0" + def(d.mass_ratio));
    command.add_option("--wa", wa, "tuning ratio wa = omega2/omega1, omega2 = sqrt(k2/m2), > 0" +
                                       def(d.tuning_ratio));
    command.add_option("--mu", mu, "friction coefficient mu (slip force mu N), > 0" +
                                       def(d.friction_coefficient));
    command.add_option("--fe", fe, "excitation amplitude fe = F0/N, > 0" + def(d.excitation));
    // the laws' own parameters (model.hpp: preset_parameters), each with the laws that read it
    for (const PresetParameter& p : preset_parameters()) {
        if (p.harmonic_balance_only && !with_smooth_options) continue;
        const std::string full = std::string(p.help) + " (" + laws_reading(p.symbol) + ")" + def(d.*(p.field));
        // --help shows a summary line where the definition is long (the reference has it all).
        const std::string summary = std::string(p.meaning) +
                                    (p.zero_only_by_default ? ", 0 = automatic" : p.zero_allowed ? ", >= 0" : ", > 0") + " (" +
                                    laws_reading(p.symbol) + ")" + def(d.*(p.field));
        command.add_option(p.flag, law_values[p.flag], full.size() > 120 ? summary + "\n" + full : full);
    }
    for (CLI::Option* option : command.get_options())
        if (option->get_name() != "--law" && option->get_name() != "--help" && option->get_name() != "--dry-run")
            option->type_name("NUMBER");
}

void AbsorberFlags::add_excitation_harmonic(CLI::App& command) {
    command
        .add_option("--excitation-harmonic", excitation_harmonic,
                    "excitation harmonic h, 1..100: the force acts at h w (h = 2: subharmonic responses) [default 1]\nexcitation harmonic h, 1.." + std::to_string(System::max_excitation_harmonic) +
                        ": the force is F cos(h w t) and w the fundamental of the periodic response sought (h = 2: "
                        "the subharmonic response of order 1/2 to a force at 2 w; all columns are per w, *_amp1 at w); "
                        "harmonic balance needs H >= h; overrides structure.excitation_harmonic of --config [default 1]")
        ->type_name("INTEGER");
}

FrictionLaw AbsorberFlags::friction_law() const {
    try {
        return parse_friction_law(law);
    } catch (const InvalidInput& e) {
        throw UsageError(std::string("--") + e.what());
    }
}

std::vector<std::string> AbsorberFlags::given(const CLI::App& command) const {
    std::vector<std::string> flags;
    std::vector<std::string> all = {"--r", "--wa", "--mu", "--fe"};
    for (const PresetParameter& p : preset_parameters()) all.emplace_back(p.flag);
    for (const std::string& flag : all)
        if (command.get_option_no_throw(flag) != nullptr && command.count(flag) > 0) flags.push_back(flag);
    return flags;
}

AbsorberParameters AbsorberFlags::parameters(const CLI::App& command) const {
    const FrictionLaw chosen = friction_law();
    auto given_flag = [&](const char* flag) {
        return command.get_option_no_throw(flag) != nullptr && command.count(flag) > 0;
    };
    AbsorberParameters p;
    auto set = [&](const char* flag, const std::string& text, double& target) {
        if (given_flag(flag)) target = parse_double(flag, text);
    };
    set("--r", r, p.mass_ratio);
    set("--wa", wa, p.tuning_ratio);
    set("--mu", mu, p.friction_coefficient);
    set("--fe", fe, p.excitation);
    std::vector<std::string> keywords;  // the law's parameters given (by their Python keyword)
    for (const PresetParameter& q : preset_parameters())
        if (given_flag(q.flag)) keywords.push_back(q.keyword);
    try {
        for (const PresetParameter& q : preset_parameters())
            if (given_flag(q.flag)) p.*(q.field) = parse_double(q.flag, law_values.at(q.flag));
        check_given_preset_parameters(chosen, p, keywords);  // a flag the law does not read, an explicit 0
        p.validate(chosen);
    } catch (const InvalidInput& e) {
        // The library names the parameter (r, wa, ..., mu_s, vs, sigma2, or the keyword of a
        // law's parameter given): name the flag too.
        const std::string what = e.what();
        const std::string name = what.substr(0, what.find(' '));
        std::map<std::string, std::string> flags = {{"r", "--r"}, {"wa", "--wa"}, {"mu", "--mu"}, {"fe", "--fe"}};
        for (const PresetParameter& q : preset_parameters()) flags[q.symbol] = flags[q.keyword] = q.flag;
        const auto flag = flags.find(name);
        throw UsageError(flag == flags.end() ? what : flag->second + ": " + what);
    }
    return p;
}

namespace {
/// --excitation-harmonic, when given, on the chosen system.
void apply_excitation_harmonic(const CLI::App& command, const AbsorberFlags& flags, ChosenSystem& chosen) {
    if (command.get_option_no_throw("--excitation-harmonic") != nullptr && command.count("--excitation-harmonic") > 0) {
        const long long h = parse_integer("--excitation-harmonic", flags.excitation_harmonic);
        if (h < 1 || h > System::max_excitation_harmonic)
            throw UsageError("--excitation-harmonic = " + flags.excitation_harmonic + " is out of range: allowed 1.." +
                             std::to_string(System::max_excitation_harmonic));
        chosen.system.excitation_harmonic = static_cast<int>(h);
    }
}
}  // namespace

ChosenSystem choose_system(const CLI::App& command, const AbsorberFlags& flags, const std::string& config_path) {
    ChosenSystem chosen;
    if (config_path.empty() && command.get_option_no_throw("--config") != nullptr && command.count("--config") > 0)
        throw UsageError("--config is empty: allowed the path of a TOML system file (omit --config for the "
                         "paper's absorber)");
    if (config_path.empty()) {
        const FrictionLaw law = flags.friction_law();
        chosen.absorber = flags.parameters(command);
        chosen.system = friction_absorber(chosen.absorber, law);
        chosen.law_name = to_string(law);
        apply_excitation_harmonic(command, flags, chosen);
        if (command.get_option_no_throw("--force-scale") != nullptr && command.count("--force-scale") > 0)
            throw UsageError("--force-scale scales a --config file's excitation: for the paper's absorber set --fe");
        return chosen;
    }
    const std::vector<std::string> preset = flags.given(command);
    if (!preset.empty())
        throw UsageError(preset.front() + " sets a parameter of the paper's absorber preset: with --config, set "
                         "the structure and its contacts in the file");
    chosen.config = io::read_system_config(config_path);
    chosen.system = chosen.config->system;
    if (command.count("--law") > 0) {  // every contact takes the law given on the command line
        const FrictionLaw law = flags.friction_law();
        for (Contact& c : chosen.system.contacts) c.law = law;
        try {
            chosen.system.validate();
        } catch (const InvalidInput& e) {
            throw UsageError("--law = " + flags.law + " does not fit the contacts of " + config_path + ": " + e.what());
        }
    }
    std::vector<std::string> laws;  // each law once, in the order of the contacts
    for (const Contact& c : chosen.system.contacts) {
        const std::string name = to_string(c.law);
        if (std::find(laws.begin(), laws.end(), name) != laws.end()) continue;
        laws.push_back(name);
        chosen.law_name += (chosen.law_name.empty() ? "" : ",") + name;
    }
    chosen.outputs = chosen.config->outputs;
    apply_excitation_harmonic(command, flags, chosen);
    if (command.get_option_no_throw("--force-scale") != nullptr && command.count("--force-scale") > 0) {
        const double scale = parse_double("--force-scale", flags.force_scale);
        if (!(scale > 0.0) || !std::isfinite(scale))
            throw UsageError("--force-scale = " + flags.force_scale + " is out of range: allowed a finite factor > 0");
        chosen.system.excitation *= scale;
        chosen.force_scale = scale;
    }
    // Accepted, but rarely meant: said before the work (the exit code is the result's).
    for (const std::string& w : chosen.system.warnings())
        std::cerr << "hbf " << command.get_name() << ": warning: " << config_path << ": " << w << "\n";
    if (!chosen.config->outputs_note.empty())
        std::cerr << "hbf " << command.get_name() << ": note: " << chosen.config->outputs_note << "\n";
    if (!chosen.config->cyclic_note.empty())
        std::cerr << "hbf " << command.get_name() << ": note: " << chosen.config->cyclic_note << "\n";
    if (chosen.config->reduction) {
        std::cerr << "hbf " << command.get_name() << ": note: " << config_path << ": " << chosen.config->reduction->summary()
                  << "\n";
        for (const std::string& w : chosen.config->reduction->warnings())
            std::cerr << "hbf " << command.get_name() << ": warning: " << config_path << ": " << w << "\n";
    }
    return chosen;
}

std::string default_text(double value) {
    std::string text = format_number(value);
    const std::size_t e = text.find('e');
    if (e == std::string::npos) return text;
    std::size_t digits = e + 1;
    if (digits < text.size() && (text[digits] == '-' || text[digits] == '+')) ++digits;
    while (digits + 1 < text.size() && text[digits] == '0') text.erase(digits, 1);
    if (text[e + 1] == '+') text.erase(e + 1, 1);
    return text;
}

FrfChoices frf_choices(const CLI::App& command, const std::string& harmonics, const std::string& time_samples,
                       const ChosenSystem& chosen) {
    FrfChoices c = chosen.config ? chosen.config->choices : FrfChoices{};
    // H, or "odd" / "odd:H": the odd harmonics <= H only (H automatic without ":H").
    const bool odd = harmonics == "odd" || harmonics.rfind("odd:", 0) == 0;
    const std::string count = odd ? (harmonics == "odd" ? "0" : harmonics.substr(4)) : harmonics;
    const long long parsed = parse_integer("--harmonics", count);
    if (odd && harmonics != "odd" && parsed == 0)
        throw UsageError("--harmonics = " + harmonics + " is out of range: allowed odd (automatic H) or odd:H with H "
                         "in 1.." + std::to_string(max_harmonics));
    if (parsed < 0 || parsed > max_harmonics)
        throw UsageError("--harmonics = " + harmonics + " is out of range: allowed 0 (automatic), 1.." +
                         std::to_string(max_harmonics) +
                         ", odd, or odd:H (odd harmonics <= H only; above " +
                         std::to_string(max_harmonics) +
                         " a branch takes many minutes: README, inputs)");
    if (command.count("--harmonics") > 0) {  // over the file's H and odd_harmonics; 0: automatic
        c.harmonics = parsed > 0 ? std::optional<int>(static_cast<int>(parsed)) : std::nullopt;
        c.odd_harmonics = odd;
    }
    if (command.count("--time-samples") > 0) c.time_samples = parse_int("--time-samples", time_samples);  // range: validate()
    return c;
}

int parse_int(const std::string& flag, const std::string& text) {
    const long long value = parse_integer(flag, text);
    if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
        throw UsageError(flag + " = " + text + " is out of range: more than an int holds");
    return static_cast<int>(value);
}

void check_naming_source(const std::function<void()>& check, const CLI::App& command, const ChosenSystem& chosen,
                         const std::string& config_path) {
    try {
        check();
    } catch (const InvalidInput& e) {
        const std::string what = e.what();
        const std::size_t equals = what.find(" = ");
        if (equals == std::string::npos || !chosen.config) throw;
        const std::string field = what.substr(0, equals);
        std::string flag = "--" + field;
        std::replace(flag.begin(), flag.end(), '_', '-');
        if (command.get_option_no_throw(flag) != nullptr && command.count(flag) > 0) throw;  // the flag's (program.cpp)
        for (const auto& [key, line] : chosen.config->lines) {
            const std::size_t dot = key.rfind('.');
            if (dot == std::string::npos || key.substr(dot + 1) != field) continue;
            throw UsageError(config_path + ":" + std::to_string(line) + ": key '" + key + "': " + what.substr(equals + 3));
        }
        throw;
    }
}

HarmonicBalanceOptions harmonic_balance_options(const CLI::App& command, const std::string& harmonics,
                                                const std::string& time_samples, const ChosenSystem& chosen,
                                                const std::string& config_path, bool exact) {
    FrfChoices choices = frf_choices(command, harmonics, time_samples, chosen);
    choices.exact = exact;
    const HarmonicBalanceOptions hbo = frf_settings(chosen.system, {}, choices).harmonic_balance;
    check_naming_source([&hbo] { hbo.validate(); }, command, chosen, config_path);
    return hbo;
}

}  // namespace hbf::cli
