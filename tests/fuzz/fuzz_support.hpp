// hbfriction fuzz targets — what the three targets share: a private temporary directory per
// process, the fuzz input written to a file in it (the readers take paths), the shipped
// example matrices copied beside it, and silenced iostreams.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <streambuf>
#include <string>
#include <system_error>

#ifndef HBF_FUZZ_EXAMPLES_DIR
#error "HBF_FUZZ_EXAMPLES_DIR (examples/systems of the source tree) must be defined"
#endif

namespace hbf_fuzz {

namespace fs = std::filesystem;

[[noreturn]] inline void die(const std::string& what) {
    std::fprintf(stderr, "hbf fuzz target: %s\n", what.c_str());
    std::abort();
}

/// A private directory ($TMPDIR or /tmp, hbf-fuzz.XXXXXX), created on first use and removed
/// when the process exits normally (a crash leaves it: scripts/fuzz.sh points TMPDIR into
/// build-fuzz/ and empties it).
inline const std::string& private_dir() {
    static const std::string dir = [] {
        const char* base = std::getenv("TMPDIR");
        std::string pattern = std::string(base && *base ? base : "/tmp") + "/hbf-fuzz.XXXXXX";
        if (!::mkdtemp(pattern.data())) die("mkdtemp(" + pattern + ") failed");
        static const std::string removed = pattern;
        std::atexit([] {
            std::error_code ignored;
            fs::remove_all(removed, ignored);
        });
        return pattern;
    }();
    return dir;
}

/// Writes the input to private_dir()/name (created or truncated, the same file every run) and
/// returns its path.
inline std::string write_input(const std::string& name, const std::uint8_t* data, std::size_t size) {
    const std::string path = private_dir() + "/" + name;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) die("cannot open " + path);
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::write(fd, data + done, size - done);
        if (n <= 0) die("cannot write " + path);
        done += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0) die("cannot close " + path);
    return path;
}

/// Copies every .mtx file of examples/systems and examples/systems/beam into the private
/// directory, so that the seed systems' relative Matrix Market names resolve (the files stay
/// untouched in the source tree).
inline void copy_example_matrices() {
    for (const std::string& dir : {std::string(HBF_FUZZ_EXAMPLES_DIR), std::string(HBF_FUZZ_EXAMPLES_DIR) + "/beam"}) {
        std::error_code error;
        for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
            if (entry.path().extension() != ".mtx") continue;
            fs::copy_file(entry.path(), fs::path(private_dir()) / entry.path().filename(),
                          fs::copy_options::overwrite_existing, error);
            if (error) die("cannot copy " + entry.path().string());
        }
        if (error) die("cannot list " + dir);
    }
}

/// Sends std::cout and std::cerr (the library's and the CLI's messages, --help) nowhere.
/// File descriptors 1 and 2 stay open: libFuzzer and the sanitizers report there.
inline void silence_iostreams() {
    struct Null : std::streambuf {
        int overflow(int c) override { return traits_type::not_eof(c); }
        std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
    };
    // Never destroyed: the standard streams flush at exit, after every static object is gone
    // (a static Null here was flushed after its destruction: a crash at exit under ASan).
    static Null* const null = new Null;
    std::cout.rdbuf(null);
    std::cerr.rdbuf(null);
    std::clog.rdbuf(null);
}

}  // namespace hbf_fuzz
