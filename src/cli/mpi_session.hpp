// hbf command line — MPI for `hbf map` on a cluster (`mpirun -n K hbf map ...`). Open MPI is
// an optional build dependency: without it (HBF_WITH_MPI undefined) every process is a single
// rank, and a process launched by mpirun is refused (it would compute and write the whole map
// once per rank).
#pragma once

#include <string>
#include <vector>

namespace hbf::cli {

class MpiSession {
public:
    /// Initialises MPI when the process was started by mpirun/srun (their environment
    /// variables), else a single rank. Throws std::runtime_error under mpirun without MPI.
    MpiSession();
    /// Finalises MPI; while an exception unwinds, aborts the job instead (the other ranks
    /// would wait for this one for ever).
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    /// Whether this binary was built with MPI.
    static bool available();
    /// Every rank's string, in rank order, at rank 0 (empty on the others).
    std::vector<std::string> gather(const std::string& mine) const;
    /// Rank 0's value on every rank.
    int broadcast(int value) const;

private:
    bool active_ = false;
    int rank_ = 0, size_ = 1;
};

}  // namespace hbf::cli
