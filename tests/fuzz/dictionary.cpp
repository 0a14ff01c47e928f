// The words of the fuzz targets' libFuzzer dictionaries that come from the code, not by hand:
// every command, flag and enumerated flag value of the command line (as the commands register
// them with CLI11), and every contact law's name and parameter keys (the law registry,
// hbf/contact_law.hpp). scripts/fuzz.sh appends this program's output to the hand-written part
// (tests/fuzz/<target>.dict: syntax, numbers, files), so that a law or a flag added in its own
// file reaches the fuzzer without editing a dictionary.
//
//   fuzz_dictionary cli|config          print the generated words of that target, one per line
//   fuzz_dictionary --check DICT_DIR    fail (exit 1, naming the word) when a hand-written
//                                       dictionary in DICT_DIR repeats a generated word, or when
//                                       a generated word is not valid dictionary syntax
#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <set>
#include <string>
#include <vector>

#include "commands.hpp"
#include "hbf/contact_law.hpp"

namespace {

/// A dictionary entry: the word in double quotes, with '"' and '\' escaped.
std::string entry(const std::string& word) {
    std::string text = "\"";
    for (const char c : word) {
        if (c == '"' || c == '\\') text += '\\';
        text += c;
    }
    return text + "\"";
}

/// The flag values a command lists in its type name ("automatic|condensed|full"): the words of
/// lower-case letters, digits, '-' and ',' (INT, NUMBER, FILE and the like are placeholders).
void add_values(const std::string& type_name, std::set<std::string>& words) {
    std::size_t start = 0;
    while (start <= type_name.size()) {
        const std::size_t bar = type_name.find('|', start);
        const std::string word = type_name.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
        bool value = !word.empty();
        for (const char c : word) value = value && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == ',');
        if (value) words.insert(word);
        if (bar == std::string::npos) break;
        start = bar + 1;
    }
}

std::set<std::string> cli_words() {
    CLI::App app("hbf", "hbf");
    app.set_version_flag("--version", "");
    // The commands register themselves as hbf's run_program does (cli/commands.hpp).
    hbf::cli::add_analytic_command(app);
    hbf::cli::add_frf_command(app);
    hbf::cli::add_loop_command(app);
    hbf::cli::add_map_command(app);
    hbf::cli::add_optimize_command(app);
    hbf::cli::add_timeint_command(app);
    std::set<std::string> words;
    std::vector<const CLI::App*> apps = {&app};
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
        words.insert(command->get_name());
        apps.push_back(command);
    }
    for (const CLI::App* command : apps)
        for (const CLI::Option* option : command->get_options()) {
            for (const std::string& name : option->get_lnames()) words.insert("--" + name);
            for (const std::string& name : option->get_snames()) words.insert("-" + name);
            add_values(option->get_type_name(), words);
        }
    for (const hbf::ContactLaw* law : hbf::contact_laws()) words.insert(law->name());
    return words;
}

std::set<std::string> config_words() {
    std::set<std::string> words;
    for (const hbf::ContactLaw* law : hbf::contact_laws()) {
        words.insert("\"" + std::string(law->name()) + "\"");  // the law as a TOML string: "coulomb"
        for (const hbf::LawParameter& p : law->parameters()) words.insert(p.key);
    }
    return words;
}

/// The entries of a dictionary file (its non-comment, non-empty lines).
std::set<std::string> entries(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    std::set<std::string> lines;
    std::string line;
    while (std::getline(in, line))
        if (!line.empty() && line[0] != '#') lines.insert(line);
    return lines;
}

int check(const std::string& dir) {
    int problems = 0;
    for (const std::string target : {"cli", "config"}) {
        const std::set<std::string> words = target == "cli" ? cli_words() : config_words();
        if (words.empty()) {
            std::cerr << target << ": no generated words\n";
            ++problems;
        }
        const std::set<std::string> hand = entries(dir + "/" + target + ".dict");
        for (const std::string& word : words) {
            if (word.empty() || word.find('\n') != std::string::npos) {
                std::cerr << target << ": generated word '" << word << "' is not a dictionary word\n";
                ++problems;
            }
            if (hand.count(entry(word)) > 0) {
                std::cerr << target << ".dict: " << entry(word)
                          << " is written by hand but generated (tests/fuzz/dictionary.cpp): remove it\n";
                ++problems;
            }
        }
    }
    return problems == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string what = argc > 1 ? argv[1] : "";
    try {
        if (what == "--check" && argc == 3) return check(argv[2]);
        if ((what == "cli" || what == "config") && argc == 2) {
            for (const std::string& word : what == "cli" ? cli_words() : config_words()) std::cout << entry(word) << "\n";
            return 0;
        }
    } catch (const std::exception& e) {
        std::cerr << "fuzz_dictionary: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "usage: fuzz_dictionary cli|config, or fuzz_dictionary --check DICT_DIR\n";
    return 2;
}
