// hbf command line — the MPI session of `hbf map` (mpi_session.hpp): ranks, or one process
// without Open MPI.
#include "mpi_session.hpp"

#include <cstdlib>
#include <exception>
#include <stdexcept>

#ifdef HBF_WITH_MPI
#include <mpi.h>
#endif

namespace hbf::cli {

namespace {
/// Started by an MPI launcher (Open MPI, MPICH/PMI, Slurm's PMIx)?
bool launched_by_mpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(name) != nullptr) return true;
    return false;
}
}  // namespace

bool MpiSession::available() {
#ifdef HBF_WITH_MPI
    return true;
#else
    return false;
#endif
}

MpiSession::MpiSession() {
    if (!launched_by_mpirun()) return;
#ifdef HBF_WITH_MPI
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) MPI_Init(nullptr, nullptr);
    active_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
#else
    throw std::runtime_error("this hbf was built without MPI, but it runs under mpirun: every rank would compute "
                             "the whole map; run it without mpirun (threads: --threads), or install libopenmpi-dev "
                             "and rebuild");
#endif
}

MpiSession::~MpiSession() {
#ifdef HBF_WITH_MPI
    if (!active_) return;
    if (std::uncaught_exceptions() > 0 && size_ > 1) {
        MPI_Abort(MPI_COMM_WORLD, 1);
        return;
    }
    MPI_Finalize();
#endif
}

std::vector<std::string> MpiSession::gather(const std::string& mine) const {
    if (!active_ || size_ == 1) return {mine};
#ifdef HBF_WITH_MPI
    // Lengths first, then the bytes (MPI_Gatherv counts are int: each rank's part < 2 GB).
    if (mine.size() > 2000000000u) throw std::runtime_error("MPI gather: a rank's results exceed 2 GB");
    const int length = static_cast<int>(mine.size());
    std::vector<int> lengths(rank_ == 0 ? static_cast<std::size_t>(size_) : 0u);
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::vector<int> offsets(lengths.size());
    long long total = 0;
    for (std::size_t r = 0; r < lengths.size(); ++r) {
        offsets[r] = static_cast<int>(total);
        total += lengths[r];
    }
    if (total > 2000000000LL) throw std::runtime_error("MPI gather: the results exceed 2 GB");
    std::string all(static_cast<std::size_t>(total), '\0');
    MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
    std::vector<std::string> parts;
    for (std::size_t r = 0; r < lengths.size(); ++r)
        parts.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(lengths[r])));
    return parts;
#else
    return {mine};
#endif
}

int MpiSession::broadcast(int value) const {
#ifdef HBF_WITH_MPI
    if (active_ && size_ > 1) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
    return value;
}

}  // namespace hbf::cli
