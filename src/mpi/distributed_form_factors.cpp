// The distributed form-factor job: rank 0's guided work queue, the ranks' worker threads, gathering.
//
// Messages of the queue (rank r > 0 and rank 0; every ask gets exactly one reply except "finished",
// so no message is left unreceived):
//
//   r -> 0  kTagAsk    {kind, rows done, failed}   kind 0: progress only, 1: wants rows, 2: finished
//   0 -> r  kTagReply  {begin, end, state}         rows[begin, end) (may be empty); state 0 go on,
//                                                  1 no rows left, 2 abort (a rank failed)
#include "mpi/distributed_form_factors.hpp"
#include "mpi/distributed_reciprocity.hpp"

#include "engine/form_factor_file.hpp"
#include "engine/memory.hpp"
#include "engine/threads.hpp"
#include "preprocess/backend_registry.hpp"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <thread>

namespace hemirad::mpi {
namespace {

constexpr int kTagAsk = 101, kTagReply = 102, kTagColumns = 103, kTagValues = 104;
enum : std::uint64_t { kProgress = 0, kWantRows = 1, kFinished = 2 };
enum : std::uint64_t { kGoOn = 0, kNoRowsLeft = 1, kAbort = 2 };

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// The rows a rank's back end pulls: blocks of the ordered row list (granted in the list's order,
/// the same on every rank) pushed by the main thread; next() waits for one.
class QueueSource final : public RowSource {
public:
    QueueSource(const std::vector<PatchId>& ordered, std::size_t patches)
        : m_ordered(ordered.data()), m_hint(ordered.size()), m_queued(new std::atomic<std::uint8_t>[patches]()),
          m_position(patches, kUnlisted) {
        for (std::size_t k = 0; k < ordered.size(); ++k) m_position[ordered[k]] = std::uint32_t(k);
    }
    bool next(PatchId& row) override {
        std::unique_lock<std::mutex> lock(m_mutex);
        m_ready.wait(lock, [&] { return !m_rows.empty() || m_closed; });
        if (m_rows.empty()) return false;
        row = m_rows.front();
        m_rows.pop_front();
        return true;
    }
    std::size_t sizeHint() const override { return m_hint; }
    /// Rows pushed here, and rows past every block pushed here (not granted to any rank yet, as far
    /// as this rank knows): work kept for them pays when their block comes here. Rows before the
    /// latest block that are not here went to other ranks. The frontier is read first: a row pushed
    /// with it is seen as pushed.
    bool mayHandOut(PatchId row) const override {
        const std::size_t frontier = m_frontier.load(std::memory_order_acquire);
        const std::uint32_t position = m_position[row];
        if (position != kUnlisted && position >= frontier) return true;
        return m_queued[row].load(std::memory_order_relaxed) != 0;
    }
    /// Pushes the block [begin, end) of the ordered list.
    void push(const PatchId* begin, const PatchId* end) {
        for (const PatchId* row = begin; row != end; ++row) m_queued[*row].store(1, std::memory_order_relaxed);
        m_frontier.store(std::size_t(end - m_ordered), std::memory_order_release);
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_rows.insert(m_rows.end(), begin, end);
        }
        m_ready.notify_all();
    }
    void close() {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_closed = true;
        }
        m_ready.notify_all();
    }
    std::size_t pending() const {
        std::lock_guard<std::mutex> lock(m_mutex);
        return m_rows.size();
    }

private:
    static constexpr std::uint32_t kUnlisted = ~std::uint32_t(0);
    const PatchId* m_ordered;
    std::size_t m_hint;
    std::unique_ptr<std::atomic<std::uint8_t>[]> m_queued;  ///< per patch: pushed to this rank
    std::vector<std::uint32_t> m_position;                  ///< per patch: its place in the ordered list
    std::atomic<std::size_t> m_frontier{0};                 ///< the end of the latest block pushed here
    mutable std::mutex m_mutex;
    std::condition_variable m_ready;
    std::deque<PatchId> m_rows;
    bool m_closed = false;
};

/// Guided self-scheduling over the row list, weighed by row cost: a block holds about 1/(2K) of the
/// cost left (at most 1/(8K) of the whole, so that an abort or the tail waits for no huge block), and
/// at least `minRows` rows so that every worker thread of a rank has rows.
class Schedule {
public:
    Schedule(std::vector<double> cost, int ranks, std::size_t minRows)
        : m_cost(std::move(cost)), m_ranks(ranks), m_minRows(std::max<std::size_t>(1, minRows)) {
        for (double c : m_cost) m_left += c;
        m_cap = m_left / (8.0 * ranks);
    }
    /// [begin, end) of the next block; begin == end when none is left.
    std::pair<std::size_t, std::size_t> next() {
        const std::size_t begin = m_next;
        const double target = std::min(m_cap, m_left / (2.0 * m_ranks));
        double taken = 0;
        while (m_next < m_cost.size() && (m_next - begin < m_minRows || taken < target)) taken += m_cost[m_next++];
        m_left -= taken;
        return {begin, m_next};
    }

private:
    std::vector<double> m_cost;
    int m_ranks;
    std::size_t m_minRows, m_next = 0;
    double m_left = 0, m_cap = 0;
};

/// The back end on a worker thread, pulling from a queue; the main thread keeps MPI. On any path out
/// that skips join() (an MPI failure or another exception on the main thread), the builder is
/// cancelled and the queue closed before the thread is joined: a worker waiting for rows that will
/// never come would otherwise hold the join, and the rank, forever.
struct Worker {
    Worker(FormFactorBackend& backend, QueueSource& rows, FormFactorBuilder& into) : queue(rows), builder(into) {
        thread = std::thread([this, &backend] {
            const auto t0 = Clock::now();
            try {
                backend.computeRows(queue, builder);
            } catch (...) {
                failure = std::current_exception();
            }
            busySeconds = since(t0);
            done.store(true);
        });
    }
    ~Worker() {
        if (!thread.joinable()) return;
        builder.cancel();
        queue.close();
        thread.join();
    }
    /// Waits for the worker's end: its rows done, or stopped by a cancel and a closed queue.
    void join() { thread.join(); }
    QueueSource& queue;
    FormFactorBuilder& builder;
    std::thread thread;
    std::atomic<bool> done{false};
    std::exception_ptr failure;
    double busySeconds = 0;
};

std::string messageOf(const std::exception_ptr& failure) {
    try {
        std::rethrow_exception(failure);
    } catch (const std::bad_alloc&) {
        return "out of memory";
    } catch (const std::exception& e) {
        return e.what();
    }
    return "unknown failure";
}

// The main thread of each rank polls MPI at this period while its worker computes. Waking every
// 0.5 ms cost about 10 % of the rows' throughput with one rank per core (street64k at 768 directions:
// 6.56 s against 5.94 s at 5 ms), so rows are held in reserve instead: enough for a few periods.
constexpr double kPollSeconds = 0.002;

void pause() { std::this_thread::sleep_for(std::chrono::duration<double>(kPollSeconds)); }

/// Rows a rank keeps queued before it asks for more: four polling periods of work at the rate seen so
/// far (at least two rows per thread), so its worker never waits for an answer and the tail stays
/// a few milliseconds long.
std::size_t reserveRows(const FormFactorBuilder& builder, Clock::time_point start, std::size_t threads) {
    const double seconds = since(start);
    const double rate = seconds > 0 ? double(builder.rowsDone()) / seconds : 0.0;
    return std::max<std::size_t>(2 * threads, std::size_t(rate * 4 * kPollSeconds));
}

/// F with its rows [first, last) alone (the others not computed); `F` is released.
FormFactors keepRows(FormFactors&& F, std::size_t first, std::size_t last) {
    std::vector<std::vector<FormFactors::Entry>> rows(F.size());
    std::vector<std::uint8_t> computed(F.size(), 0);
    for (std::size_t i = first; i < last; ++i) {
        computed[i] = F.rowComputed(i) ? 1 : 0;
        for (std::uint64_t k = F.rowBegin(i); k < F.rowEnd(i); ++k) rows[i].push_back({F.columns()[k], F.values()[k]});
    }
    FormFactors kept = FormFactors::fromRows(std::move(rows), std::move(computed));
    kept.sceneHash = F.sceneHash;
    kept.provenance = F.provenance;
    kept.parameters = F.parameters;
    F = FormFactors();
    return kept;
}

/// Refuses (hemirad::Error naming `path`) F's rows on this node when its ranks, each holding up to
/// `largest` bytes (`holds` says what), would need more than 80 % of the node's available memory,
/// the budget of the computed F's check; `advice` says what to do instead. Unknown memory: no check.
void checkNodeMemory(const Context& context, const std::string& path, double largest, const std::string& holds,
                     const std::string& advice) {
    const std::size_t available = availableMemory();
    const double budget = 0.8 * double(available), together = largest * double(context.ranksOnNode());
    if (!available || together <= budget) return;
    throw Error(path, 0, "the " + std::to_string(context.ranksOnNode()) + " ranks on this node would hold about " +
                             bytesText(together) + " of F together (" + holds + "), more than the " + bytesText(budget) +
                             " available; " + advice + ", or pass --no-memory-check");
}

}  // namespace

DistributedFormFactors computeDistributed(const Context& context, const Scene& scene, const MethodSettings& settings,
                                          const std::vector<PatchId>& listed, const ProgressCallback& progress) {
    const int K = context.size();
    std::unique_ptr<FormFactorBackend> backend;
    auto t0 = Clock::now();
    context.collectively([&] {
        backend = makeBackend(settings);
        backend->prepare(scene);
    });
    double prepareSeconds = since(t0);
    std::vector<PatchId> rows(listed);  // in the back end's order (the same on every rank)
    backend->orderRows(rows);

    FormFactorBuilder builder(scene);
    QueueSource queue(rows, scene.size());
    const std::size_t threads = std::size_t(resolveThreads(settings.common.threads));
    const std::size_t minRows = 4 * threads;
    std::vector<std::int32_t> owner(scene.size(), -1);
    const auto start = Clock::now();
    bool aborted = false;
    std::unique_ptr<Worker> worker;
    if (context.root()) {
        std::vector<double> cost(rows.size());
        for (std::size_t k = 0; k < rows.size(); ++k) cost[k] = std::max(1e-3, backend->rowCost(rows[k]));
        Schedule schedule(std::move(cost), K, minRows);
        auto grant = [&](int rank) {
            const auto block = schedule.next();
            for (std::size_t k = block.first; k < block.second; ++k) owner[rows[k]] = rank;
            return block;
        };
        worker = std::make_unique<Worker>(*backend, queue, builder);
        std::vector<std::uint64_t> done(std::size_t(K), 0);
        int finished = 0;
        bool exhausted = false, failed = false;
        auto lastProgress = Clock::now();
        while (finished < K - 1 || !worker->done.load()) {
            int flag = 0;
            MPI_Status status;
            for (;;) {
                checkMpi(MPI_Iprobe(MPI_ANY_SOURCE, kTagAsk, MPI_COMM_WORLD, &flag, &status), "waiting for the ranks");
                if (!flag) break;
                std::uint64_t ask[3];
                const int source = status.MPI_SOURCE;
                checkMpi(MPI_Recv(ask, 3, MPI_UINT64_T, source, kTagAsk, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                         "receiving a rank's request");
                done[std::size_t(source)] = ask[1];
                failed = failed || ask[2];
                if (ask[0] == kFinished) {
                    ++finished;
                    continue;
                }
                std::uint64_t reply[3] = {0, 0, failed ? kAbort : kGoOn};
                if (!failed && ask[0] == kWantRows) {
                    const auto block = grant(source);
                    reply[0] = block.first, reply[1] = block.second;
                    if (block.first == block.second) reply[2] = kNoRowsLeft;
                }
                checkMpi(MPI_Send(reply, 3, MPI_UINT64_T, source, kTagReply, MPI_COMM_WORLD), "granting rows");
            }
            if (worker->done.load() && worker->failure) failed = true;
            if (failed && !aborted) {
                builder.cancel();
                queue.close();
                aborted = true;
            }
            if (!exhausted && !aborted && queue.pending() < reserveRows(builder, start, threads)) {
                const auto block = grant(0);
                if (block.first == block.second) {
                    queue.close();
                    exhausted = true;
                } else {
                    queue.push(rows.data() + block.first, rows.data() + block.second);
                }
            }
            if (progress && since(lastProgress) > 0.1) {
                std::uint64_t total = builder.rowsDone();
                for (int r = 1; r < K; ++r) total += done[std::size_t(r)];
                progress(std::min<std::size_t>(total, rows.size()), rows.size(), since(start));
                lastProgress = Clock::now();
            }
            pause();
        }
    } else {
        worker = std::make_unique<Worker>(*backend, queue, builder);
        bool outstanding = false, exhausted = false;
        std::uint64_t reply[3] = {0, 0, 0};
        MPI_Request request = MPI_REQUEST_NULL;
        auto lastAsk = Clock::now();
        auto ask = [&](std::uint64_t kind) {
            const bool failed = worker->done.load() && worker->failure;
            const std::uint64_t message[3] = {kind, builder.rowsDone(), failed ? 1u : 0u};
            checkMpi(MPI_Send(message, 3, MPI_UINT64_T, 0, kTagAsk, MPI_COMM_WORLD), "asking for rows");
            lastAsk = Clock::now();
        };
        for (;;) {
            if (outstanding) {
                int flag = 0;
                checkMpi(MPI_Test(&request, &flag, MPI_STATUS_IGNORE), "waiting for rows");
                if (flag) {
                    outstanding = false;
                    if (reply[2] == kAbort && !aborted) {
                        builder.cancel();
                        queue.close();
                        aborted = exhausted = true;
                    } else if (reply[2] == kNoRowsLeft) {
                        queue.close();
                        exhausted = true;
                    } else if (reply[0] < reply[1]) {
                        queue.push(rows.data() + reply[0], rows.data() + reply[1]);
                    }
                }
            }
            if (!outstanding) {
                const bool workerDone = worker->done.load();
                if (workerDone && (exhausted || worker->failure)) {
                    ask(kFinished);
                    break;
                }
                const bool wantRows = !exhausted && queue.pending() < reserveRows(builder, start, threads);
                if (wantRows || since(lastAsk) > 0.5) {
                    ask(wantRows ? kWantRows : kProgress);
                    checkMpi(MPI_Irecv(reply, 3, MPI_UINT64_T, 0, kTagReply, MPI_COMM_WORLD, &request), "waiting for rows");
                    outstanding = true;
                }
            }
            pause();
        }
    }
    worker->join();
    const double computeSeconds = since(start);
    // A worker's error, if any: the first failing rank's message ends every rank.
    context.agree(worker->failure ? 1 : 0, worker->failure ? messageOf(worker->failure) : std::string());

    DistributedFormFactors result;
    // Rank 0 knows every block's rank; the other ranks learn it (the solve and the gather need it).
    MPI_Bcast(owner.data(), int(owner.size()), MPI_INT32_T, 0, MPI_COMM_WORLD);
    result.owner = std::move(owner);
    result.local = builder.finish();
    result.local.sceneHash = scene.geometryHash();
    result.local.provenance = backend->provenance();
    result.local.parameters = backend->parameters();
    result.local.parameters["settings"] = formFactorSettingsText(settings);  // as one process records it

    // Bookkeeping to rank 0: counts summed (the largest direct sum taken), stage times, per-rank load.
    const RayCounts mine = builder.counts();
    std::uint64_t integers[15] = {mine.rays,         mine.bounces,       mine.misses,
                                  mine.backfaces,    mine.rescaledRows,  mine.shadowTerms,
                                  mine.contactPairs, mine.contactShafts, mine.contactEvaluations,
                                  mine.straddlingPairs, mine.penumbralPairs, mine.coveredRows,
                                  mine.shadowProbes, mine.cutPairs, mine.cutWholePairs},
                  integerSums[15];
    double reals[4] = {mine.lostWeight, mine.cutoffWeight, mine.lostArea, mine.rowArea}, realSums[4];
    MPI_Reduce(integers, integerSums, 15, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(reals, realSums, 4, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    double largest = 0;
    MPI_Reduce(&mine.largestDirectSum, &largest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    std::uint64_t solids[2] = {mine.convexSolids, mine.solidFaces}, solidsMost[2] = {0, 0};  // the scene's: the largest
    MPI_Reduce(solids, solidsMost, 2, MPI_UINT64_T, MPI_MAX, 0, MPI_COMM_WORLD);
    MPI_Reduce(&prepareSeconds, &result.prepareSeconds, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    std::uint64_t rowsHere = builder.rowsDone();
    result.rowsPerRank.resize(context.root() ? std::size_t(K) : 0);
    result.busySeconds.resize(result.rowsPerRank.size());
    MPI_Gather(&rowsHere, 1, MPI_UINT64_T, result.rowsPerRank.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    MPI_Gather(&worker->busySeconds, 1, MPI_DOUBLE, result.busySeconds.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    std::string stages;
    for (const auto& [stage, seconds] : builder.stageSeconds()) stages += stage + '\t' + std::to_string(seconds) + '\n';
    for (const std::string& text : context.gatherText(stages)) {
        std::size_t at = 0;
        while (at < text.size()) {
            const std::size_t tab = text.find('\t', at), end = text.find('\n', tab);
            result.stageSeconds[text.substr(at, tab - at)] += std::stod(text.substr(tab + 1, end - tab - 1));
            at = end + 1;
        }
    }
    if (context.root()) {
        RayCounts& c = result.counts;
        c.rays = integerSums[0], c.bounces = integerSums[1], c.misses = integerSums[2], c.backfaces = integerSums[3];
        c.rescaledRows = integerSums[4], c.shadowTerms = integerSums[5];
        c.contactPairs = integerSums[6], c.contactShafts = integerSums[7], c.contactEvaluations = integerSums[8];
        c.straddlingPairs = integerSums[9], c.penumbralPairs = integerSums[10], c.coveredRows = integerSums[11];
        c.shadowProbes = integerSums[12], c.cutPairs = integerSums[13], c.cutWholePairs = integerSums[14];
        c.lostWeight = realSums[0], c.cutoffWeight = realSums[1], c.lostArea = realSums[2], c.rowArea = realSums[3];
        c.largestDirectSum = largest;
        c.convexSolids = solidsMost[0], c.solidFaces = solidsMost[1];
    }
    result.computeSeconds = computeSeconds;
    result.rowsComputed = rows.size();
    result.device = backend->device();
    if (backend->pairsFromEmitters()) {
        const auto assembling = Clock::now();
        result.emittedPairs = takePairsFromEmittersDistributed(context, scene, result);
        result.assembleSeconds = since(assembling);
    }
    return result;
}

FormFactors gatherFormFactors(const Context& context, const DistributedFormFactors& F) {
    const std::size_t n = F.owner.size();
    std::vector<std::uint64_t> lengths(n, 0), total(context.root() ? n : 0);
    for (std::size_t i = 0; i < n; ++i)
        if (F.owner[i] == context.rank()) lengths[i] = F.local.rowEnd(i) - F.local.rowBegin(i);
    MPI_Reduce(lengths.data(), total.data(), int(n), MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    if (!context.root()) {
        sendVector(F.local.columnVector(), 0, kTagColumns);
        sendVector(F.local.valueVector(), 0, kTagValues);
        return {};
    }
    std::vector<std::uint64_t> start(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) start[i + 1] = start[i] + total[i];
    std::vector<std::uint32_t> columns(start[n]);
    std::vector<double> values(start[n]);
    std::vector<std::uint8_t> computed(n, 0);
    for (int r = 0; r < context.size(); ++r) {
        std::vector<std::uint32_t> theirColumns;
        std::vector<double> theirValues;
        if (r > 0) {
            theirColumns = receiveVector<std::uint32_t>(r, kTagColumns);
            theirValues = receiveVector<double>(r, kTagValues);
        }
        const std::uint32_t* c = r ? theirColumns.data() : F.local.columns();
        const double* v = r ? theirValues.data() : F.local.values();
        std::uint64_t at = 0;  // rows arrive in ascending order, as the rank's CSR holds them
        for (std::size_t i = 0; i < n; ++i) {
            if (F.owner[i] != r) continue;
            computed[i] = 1;
            std::copy(c + at, c + at + total[i], columns.begin() + std::ptrdiff_t(start[i]));
            std::copy(v + at, v + at + total[i], values.begin() + std::ptrdiff_t(start[i]));
            at += total[i];
        }
    }
    FormFactors all = FormFactors::fromCsr(std::move(start), std::move(columns), std::move(values), std::move(computed));
    all.sceneHash = F.local.sceneHash;
    all.provenance = F.local.provenance;
    all.parameters = F.local.parameters;
    return all;
}

DistributedFormFactors readOwnRows(const Context& context, const std::string& path, std::size_t patches, bool memoryCheck) {
    const std::size_t K = std::size_t(context.size()), rank = std::size_t(context.rank());
    // Rank r holds the rows i with i K / N = r.
    const auto firstRow = [&](std::size_t r) { return (r * patches + K - 1) / K; };
    DistributedFormFactors result;
    context.collectively([&] {
        if (formFactorFormatFor(path) == FormFactorFormat::Hff) {
            if (memoryCheck) {
                const HffRowIndex index = readHffRowIndex(path, patches);
                std::uint64_t largest = 0;  // the entries of the largest share: the same on every rank
                for (std::size_t r = 0; r < K; ++r) {
                    std::uint64_t entries = 0;
                    for (std::size_t i = firstRow(r); i < firstRow(r + 1); ++i) entries += index.lengths[i];
                    largest = std::max(largest, entries);
                }
                // Its entries (a column and a value each), and the row flags and starts read and kept.
                checkNodeMemory(context, path, 12.0 * double(largest) + 18.0 * double(patches),
                                "each rank a share of its rows", "run fewer ranks on each node");
            }
            result.local = loadHffRows(path, firstRow(rank), firstRow(rank + 1), patches);
        } else {
            std::error_code unknown;
            const auto bytes = std::filesystem::file_size(path, unknown);
            if (memoryCheck && !unknown)
                checkNodeMemory(context, path, 2.0 * double(bytes),
                                "each rank reads the whole text and all its entries: about twice the file's size",
                                "store F as .hff, whose rows each rank reads alone, or run fewer ranks on each node");
            result.local = keepRows(loadFormFactors(path, patches), firstRow(rank), firstRow(rank + 1));
        }
    });
    // Every rank learns which rank holds each row that the file has.
    std::vector<std::int32_t> mine(patches);
    for (std::size_t i = 0; i < patches; ++i) mine[i] = result.local.rowComputed(i) ? context.rank() : -1;
    result.owner.resize(patches);
    checkMpi(MPI_Allreduce(mine.data(), result.owner.data(), int(patches), MPI_INT32_T, MPI_MAX, MPI_COMM_WORLD),
             "sharing the rows' owners");
    return result;
}

FormFactorStats distributedRowStats(const Context& context, const DistributedFormFactors& F) {
    double sumMin = INFINITY, sumMax = 0, sum = 0;
    std::uint64_t counts[3] = {0, F.local.nonZeros(), 0};  // computed rows, nonzeros, rows with F_ii > 0
    for (std::size_t i = 0; i < F.owner.size(); ++i) {
        if (F.owner[i] != context.rank()) continue;
        const double s = F.local.rowSum(i);
        sumMin = std::min(sumMin, s), sumMax = std::max(sumMax, s), sum += s;
        ++counts[0];
        if (F.local.at(i, i) > 0) ++counts[2];
    }
    FormFactorStats stats;
    std::uint64_t totals[3];
    MPI_Reduce(counts, totals, 3, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Reduce(&sumMin, &stats.rowSumMin, 1, MPI_DOUBLE, MPI_MIN, 0, MPI_COMM_WORLD);
    MPI_Reduce(&sumMax, &stats.rowSumMax, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
    MPI_Reduce(&sum, &stats.rowSumMean, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    stats.rows = F.owner.size();
    stats.computedRows = totals[0], stats.nonZeros = totals[1], stats.selfFactors = totals[2];
    if (stats.computedRows) stats.rowSumMean /= double(stats.computedRows);
    else stats.rowSumMin = 0;
    return stats;
}

}  // namespace hemirad::mpi
