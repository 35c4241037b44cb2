#pragma once
// MPI runs: `mpirun -np N littoral run|render ...` (docs/cluster.md). Built when CMake finds an MPI
// library (LITTORAL_MPI=AUTO, the default; OpenMPI from Debian); the same binary runs without
// mpirun as one process and never initialises MPI then.
//
// Under mpirun the session starts MPI for the main thread (MPI_THREAD_FUNNELED: the ranks' threads
// never call MPI), installs the ranks as core/ranks.h's group, and silences every rank but 0 (its
// log, progress and summary). At the end, finish() lets the ranks agree on the outcome: when every
// rank failed alike (bad input, which every rank meets at the same point), rank 0 has printed the
// error and they all exit with its code; when one rank failed alone (the others wait in an exchange
// that will never complete), it prints its error with its rank and aborts the job.
#include <memory>
#include <string>

namespace littoral::pipelines {

class MpiSession {
public:
    // Starts MPI when the environment says mpirun (or srun) launched this process with several
    // ranks; otherwise does nothing. InputError when launched so by a build without MPI.
    MpiSession(int* argc, char*** argv);
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    int rank() const;
    int size() const;
    // The command ended with exit code rc (0: success) and, on failure, `message` (already printed
    // on rank 0). Returns the exit code; may abort the job instead (a rank that failed alone).
    int finish(int rc, const std::string& message);

private:
    bool active_ = false;
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace littoral::pipelines
