// Fuzz target: the command line, hbf::cli::run_program (src/cli/), always as a dry run.
//
// The input is the argument list: words separated by newline or NUL bytes, taken raw (the
// first word is the command: frf, timeint, loop, analytic, or anything else). The target
// makes argv = {"hbf", words..., "--dry-run"}, puts another "--dry-run" right after the first
// word that names a command (a trailing value-taking flag could swallow the last one: "--wmin
// --dry-run" is --wmin = '--dry-run'), and rewrites a given "--dry-run=VALUE" to "--dry-run"
// (CLI11 lets "--dry-run=0" switch the flag off). Every command then checks all its inputs and
// outputs and returns before the computation.
//
// No file may be written. The target has a private temporary directory holding `systems` (a
// link to examples/systems: the seeds' --config files) and `out`:
// - every value of --out, --summary, --plot and --overlay-out other than '-' and '' is moved
//   into <private>/out/ (its relative components kept, '.', '..' and the leading '/' dropped:
//   'a/b.csv' becomes <private>/out/a/b.csv, whose directory does not exist);
// - a relative --config is read from <private>/ ('systems/chain3.toml' works), an absolute one
//   as given (reading is harmless; a non-regular file is refused by the reader).
// The process's working directory is left alone (libFuzzer writes its corpus and artifacts
// there when given relative paths). After every run <private>/ must hold `systems` and an
// empty `out`, nothing else.
//
// Exit codes 0 and 2 are expected (a dry run computes nothing, so 1 and 3 cannot be honest);
// any other, an exception out of run_program, a crash, a sanitizer report, a timeout (a
// computation that ran anyway) or a written file is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzz_support.hpp"

namespace {

namespace fs = std::filesystem;

const char* const commands[] = {"frf", "timeint", "loop", "analytic"};
const char* const output_flags[] = {"--out", "--summary", "--plot", "--overlay-out"};

std::string out_dir() { return hbf_fuzz::private_dir() + "/out"; }

bool is_command(const std::string& word) {
    for (const char* c : commands)
        if (word == c) return true;
    return false;
}

bool is_output_flag(const std::string& word) {
    for (const char* f : output_flags)
        if (word == f) return true;
    return false;
}

bool is_path_flag(const std::string& word) { return is_output_flag(word) || word == "--config"; }

/// The value of a path flag as the target passes it on (see the top of the file).
std::string rewrite(const std::string& flag, const std::string& value) {
    if (value.empty()) return value;  // the empty-value refusals
    if (flag == "--config") return value.front() == '/' ? value : hbf_fuzz::private_dir() + "/" + value;
    if (value == "-") return value;   // standard output
    std::string result = out_dir();
    std::size_t start = 0;
    while (start <= value.size()) {
        std::size_t end = value.find('/', start);
        if (end == std::string::npos) end = value.size();
        const std::string part = value.substr(start, end - start);
        if (!part.empty() && part != "." && part != "..") result += "/" + part;
        start = end + 1;
    }
    if (value.back() == '/') result += "/";
    return result;
}

/// What the private directory holds after a run: `systems` and an empty `out`, nothing else.
void check_nothing_written() {
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(hbf_fuzz::private_dir(), error)) {
        const std::string name = entry.path().filename().string();
        if (name != "systems" && name != "out") hbf_fuzz::die("a dry run wrote " + entry.path().string());
    }
    if (error) hbf_fuzz::die("cannot list " + hbf_fuzz::private_dir());
    if (!fs::is_empty(out_dir(), error) || error) hbf_fuzz::die("a dry run wrote into " + out_dir());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    const std::string& dir = hbf_fuzz::private_dir();
    std::error_code error;
    fs::create_directory(out_dir(), error);
    if (error) hbf_fuzz::die("cannot create " + out_dir());
    fs::create_directory_symlink(HBF_FUZZ_EXAMPLES_DIR, dir + "/systems", error);
    if (error) hbf_fuzz::die("cannot link " + dir + "/systems");
    hbf_fuzz::silence_iostreams();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The words: split on '\n' and '\0' (a trailing separator ends the last word).
    std::vector<std::string> words;
    std::string word;
    for (std::size_t i = 0; i < size; ++i) {
        const char c = static_cast<char>(data[i]);
        if (c == '\n' || c == '\0') {
            words.push_back(word);
            word.clear();
        } else {
            word += c;
        }
    }
    if (size > 0 && data[size - 1] != '\n' && data[size - 1] != '\0') words.push_back(word);

    std::vector<std::string> args = {"hbf"};
    bool inserted = false;
    for (std::size_t k = 0; k < words.size(); ++k) {
        const std::string& w = words[k];
        const auto equals = w.find('=');
        if (w.rfind("--dry-run=", 0) == 0) {
            args.push_back("--dry-run");
        } else if (equals != std::string::npos && is_path_flag(w.substr(0, equals))) {  // --out=VALUE
            args.push_back(w.substr(0, equals + 1) + rewrite(w.substr(0, equals), w.substr(equals + 1)));
        } else {
            args.push_back(w);
            if (is_path_flag(w) && k + 1 < words.size()) {  // --out VALUE
                args.push_back(rewrite(w, words[k + 1]));
                ++k;
            }
        }
        if (!inserted && is_command(w)) {
            args.push_back("--dry-run");
            inserted = true;
        }
    }
    args.push_back("--dry-run");

    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int code = hbf::cli::run_program(static_cast<int>(args.size()), argv.data());
    if (code != 0 && code != 2) hbf_fuzz::die("a dry run exited with " + std::to_string(code) + " (allowed 0 and 2)");
    check_nothing_written();
    return 0;
}
