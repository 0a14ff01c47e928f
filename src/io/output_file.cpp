// hbfriction — the output policy (output_file.hpp): every output path checked before any work, and
// OutputFile, which writes atomically or in place and never leaves a partial file.

#include "hbf/output_file.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>

#include "hbf/error.hpp"

namespace hbf::io {

namespace {
namespace fs = std::filesystem;

/// Standard output: '-' (or empty), and the names the system gives its descriptor 1.
bool is_stdout(const std::string& path) {
    return path.empty() || path == "-" || path == "/dev/stdout" || path == "/dev/fd/1" || path == "/proc/self/fd/1";
}

/// A name of an open descriptor of this process (/dev/stderr, /dev/fd/N, /proc/self/fd/N):
/// its link points into /proc (a pipe's "pipe:[N]" resolves to nothing), so it is opened as
/// named and written in place, whatever it refers to (a pipe, a terminal, a file).
bool is_descriptor(const std::string& path) {
    return path == "/dev/stderr" || path.rfind("/dev/fd/", 0) == 0 || path.rfind("/proc/self/fd/", 0) == 0;
}

std::string temporary_name(const std::string& path) {
    std::random_device device;
    return path + ".tmp" + std::to_string(device() % 1000000000u);
}

/// What an existing or new output path is, symlinks followed.
struct Resolved {
    fs::path target;           ///< the final target (the path itself when it does not exist)
    fs::file_status status;    ///< of the target (not_found for a new file)
    bool dangling = false;     ///< a symlink whose target does not exist
    bool descriptor = false;   ///< is_descriptor: written in place
};

Resolved resolve(const std::string& path) {
    Resolved r;
    std::error_code error;
    if (is_descriptor(path)) {
        r.target = path;
        r.descriptor = true;
        r.status = fs::file_status(fs::file_type::character);
        if (::access(path.c_str(), F_OK) != 0) r.dangling = true;  // no such descriptor
        return r;
    }
    const fs::file_status link = fs::symlink_status(path, error);
    if (fs::is_symlink(link)) {
        r.target = fs::canonical(path, error);
        if (error) {
            r.dangling = true;
            r.target = path;
            return r;
        }
    } else {
        r.target = path;
    }
    r.status = fs::status(r.target, error);
    return r;
}

bool written_in_place(const fs::file_status& status) {
    return fs::is_character_file(status) || fs::is_fifo(status);
}

/// The name under which two spellings of one file compare equal, whether it exists or not:
/// the canonical directory (".", "sub/..", $PWD, /proc/self/cwd and symlinked directories
/// all resolve to one) and the file name.
fs::path identity(const fs::path& target) {
    std::error_code error;
    const fs::path directory = fs::canonical(target.has_parent_path() ? target.parent_path() : fs::path("."), error);
    return error ? fs::weakly_canonical(target, error) : directory / target.filename();
}

/// FIFOs opened (without blocking) by check_outputs, held until their OutputFile writes: a
/// FIFO without a reader is refused before the work, and the reader that was there then is
/// not sent an end of file by a close in between. Keyed by the FIFO's identity().
std::map<std::string, int>& held_fifos() {
    static std::map<std::string, int> fds;
    return fds;
}

/// Writes all of `text` to `fd`; false with errno set on a failure (EFBIG, ENOSPC, EPIPE...).
bool write_all(int fd, const std::string& text) {
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        done += static_cast<std::size_t>(n);
    }
    return true;
}

}  // namespace

HeldSignals::HeldSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&set, signal);
    blocked_ = ::pthread_sigmask(SIG_BLOCK, &set, &old_mask_) == 0;
    struct sigaction ignore {};
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    ignored_ = ::sigaction(SIGXFSZ, &ignore, &old_xfsz_) == 0;
}

HeldSignals::~HeldSignals() {
    if (ignored_) ::sigaction(SIGXFSZ, &old_xfsz_, nullptr);
    if (blocked_) ::pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
}

void check_input_file(const std::string& flag, const std::string& path, std::uintmax_t max_bytes) {
    std::error_code error;
    const auto status = fs::status(path, error);
    if (!fs::exists(status)) throw InvalidInput(flag + " = '" + path + "' cannot be read (no such file, or not readable)");
    if (!fs::is_regular_file(status))
        throw InvalidInput(flag + " = '" + path + "' is not a regular file (a directory, device or FIFO): allowed a file");
    const std::uintmax_t bytes = fs::file_size(path, error);
    if (error || bytes > max_bytes)
        throw InvalidInput(flag + " = '" + path + "' has " + std::to_string(bytes) + " bytes: allowed at most " +
                           std::to_string(max_bytes));
}

void check_outputs(const std::vector<OutputTarget>& targets, const std::vector<InputFile>& inputs) {
    struct Seen {
        std::string flag;
        fs::path path;
        dev_t device = 0;
        ino_t inode = 0;
        bool exists = false, character = false;
    };
    // Every input of the run, by device and inode (symlinks followed, hard links the same inode).
    struct Input {
        std::string what, path;
        dev_t device;
        ino_t inode;
    };
    std::vector<Input> input_files;
    for (const InputFile& in : inputs) {
        struct stat info {};
        if (!in.path.empty() && ::stat(in.path.c_str(), &info) == 0)
            input_files.push_back({in.what, in.path, info.st_dev, info.st_ino});
    }
    std::vector<Seen> seen;
    std::string to_stdout;
    for (const OutputTarget& t : targets) {
        if (t.path.empty()) {
            if (t.given)
                throw InvalidInput(t.flag + " is empty: allowed a file path" +
                                   (t.stdout_if_empty ? std::string(", or - for standard output") : std::string()));
            if (!t.stdout_if_empty) continue;
        }
        if (is_stdout(t.path)) {
            if (t.image) throw InvalidInput(t.flag + " = '-': an image is written to a file: allowed a .png or .svg path");
            if (!to_stdout.empty())
                throw InvalidInput(t.flag + " and " + to_stdout + " both go to standard output: allowed one of them");
            to_stdout = t.flag;
            continue;
        }
        const std::string where = t.flag + " = '" + t.path + "'";
        const Resolved r = resolve(t.path);
        if (r.dangling)
            throw InvalidInput(where + (r.descriptor ? " is not an open descriptor of this process"
                                                     : " is a symlink to nothing: allowed a file, or a link to one"));
        Seen mine{t.flag, r.target, 0, 0, false, false};
        // A device or descriptor is opened now, without blocking, as the write will open it:
        // /dev/tty without a terminal or a closed descriptor fails here, not after the work.
        auto try_open = [&](const std::string& what) {
            const int fd = ::open(r.target.c_str(), O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
            if (fd < 0)
                throw InvalidInput(where + " " + what + " cannot be opened for writing (" + std::strerror(errno) + ")");
            ::close(fd);
        };
        if (r.descriptor) {
            if (t.image) throw InvalidInput(where + " is a descriptor: an image needs a regular file path");
            try_open("(a descriptor)");
            seen.push_back(mine);
            continue;
        }
        if (fs::exists(r.status)) {
            if (fs::is_directory(r.status)) throw InvalidInput(where + " is a directory: allowed a file path");
            const bool regular = fs::is_regular_file(r.status);
            if (!regular && !written_in_place(r.status))
                throw InvalidInput(where + " is neither a file, a character device nor a FIFO: allowed those");
            if (!regular && t.image)
                throw InvalidInput(where + " is a device or FIFO: an image needs a regular file path");
            if (::access(r.target.c_str(), W_OK) != 0) throw InvalidInput(where + " is not writable");
            struct stat info {};
            if (::stat(r.target.c_str(), &info) == 0) {
                mine.exists = true;
                mine.device = info.st_dev;
                mine.inode = info.st_ino;
                mine.character = S_ISCHR(info.st_mode);
                for (const Input& in : input_files)
                    if (in.device == info.st_dev && in.inode == info.st_ino)
                        throw InvalidInput(where + " is " + in.what + " ('" + in.path +
                                           "'), an input of this run: allowed a file that is not an input");
            }
            if (fs::is_character_file(r.status)) try_open("(a character device)");
            if (fs::is_fifo(r.status)) {
                const std::string key = identity(r.target).string();
                auto& held = held_fifos();
                if (held.count(key) == 0) {
                    const int fd = ::open(r.target.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
                    if (fd < 0 && errno == ENXIO)
                        throw InvalidInput(where + " is a FIFO without a reader: start the reader first (the write "
                                           "would wait for one forever)");
                    if (fd < 0)
                        throw InvalidInput(where + " (a FIFO) cannot be opened for writing (" + std::strerror(errno) + ")");
                    held[key] = fd;
                }
            }
        }
        // Regular files are replaced through a temporary file in their directory: it must
        // exist and be writable (new files likewise).
        if (!fs::exists(r.status) || fs::is_regular_file(r.status)) {
            const fs::path directory = r.target.has_parent_path() ? r.target.parent_path() : fs::path(".");
            std::error_code error;
            if (!fs::is_directory(directory, error))
                throw InvalidInput(where + ": the directory '" + directory.string() + "' does not exist");
            if (::access(directory.c_str(), W_OK | X_OK) != 0)
                throw InvalidInput(where + ": the directory '" + directory.string() + "' is not writable");
        }
        mine.path = identity(r.target);
        for (const Seen& other : seen) {
            const bool same_inode = mine.exists && other.exists && mine.device == other.device && mine.inode == other.inode;
            if ((same_inode || mine.path == other.path) && !(mine.character && other.character))
                throw InvalidInput(t.flag + " and " + other.flag + " name the same file '" + t.path +
                                   "': allowed different files");
        }
        seen.push_back(mine);
    }
}

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
    if (is_stdout(path_)) return;
    const Resolved r = resolve(path_);
    if (r.dangling) throw std::runtime_error("output '" + path_ + "' is a symlink to nothing");
    target_ = r.target.string();
    in_place_ = r.descriptor || written_in_place(r.status);
    fifo_ = !r.descriptor && fs::is_fifo(r.status);
}

OutputFile::~OutputFile() = default;

std::ostream& OutputFile::stream() { return buffer_; }

void OutputFile::commit() {
    const std::string text = buffer_.str();
    if (is_stdout(path_)) {
        std::cout << text;
        std::cout.flush();
        if (!std::cout) throw std::runtime_error("cannot write to standard output");
        committed_ = true;
        return;
    }
    if (in_place_) {  // a device, FIFO or descriptor: written where it is, never replaced
        int fd = -1;
        if (fifo_) {
            auto& held = held_fifos();
            const auto it = held.find(identity(target_).string());
            if (it != held.end()) {
                fd = it->second;
                held.erase(it);
            } else {
                fd = ::open(target_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
                if (fd < 0 && errno == ENXIO)
                    throw std::runtime_error("output '" + path_ + "' is a FIFO without a reader: nothing written");
            }
            if (fd >= 0) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
        } else {
            fd = ::open(target_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
        }
        if (fd < 0) throw std::runtime_error("cannot open output '" + path_ + "' for writing (" + std::strerror(errno) + ")");
        HeldSignals quiet;
        const bool written = write_all(fd, text);
        const int error = errno;
        ::close(fd);
        if (!written) throw std::runtime_error("cannot write output '" + path_ + "' (" + std::strerror(error) + ")");
        committed_ = true;
        return;
    }
    // A regular file: a temporary file beside the target, created only now, with the mode
    // (and, where permitted, the owner) of the file it replaces, on disk before the rename
    // makes it visible (a crash leaves the old file), and removed on any failure.
    HeldSignals quiet;
    struct stat old {};
    const bool replacing = ::stat(target_.c_str(), &old) == 0 && S_ISREG(old.st_mode);
    int fd = -1;
    std::string temporary;
    for (int attempt = 0; attempt < 16 && fd < 0; ++attempt) {
        temporary = temporary_name(target_);
        fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    if (fd < 0)
        throw std::runtime_error("cannot create a temporary file beside '" + path_ + "' (" + std::strerror(errno) + ")");
    if (replacing) {
        if (::fchown(fd, old.st_uid, old.st_gid) != 0) {
            // not permitted (another user's file, as a normal user): the mode is kept below
        }
        ::fchmod(fd, old.st_mode & 07777);
    }
    bool good = write_all(fd, text);
    int error = errno;
    if (good && ::fsync(fd) != 0) {
        good = false;
        error = errno;
    }
    if (::close(fd) != 0 && good) {
        good = false;
        error = errno;
    }
    if (good && std::rename(temporary.c_str(), target_.c_str()) != 0) {
        good = false;
        error = errno;
    }
    if (!good) {
        ::unlink(temporary.c_str());
        throw std::runtime_error("cannot write output file '" + path_ + "' (" + std::strerror(error) + ")");
    }
    committed_ = true;
}

}  // namespace hbf::io
