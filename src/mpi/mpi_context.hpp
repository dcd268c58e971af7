// MPI for hemirad: started only when a launcher (mpirun) made this process a rank, and the failure
// agreement that every rank joins at each phase boundary so that an error anywhere ends all ranks
// with one message, never a hang.
#pragma once

#include "engine/error.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace hemirad::mpi {

/// An error every rank agreed on: rank 0 prints it once; every rank exits with `status`.
class AgreedFailure : public Error {
public:
    AgreedFailure(int status, const std::string& message) : Error(message), m_status(status) {}
    int status() const { return m_status; }

private:
    int m_status;
};

/// MPI_COMM_WORLD for the life of the object (MPI_THREAD_FUNNELED: only the main thread calls MPI;
/// back ends compute on worker threads meanwhile); start() initialises PETSc (no command-line options,
/// no signal handlers) so that the solve can use it.
class Context {
public:
    /// Starts MPI. Throws hemirad::Error when MPI_Init_thread fails (no rank can tell another then).
    Context();
    /// Finalises PETSc where start() initialised it, then MPI: also after a failed start.
    ~Context();
    /// Checks MPI's thread level and initialises PETSc on every rank, each step agreed: a rank's
    /// failure (PETSc cannot read the options file PETSC_OPTIONS names) throws AgreedFailure on every
    /// rank. Collective; once, before anything else.
    void start();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    int rank() const { return m_rank; }
    int size() const { return m_size; }
    bool root() const { return m_rank == 0; }
    /// Ranks on this rank's node (they share its memory).
    int ranksOnNode() const { return m_ranksOnNode; }

    /// Every rank calls this at the same point of the program with its status (0 = fine, 1 runtime
    /// error, 2 usage error) and message. Returns when every rank is fine; otherwise throws
    /// AgreedFailure on every rank with the first failing rank's status and message ("rank R of K: "
    /// in front unless every rank failed the same way, as all do for a malformed scene).
    void agree(int status = 0, const std::string& message = {}) const;

    /// Runs `step` on every rank, then agree()s: an Error thrown on one rank ends all of them.
    template <class Step>
    void collectively(Step&& step) const {
        int status = 0;
        std::string message;
        try {
            step();
        } catch (const AgreedFailure&) {
            throw;
        } catch (const Error& e) {
            status = statusOf(e);
            message = e.what();
        } catch (const std::bad_alloc&) {
            status = 1;
            message = "out of memory";
        } catch (const std::exception& e) {
            status = 1;
            message = e.what();
        }
        agree(status, message);
    }

    /// Rank 0's `value` on every rank: for a decision every rank must take alike (a file's kind, read on
    /// a filesystem that might not look the same from every node). Collective.
    bool rootDecides(bool value) const;

    /// The ranks whose `value` differs from rank 0's, in rank order, on every rank (empty when all
    /// agree). Collective.
    std::vector<int> ranksDiffering(std::uint64_t value) const;

    /// Rank 0's `text` on every rank (the others' `text` is not read). Collective.
    std::string broadcastText(const std::string& text) const;

    /// Texts from every rank, in rank order, on rank 0 (empty elsewhere).
    std::vector<std::string> gatherText(const std::string& text) const;

    /// Ends every rank at once (an error outside any agreement point); does not return.
    [[noreturn]] void abort(const std::string& message) const;

private:
    static int statusOf(const Error& e);
    int m_rank = 0, m_size = 1, m_ranksOnNode = 1, m_threadLevel = 0;
    bool m_petsc = false;  ///< PETSc initialised (by start())
};

/// Throws hemirad::Error "MPI: `what`: MPI's text for `code`" unless `code` is MPI_SUCCESS (errors
/// come back as codes: MPI_ERRORS_RETURN).
void checkMpi(int code, const char* what);

/// Prints "hemirad: error: rank R of K: message" and ends every rank at once (MPI_Abort): for an error
/// inside a collective, where the other ranks cannot be told otherwise. Does not return.
[[noreturn]] void abortAllRanks(const std::string& message);

/// Sends or receives a large array in pieces below MPI's int count limit (blocking, point to point).
void sendBytes(const void* data, std::size_t bytes, int destination, int tag);
void receiveBytes(void* data, std::size_t bytes, int source, int tag);

template <class T>
void sendVector(const std::vector<T>& v, int destination, int tag) {
    const std::uint64_t n = v.size();
    sendBytes(&n, sizeof n, destination, tag);
    sendBytes(v.data(), n * sizeof(T), destination, tag);
}
template <class T>
std::vector<T> receiveVector(int source, int tag) {
    std::uint64_t n = 0;
    receiveBytes(&n, sizeof n, source, tag);
    std::vector<T> v(n);
    receiveBytes(v.data(), n * sizeof(T), source, tag);
    return v;
}

}  // namespace hemirad::mpi
