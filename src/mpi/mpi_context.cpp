// MPI context: MPI and PETSc start-up, the failure agreement, chunked transfers.
#include "mpi/mpi_context.hpp"

#include "cli/options.hpp"
#include "engine/console.hpp"

#include <mpi.h>
#include <petscsys.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <string>

namespace hemirad::mpi {
namespace {

/// Pieces of at most 256 MiB: far below the int count limit, large enough to stream at full speed.
constexpr std::size_t kPieceBytes = std::size_t(1) << 28;

/// A PETSc error handler that prints nothing and keeps the first message in `kept` (a std::string).
PetscErrorCode keepFirstMessage(MPI_Comm, int, const char*, const char*, PetscErrorCode code, PetscErrorType type,
                                const char* message, void* kept) {
    auto& text = *static_cast<std::string*>(kept);
    if (text.empty() && type == PETSC_ERROR_INITIAL && message) text = message;
    return code;
}

}  // namespace

void checkMpi(int code, const char* what) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(std::string("MPI: ") + what + ": " + std::string(text, std::size_t(length)));
}

Context::Context() {
    checkMpi(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &m_threadLevel), "MPI_Init_thread");
    MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m_size);
    // Errors come back as codes (turned into hemirad::Error), never as MPI's abort.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, m_rank, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &m_ranksOnNode);
    MPI_Comm_free(&node);
}

void Context::start() {
    // Only the main thread calls MPI, but worker threads exist: a library without that level may not cope.
    std::string failure;
    if (m_threadLevel < MPI_THREAD_FUNNELED)
        failure = "MPI: the library does not support MPI_THREAD_FUNNELED (got level " + std::to_string(m_threadLevel) + ")";
    agree(failure.empty() ? 0 : 1, failure);
    // PETSc on the same communicator; hemirad's own flags are not PETSc options, and Ctrl-C stays ours.
    // Its errors, those of its start included, come back as codes that hemirad turns into its own
    // messages (no traceback from every rank).
    PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
    std::string message;
    PetscPushErrorHandler(keepFirstMessage, &message);
    m_petsc = PetscInitializeNoArguments() == 0;
    PetscPopErrorHandler();
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    if (!m_petsc)
        failure = "PETSc: initialisation failed: " + (message.empty() ? std::string("no message") : message) +
                  " (PETSc reads options from PETSC_OPTIONS and .petscrc files too)";
    agree(failure.empty() ? 0 : 1, failure);
}

Context::~Context() {
    if (m_petsc) PetscFinalize();
    MPI_Finalize();
}

int Context::statusOf(const Error& e) { return dynamic_cast<const UsageError*>(&e) ? 2 : 1; }

void Context::agree(int status, const std::string& message) const {
    // (failed?, first failing rank) in one reduction: MINLOC over (0 fine / -1 failed, rank)
    struct {
        int value;
        int rank;
    } mine{status ? -1 : 0, m_rank}, first{0, 0};
    checkMpi(MPI_Allreduce(&mine, &first, 1, MPI_2INT, MPI_MINLOC, MPI_COMM_WORLD), "agreement");
    if (first.value == 0) return;
    int failures = 0, failed = status ? 1 : 0;
    MPI_Allreduce(&failed, &failures, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    // The first failing rank's status and message go to everybody.
    int agreedStatus = status;
    MPI_Bcast(&agreedStatus, 1, MPI_INT, first.rank, MPI_COMM_WORLD);
    unsigned long length = message.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG, first.rank, MPI_COMM_WORLD);
    std::string text = m_rank == first.rank ? message : std::string(length, '\0');
    MPI_Bcast(text.data(), int(std::min<unsigned long>(length, INT_MAX)), MPI_CHAR, first.rank, MPI_COMM_WORLD);
    // Every rank failing with the same message (a malformed scene) reads as in one process.
    int same = !status || message == text ? 1 : 0, allSame = 0;
    MPI_Allreduce(&same, &allSame, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    if (!(failures == m_size && allSame)) {
        std::string where = "rank " + std::to_string(first.rank) + " of " + std::to_string(m_size);
        if (failures > 1) where += " (and " + std::to_string(failures - 1) + " more)";
        text = where + ": " + text;
    }
    throw AgreedFailure(agreedStatus, text);
}

std::vector<std::string> Context::gatherText(const std::string& text) const {
    int length = int(text.size());
    std::vector<int> lengths(m_rank == 0 ? m_size : 0), offsets(lengths.size());
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string all;
    if (m_rank == 0) {
        int total = 0;
        for (int r = 0; r < m_size; ++r) offsets[r] = total, total += lengths[r];
        all.resize(std::size_t(total));
    }
    MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
    std::vector<std::string> texts;
    for (int r = 0; m_rank == 0 && r < m_size; ++r) texts.push_back(all.substr(std::size_t(offsets[r]), std::size_t(lengths[r])));
    return texts;
}

std::vector<int> Context::ranksDiffering(std::uint64_t value) const {
    std::vector<std::uint64_t> values(std::size_t(m_size), 0);
    checkMpi(MPI_Allgather(&value, 1, MPI_UINT64_T, values.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD), "gathering hashes");
    std::vector<int> differing;
    for (int r = 1; r < m_size; ++r)
        if (values[std::size_t(r)] != values[0]) differing.push_back(r);
    return differing;
}

std::string Context::broadcastText(const std::string& text) const {
    std::uint64_t length = text.size();
    checkMpi(MPI_Bcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "broadcast");
    std::string all = m_rank == 0 ? text : std::string(std::size_t(length), '\0');
    for (std::size_t done = 0; done < all.size(); done += kPieceBytes)
        checkMpi(MPI_Bcast(all.data() + done, int(std::min(kPieceBytes, all.size() - done)), MPI_CHAR, 0, MPI_COMM_WORLD),
              "broadcast");
    return all;
}

bool Context::rootDecides(bool value) const {
    int flag = value ? 1 : 0;
    MPI_Bcast(&flag, 1, MPI_INT, 0, MPI_COMM_WORLD);
    return flag != 0;
}

void Context::abort(const std::string& message) const { abortAllRanks(message); }

void abortAllRanks(const std::string& message) {
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    printError("rank " + std::to_string(rank) + " of " + std::to_string(size) + ": " + message);
    MPI_Abort(MPI_COMM_WORLD, 1);
    std::_Exit(1);
}

void sendBytes(const void* data, std::size_t bytes, int destination, int tag) {
    const auto* p = static_cast<const char*>(data);
    for (std::size_t done = 0; done < bytes; done += kPieceBytes)
        checkMpi(MPI_Send(p + done, int(std::min(kPieceBytes, bytes - done)), MPI_BYTE, destination, tag, MPI_COMM_WORLD),
              "send");
}

void receiveBytes(void* data, std::size_t bytes, int source, int tag) {
    auto* p = static_cast<char*>(data);
    for (std::size_t done = 0; done < bytes; done += kPieceBytes)
        checkMpi(MPI_Recv(p + done, int(std::min(kPieceBytes, bytes - done)), MPI_BYTE, source, tag, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "receive");
}

}  // namespace hemirad::mpi
