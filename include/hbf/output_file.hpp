// hbfriction — the output policy and atomic output files: every output checked before any
// work (never an input of the run, a directory, a device replaced), written whole or not at all.
#pragma once

#include <signal.h>

#include <cstdint>
#include <iosfwd>
#include <sstream>
#include <string>
#include <vector>

namespace hbf::io {

/// An input file of a run (the config, a Matrix Market file it names): what names it, for
/// messages ("--config", "structure.mass"), and its path. No output may be one
/// (check_outputs).
struct InputFile {
    std::string what;
    std::string path;
};

/// An output a command will write: the flag naming it, its path ("-" for standard output;
/// empty: not written unless `stdout_if_empty`), and whether it is an image (--plot).
struct OutputTarget {
    std::string flag;
    std::string path;
    bool given = false;            ///< the flag was on the command line (an empty value is an error)
    bool stdout_if_empty = false;  ///< an absent path means standard output (--out)
    bool image = false;            ///< written by gnuplot: a regular file only
};

/// The output policy, checked before any work; throws InvalidInput naming the flag:
///  - an empty value given on the command line is an error; "-" means standard output, and
///    only one output may go there;
///  - a new file needs an existing, writable directory; an existing target must not be a
///    directory; a regular file (or a symlink to one, which stays a symlink) is replaced
///    atomically (OutputFile); a character device or a FIFO (or a symlink to one) is written
///    in place and never replaced (not for images, which need a regular file); a socket or a
///    dangling symlink is refused;
///  - no output may be one of `inputs` (compared by device and inode: through symlinks and
///    hard links);
///  - no two outputs may be the same file: an existing one by device and inode, a new one by
///    its canonical directory and name (./o.csv, sub/../o.csv, $PWD/o.csv and
///    /proc/self/cwd/o.csv are one file); several outputs to one character device, such as
///    /dev/null, are allowed;
///  - a character device or descriptor is opened for writing now, without blocking (/dev/tty
///    without a terminal is refused here, not after the work); a FIFO is opened now without
///    blocking and refused when it has no reader (the write would wait forever); it is held
///    open until its OutputFile writes, so that its reader does not see an end of file.
void check_outputs(const std::vector<OutputTarget>& targets, const std::vector<InputFile>& inputs = {});

/// The input policy, before anything is read: `path` (given by `flag`) must be an existing
/// regular file (not a directory, device or FIFO, which could block or never end) of at most
/// `max_bytes` bytes. Throws InvalidInput naming the flag and what the path is.
void check_input_file(const std::string& flag, const std::string& path, std::uintmax_t max_bytes);

/// An output destination that never leaves a partial or temporary file behind: the content is
/// kept in memory and written by commit() only. A regular file is written to a temporary file
/// beside the target (a symlink's final target), with the mode and (where permitted) the
/// owner of the file it replaces, synced, and renamed onto it; SIGINT, SIGTERM, SIGHUP and
/// SIGQUIT are held back while the temporary file exists (delivered after the rename), and a
/// file-size limit (SIGXFSZ) makes the write fail cleanly. Without commit() nothing is
/// written. An empty path or "-" means standard output; an existing character device, FIFO
/// or descriptor is written in place, never replaced (a FIFO through the descriptor
/// check_outputs holds open, or opened without blocking: no reader is an error, never a wait).
class OutputFile {
public:
    explicit OutputFile(std::string path);
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    std::ostream& stream();
    /// Writes the content to its destination; throws std::runtime_error on failure (the target
    /// is then untouched and no temporary file is left).
    void commit();

private:
    std::string path_;    // as given
    std::string target_;  // the file renamed onto (symlinks resolved), or written in place
    std::ostringstream buffer_;
    bool in_place_ = false;
    bool fifo_ = false;
    bool committed_ = false;
};

/// While alive: SIGINT, SIGTERM, SIGHUP and SIGQUIT are held back in this thread (delivered
/// when it ends: a signal never leaves a temporary file behind) and SIGXFSZ is ignored (a
/// file-size limit makes write() fail with EFBIG, handled, instead of killing the process
/// with a temporary file left). Around the short moments a temporary output file exists.
class HeldSignals {
public:
    HeldSignals();
    ~HeldSignals();
    HeldSignals(const HeldSignals&) = delete;
    HeldSignals& operator=(const HeldSignals&) = delete;

private:
    sigset_t old_mask_{};
    struct sigaction old_xfsz_ {};
    bool blocked_ = false, ignored_ = false;
};

}  // namespace hbf::io
