// Pair terms handed from the row that computes them to the row of the pair's other patch.
#pragma once

#include "engine/emitted_pairs.hpp"
#include "engine/scene.hpp"

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace hemirad {

/// Row e's terms for receiver r, in `unit`s per unit of F_er, as the entry F_re that row r takes
/// (A_e F_er / A_r).
inline double handOver(const Scene& scene, double terms, PatchId e, PatchId r, double unit) {
    return terms * (scene.patches[e].area / scene.patches[r].area) / unit;
}

/// The analytic estimator computes a pair (e, r) from the points of its emitting patch e (the
/// smaller one). Row e publishes, per receiver r, what row r needs of the pair: F_re from the
/// pair's terms before row e's silhouette split, 0 for a pair hidden from every point. Row r takes
/// it instead of recomputing the pair when row e had finished before row r opened; otherwise (row e
/// in flight on another thread, on another MPI rank, or later in the row order) row r recomputes it
/// from the same points and shadow rays, equal bit for bit, so F does not depend on which rows
/// finished first. Each pair's work is then done once wherever the emitting row comes first.
///
///     emitter e: publish(e, entries) -> each appended to its open receiver's list, then e is
///                stamped with the next tick of a clock
///     receiver r: open(r) -> ticket = the clock's reading, r closed, its list moved out;
///                an emitter absent from the list had no term for r iff finished(e, ticket)
///
/// Entries go only to rows the source says it may still hand out (an MPI rank: rows pushed to it
/// and rows past its latest block, not granted yet); a row that some emitter skipped (one that
/// went to another rank, whose list is then freed, or a source that could not tell) gets ticket 0:
/// every absent pair is recomputed.
///
/// An entry takes 12 bytes (F's own size per nonzero; up to twice that with a list's growth); a
/// row's entries wait from its first emitter's end to its own start (on an MPI rank, entries for a
/// row that went to another rank wait until an emitter publishes for it again, or the end). Thread-safe: rows on any
/// threads, each row published once; a row opened again gets ticket 0.
class PairExchange {
public:
    struct __attribute__((packed, aligned(4))) Entry {  // 12 bytes, as an entry of F
        PatchId patch;  ///< the pair's other patch: the receiver in publish(), the emitter in open()
        double value;   ///< F_re as row e computed it (direct pairs: before its silhouette split, 0 when
                        ///< hidden from every point; image pairs: their sum, only when positive)
    };
    /// `patches` rows; entries are kept only for receivers `wanted` says may still be opened here.
    PairExchange(std::size_t patches, std::function<bool(PatchId)> wanted);
    /// Closes row `receiver` to further entries and moves its entries into `entries`; returns the
    /// ticket for finished() (0 when an emitter skipped the row).
    std::uint64_t open(PatchId receiver, std::vector<Entry>& entries);
    /// Whether row `emitter` had published all its entries before the row holding `ticket` opened.
    bool finished(PatchId emitter, std::uint64_t ticket) const {
        const std::uint64_t stamp = m_finishedAt[emitter].load(std::memory_order_acquire);
        return stamp != 0 && stamp <= ticket;
    }
    /// Row `emitter`'s entries, one per receiver (mostly ascending: runs share a lock).
    void publish(PatchId emitter, const std::vector<Entry>& entries);
    /// Entries held now (for tests; momentarily low while a row opens during a publish).
    std::size_t held() const;

private:
    std::mutex& stripeOf(PatchId receiver) const { return m_stripes[receiver >> kStripeShift & (kStripes - 1)]; }
    static constexpr unsigned kStripeShift = 6;  ///< 64 consecutive rows share a lock
    static constexpr std::size_t kStripes = 256;

    std::function<bool(PatchId)> m_wanted;
    std::vector<std::vector<Entry>> m_entries;  ///< per receiver, guarded by its stripe
    enum : std::uint8_t { kClosed = 1, kSkipped = 2 };
    std::vector<std::uint8_t> m_state;          ///< per receiver, guarded by its stripe
    std::unique_ptr<std::atomic<std::uint64_t>[]> m_finishedAt;  ///< per emitter: its tick, 0 = not finished
    std::atomic<std::uint64_t> m_clock{0};
    std::atomic<std::int64_t> m_held{0};  ///< signed: a row may take entries before their publish counts them
    mutable std::unique_ptr<std::mutex[]> m_stripes;
};

}  // namespace hemirad
