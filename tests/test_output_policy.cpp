// The output policy (output_file.hpp: check_outputs, OutputFile) end to end: outputs are checked before
// any work, regular files (and symlinks to them) are replaced atomically, devices and FIFOs
// are written in place and never replaced, and two outputs never name the same file.
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <future>
#include <sstream>

#include "cli_support.hpp"

using namespace test;

namespace {

std::string kind_of(const fs::path& path) {
    struct stat info {};
    if (::lstat(path.c_str(), &info) != 0) return "missing";
    if (S_ISLNK(info.st_mode)) return "symlink";
    if (S_ISCHR(info.st_mode)) return "character device";
    if (S_ISFIFO(info.st_mode)) return "fifo";
    if (S_ISREG(info.st_mode)) return "file";
    if (S_ISDIR(info.st_mode)) return "directory";
    return "other";
}

}  // namespace

TEST_CASE("Outputs to /dev/null are written in place: the device survives, also as root", "[output][cli]") {
    REQUIRE(kind_of("/dev/null") == "character device");
    TempDir dir;
    for (const std::string args : {"frf --quiet --law dahl --out /dev/null --summary /dev/null",
                                   "timeint --law dahl --w 1 --out /dev/null",
                                   "analytic --law dahl --out /dev/null", "loop --law dahl --w 1 --out /dev/null"}) {
        INFO(args);
        const Result r = run_hbf(args, dir);
        CHECK(r.exit_code == 0);
        CHECK(r.out.empty());
        CHECK(kind_of("/dev/null") == "character device");
    }
    const Result full = run_hbf("analytic --law dahl --out /dev/full", dir);
    CHECK(full.exit_code == 1);
    CHECK_THAT(full.err, Catch::Contains("cannot write output '/dev/full'"));
    CHECK(kind_of("/dev/full") == "character device");
}

TEST_CASE("A symlink to a file stays a symlink (its target is replaced), and a FIFO is written in place", "[output][cli]") {
    TempDir dir;
    const fs::path real = dir.path / "real.csv", link = dir.path / "link.csv";
    write_file(real, "old\n");
    fs::create_symlink(real, link);
    const Result reference = run_hbf("analytic --law dahl", dir);
    REQUIRE(reference.exit_code == 0);
    const Result r = run_hbf("analytic --law dahl --out '" + link.string() + "'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(kind_of(link) == "symlink");
    CHECK(slurp(real) == reference.out);

    const fs::path fifo = dir.path / "pipe";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    auto reader = std::async(std::launch::async, [&] {
        std::ifstream in(fifo);
        std::stringstream all;
        all << in.rdbuf();
        return all.str();
    });
    const Result piped = run_hbf("analytic --law dahl --out '" + fifo.string() + "'", dir);
    CHECK(piped.exit_code == 0);
    CHECK(reader.get() == reference.out);
    CHECK(kind_of(fifo) == "fifo");
    // An image needs a regular file: a FIFO is refused before any work.
    const fs::path fifo_png = dir.path / "pipe.png";
    REQUIRE(::mkfifo(fifo_png.c_str(), 0600) == 0);
    check_bad_input("analytic --law dahl --plot '" + fifo_png.string() + "'", {"--plot", "an image needs a regular file"},
                    dir);
    CHECK(kind_of(fifo_png) == "fifo");
}

TEST_CASE("Output paths are checked before any work: collisions, missing directories, directories, empty values",
          "[output][cli]") {
    TempDir dir;
    const fs::path kept = dir.path / "kept.csv", alias = dir.path / "alias.csv", hard = dir.path / "hard.csv";
    write_file(kept, "old\n");
    fs::create_symlink(kept, alias);
    fs::create_hard_link(kept, hard);
    const std::string k = "'" + kept.string() + "'";
    // Each case is refused (exit 2, the flags named) and leaves kept.csv as it was.
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
        {"frf --quiet --summary " + k, {"--summary and --out name the same file"}},
        {"frf --quiet --summary '" + alias.string() + "'", {"name the same file"}},
        {"frf --quiet --summary '" + hard.string() + "'", {"name the same file"}},
        {"frf --quiet --summary '" + (dir.path / "none" / "s.json").string() + "'", {"--summary", "does not exist"}},
        {"frf --quiet --summary '" + dir.path.string() + "'", {"--summary", "is a directory"}},
        {"frf --quiet --summary ''", {"--summary is empty"}},
        {"frf --quiet --plot '" + (dir.path / "kept.png").string() + "' --overlay-timeint 3 --overlay-out " + k,
         {"--overlay-out", "--out", "same file"}},
    };
    for (const auto& [args, expected] : cases) {
        INFO(args);
        const Result r = run_hbf(args + " --out " + k, dir);
        CHECK(r.exit_code == 2);
        for (const std::string& e : expected) CHECK_THAT(r.err, Catch::Contains(e));
        CHECK(slurp(kept) == "old\n");
        CHECK(kind_of(alias) == "symlink");
    }
    const Result empty = run_hbf("frf --quiet --out ''", dir);
    CHECK(empty.exit_code == 2);
    CHECK_THAT(empty.err, Catch::Contains("--out is empty") && Catch::Contains("- for standard output"));
    const Result both = run_hbf("frf --quiet --out - --summary -", dir);
    CHECK(both.exit_code == 2);
    CHECK_THAT(both.err, Catch::Contains("both go to standard output"));
    const fs::path dangling = dir.path / "dangling.csv";
    fs::create_symlink(dir.path / "nothing" / "x.csv", dangling);
    const Result d = run_hbf("analytic --law dahl --out '" + dangling.string() + "'", dir);
    CHECK(d.exit_code == 2);
    CHECK_THAT(d.err, Catch::Contains("symlink to nothing"));
    CHECK(kind_of(dangling) == "symlink");
}

TEST_CASE("Empty and conflicting values name the flag the user gave: --config '', --max-periods below the default "
          "--min-periods",
          "[cli]") {
    TempDir dir;
    // Before, --config '' ran the preset silently, and --max-periods 1 blamed --min-periods.
    check_bad_input("frf --quiet --config ''", {"--config is empty"}, dir);
    check_bad_input("timeint --law dahl --w 1 --config ''", {"--config is empty"}, dir);
    check_bad_input("timeint --law dahl --w 1 --max-periods 1", {"--max-periods = '1' is below --min-periods (3"}, dir);
    check_bad_input("timeint --law dahl --w 1 --max-periods 2 --min-periods 3",
                    {"--min-periods = '3' is out of range: allowed 1..--max-periods (2)"}, dir);
}
