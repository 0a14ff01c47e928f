// hbfriction benchmarks: one case in a child process, so that its peak memory (ru_maxrss) is
// its own and a crash or a runaway case cannot take the table down with it.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <functional>
#include <string>

namespace hbf::bench {

struct ChildResult {
    std::string text;    ///< what the child's `work` returned
    double peak_mb = 0;  ///< its peak resident memory
};

/// Runs `work` in a forked child and returns its text (empty if the child died) and peak memory.
inline ChildResult run_in_child(const std::function<std::string()>& work) {
    int fd[2];
    if (pipe(fd) != 0) return {};
    const pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        const std::string text = work();
        if (write(fd[1], text.data(), text.size()) < 0) _exit(2);
        close(fd[1]);
        _exit(0);
    }
    close(fd[1]);
    ChildResult r;
    char buffer[256];
    for (ssize_t got; (got = read(fd[0], buffer, sizeof buffer)) > 0;) r.text.append(buffer, static_cast<std::size_t>(got));
    close(fd[0]);
    int status = 0;
    struct rusage usage {};
    wait4(pid, &status, 0, &usage);
    r.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
    return r;
}

}  // namespace hbf::bench
