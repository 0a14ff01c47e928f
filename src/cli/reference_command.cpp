// hbf reference — everything the documentation's reference pages list, as JSON on standard
// output: every command with its flags and output columns, the contact laws with their
// parameters, and the system-file keys. The documentation is generated from it, so that a new
// flag, column, law parameter or key appears there without being written twice.

#include <nlohmann/json.hpp>

#include <iostream>

#include "commands.hpp"
#include "outputs.hpp"
#include "hbf/config.hpp"
#include "hbf/contact_law.hpp"
#include "hbf/version.hpp"

namespace hbf::cli {
namespace {

using nlohmann::json;

json flag_reference(const CLI::Option& option) {
    json flag;
    flag["name"] = option.get_name(false, true);  // "--law" (and "-h,--help")
    flag["value"] = option.get_type_size() == 0 ? "" : option.get_type_name();
    flag["default"] = option.get_default_str();
    flag["required"] = option.get_required();
    // The first line is the summary --help shows, the rest the details (program.cpp).
    const std::string& text = option.get_description();
    const std::size_t end = text.find('\n');
    flag["summary"] = text.substr(0, end);
    flag["details"] = end == std::string::npos ? std::string() : text.substr(end + 1);
    return flag;
}

json command_reference(const CLI::App& command) {
    json c;
    c["name"] = command.get_name();
    c["description"] = command.get_description();
    c["flags"] = json::array();
    for (const CLI::Option* option : command.get_options()) {
        if (option->get_name() == "--help") continue;
        c["flags"].push_back(flag_reference(*option));
    }
    const auto& outputs = output_help();
    if (const auto at = outputs.find(command.get_name()); at != outputs.end()) {
        c["output"]["intro"] = at->second.intro;
        c["output"]["outro"] = at->second.outro;
        c["output"]["columns"] = json::array();
        for (const io::Column& column : at->second.columns)
            c["output"]["columns"].push_back({{"name", column.name}, {"meaning", column.meaning}});
    }
    return c;
}

const char* kind_name(LawParameter::Kind kind) {
    switch (kind) {
        case LawParameter::Kind::number: return "number";
        case LawParameter::Kind::integer: return "integer";
        case LawParameter::Kind::pairs: return "pairs";
        case LawParameter::Kind::direction: return "direction";
        case LawParameter::Kind::rows: return "rows";
        case LawParameter::Kind::direction_rows: return "direction_rows";
    }
    return "number";
}

json law_reference(const ContactLaw& law) {
    json l;
    l["name"] = law.name();
    l["definition"] = law.definition();
    l["friction_limit"] = law.has_friction_limit();
    l["preset"] = law.has_preset();
    l["smooth"] = law.smooth();
    l["exact_stick"] = law.exact_stick();
    l["default_harmonics"] = law.default_harmonics();
    l["parameters"] = json::array();
    Contact unset;
    unset.law = law.id();
    for (const LawParameter& p : law.parameters()) {
        json parameter;
        parameter["key"] = p.key;
        parameter["meaning"] = p.meaning;
        parameter["kind"] = kind_name(p.kind);
        parameter["allowed"] = p.scalar() ? p.allowed() : "";
        parameter["zero_means"] = p.zero_means ? p.zero_means : "";
        parameter["default"] = p.scalar() ? json(p.get(unset)) : json(nullptr);
        parameter["per_area"] = p.per_area;
        l["parameters"].push_back(parameter);
    }
    return l;
}

int run_reference(const CLI::App& app) {
    json reference;
    reference["version"] = hbf::version();
    reference["program"] = {{"description", app.get_description()}, {"footer", app.get_footer()}};
    reference["commands"] = json::array();
    for (const CLI::App* command : app.get_subcommands({})) {
        if (command->get_name() == "reference") continue;
        reference["commands"].push_back(command_reference(*command));
    }
    reference["laws"] = json::array();
    for (const ContactLaw* law : contact_laws()) reference["laws"].push_back(law_reference(*law));
    reference["config"] = json::array();
    for (const io::ConfigKey& key : io::config_keys())
        reference["config"].push_back({{"table", key.table}, {"key", key.key}, {"meaning", key.meaning}});
    std::cout << reference.dump(1) << "\n";
    return 0;
}

}  // namespace

Runner add_reference_command(CLI::App& app) {
    app.add_subcommand("reference",
                       "Every command's flags and output columns, the contact laws' parameters and the system-file "
                       "keys, as JSON on standard output: the source of the documentation's reference pages.");
    return [&app]() { return run_reference(app); };
}

}  // namespace hbf::cli
