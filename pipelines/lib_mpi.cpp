#include "pipelines/lib_mpi.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "core/error.h"
#include "core/ranks.h"

#ifdef LITTORAL_WITH_MPI
#include <mpi.h>
#endif

namespace littoral::pipelines {

#ifdef LITTORAL_WITH_MPI

namespace {

constexpr size_t kPiece = size_t{1} << 30;  // bytes per message: MPI counts are ints

// The shared queue: one 64-bit counter on rank 0, advanced by MPI_Fetch_and_op (passive target, so
// rank 0 need not take part while it renders).
class MpiQueue final : public WorkQueue {
public:
    explicit MpiQueue(MPI_Comm comm) {
        int rank = 0;
        MPI_Comm_rank(comm, &rank);
        MPI_Win_allocate(rank == 0 ? sizeof(int64_t) : 0, sizeof(int64_t), MPI_INFO_NULL, comm, &base_, &win_);
        if (rank == 0) *base_ = 0;
        MPI_Win_lock_all(0, win_);
        MPI_Win_sync(win_);
        MPI_Barrier(comm);
    }
    ~MpiQueue() override {
        // Collective: a rank that unwinds an error skips it (and the session's finish() ends the job).
        if (std::uncaught_exceptions() > 0) return;
        MPI_Win_unlock_all(win_);
        MPI_Win_free(&win_);
    }
    uint64_t next() override {
        const int64_t one = 1;
        int64_t got = 0;
        MPI_Fetch_and_op(&one, &got, MPI_INT64_T, 0, 0, MPI_SUM, win_);
        MPI_Win_flush(0, win_);
        return static_cast<uint64_t>(got);
    }

private:
    MPI_Win win_{};
    int64_t* base_ = nullptr;
};

class MpiRanks final : public RankGroup {
public:
    explicit MpiRanks(MPI_Comm comm) : comm_(comm) {
        MPI_Comm_rank(comm_, &rank_);
        MPI_Comm_size(comm_, &size_);
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    std::unique_ptr<WorkQueue> workQueue() const override { return std::make_unique<MpiQueue>(comm_); }

    std::vector<Bytes> allGather(const Bytes& mine) const override {
        std::vector<uint64_t> sizes(static_cast<size_t>(size_));
        uint64_t n = mine.size();
        MPI_Allgather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, comm_);
        std::vector<Bytes> all(sizes.size());
        for (int r = 0; r < size_; ++r) {
            Bytes& b = all[static_cast<size_t>(r)];
            b = r == rank_ ? mine : Bytes(sizes[static_cast<size_t>(r)]);
            for (size_t at = 0; at < b.size(); at += kPiece)
                MPI_Bcast(b.data() + at, static_cast<int>(std::min(kPiece, b.size() - at)), MPI_BYTE, r, comm_);
        }
        return all;
    }

    std::vector<Bytes> gatherToRoot(const Bytes& mine) const override {
        std::vector<uint64_t> sizes(static_cast<size_t>(size_));
        uint64_t n = mine.size();
        MPI_Gather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, 0, comm_);
        if (rank_ != 0) {
            for (size_t at = 0; at < mine.size(); at += kPiece)
                MPI_Send(mine.data() + at, static_cast<int>(std::min(kPiece, mine.size() - at)), MPI_BYTE, 0, 1, comm_);
            return {};
        }
        std::vector<Bytes> all(sizes.size());
        all[0] = mine;
        for (int r = 1; r < size_; ++r) {
            Bytes& b = all[static_cast<size_t>(r)];
            b.resize(sizes[static_cast<size_t>(r)]);
            for (size_t at = 0; at < b.size(); at += kPiece)
                MPI_Recv(b.data() + at, static_cast<int>(std::min(kPiece, b.size() - at)), MPI_BYTE, r, 1, comm_,
                         MPI_STATUS_IGNORE);
        }
        return all;
    }

private:
    MPI_Comm comm_;
    int rank_ = 0, size_ = 1;
};

// Seconds a failed rank waits for the others to fail alike before it aborts the job.
constexpr double kAgreementSeconds = 20;

}  // namespace

struct MpiSession::State {
    MPI_Comm work = MPI_COMM_NULL, status = MPI_COMM_NULL;
    int rank = 0, size = 1;
};

MpiSession::MpiSession(int* argc, char*** argv) {
    int launched = 0;
    for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (std::getenv(var)) launched = 1;
    if (!launched) return;
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    state_ = std::make_unique<State>();
    MPI_Comm_rank(MPI_COMM_WORLD, &state_->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &state_->size);
    // The renderer's exchanges on one communicator, the end-of-command agreement on another, so a
    // rank that fails while the others exchange cannot be matched with their collectives.
    MPI_Comm_dup(MPI_COMM_WORLD, &state_->work);
    MPI_Comm_dup(MPI_COMM_WORLD, &state_->status);
    active_ = true;
    if (state_->size > 1) setRanks(std::make_unique<MpiRanks>(state_->work));
}

MpiSession::~MpiSession() {
    if (!active_) return;
    setRanks(nullptr);
    MPI_Comm_free(&state_->work);
    MPI_Comm_free(&state_->status);
    MPI_Finalize();
}

int MpiSession::rank() const { return state_ ? state_->rank : 0; }
int MpiSession::size() const { return state_ ? state_->size : 1; }

int MpiSession::finish(int rc, const std::string& message) {
    if (!active_ || state_->size < 2) return rc;
    // [this rank failed, rank 0 failed], maximised over the ranks.
    int mine[2] = {rc != 0, rc != 0 && state_->rank == 0}, any[2] = {0, 0};
    MPI_Request req{};
    MPI_Iallreduce(mine, any, 2, MPI_INT, MPI_MAX, state_->status, &req);
    int done = 0;
    if (rc == 0) {
        MPI_Wait(&req, MPI_STATUS_IGNORE);
        done = 1;
    } else {
        const auto t0 = std::chrono::steady_clock::now();
        while (!done && std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < kAgreementSeconds) {
            MPI_Test(&req, &done, MPI_STATUS_IGNORE);
            if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
    if (!done) {
        // The others are still working or exchanging: this rank failed alone.
        if (state_->rank != 0) std::fprintf(stderr, "rank %d of %d: %s\n", state_->rank, state_->size, message.c_str());
        std::fprintf(stderr, "rank %d of %d failed while the other ranks went on: aborting the MPI job\n", state_->rank,
                     state_->size);
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, rc);
    }
    // Rank 0 printed its error; a rank that failed when rank 0 did not says why.
    if (rc != 0 && state_->rank != 0 && any[1] == 0)
        std::fprintf(stderr, "rank %d of %d: %s\n", state_->rank, state_->size, message.c_str());
    return any[0] && rc == 0 ? 1 : rc;
}

#else  // without MPI

namespace {

// The size a launcher put in the environment: OpenMPI's mpirun, MPICH's hydra and Slurm's srun
// (PMI); 1 when none did.
int environmentRanks() {
    for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
        if (const char* v = std::getenv(var)) {
            const int n = std::atoi(v);
            if (n > 0) return n;
        }
    return 1;
}

}  // namespace

struct MpiSession::State {};

MpiSession::MpiSession(int*, char***) {
    if (environmentRanks() > 1)
        throw InputError(fmt::format("launched as {} MPI ranks, but this littoral was built without MPI: install "
                                     "libopenmpi-dev (scripts/setup-deps.sh does) and build again, or run it without "
                                     "mpirun",
                                     environmentRanks()));
}
MpiSession::~MpiSession() = default;
int MpiSession::rank() const { return 0; }
int MpiSession::size() const { return 1; }
int MpiSession::finish(int rc, const std::string&) { return rc; }

#endif

}  // namespace littoral::pipelines
