// Pair terms handed from the row that computes them to the row of the pair's other patch.
#include "preprocess/hemisphere/pair_exchange.hpp"

#include <algorithm>
#include <mutex>

namespace hemirad {

PairExchange::PairExchange(std::size_t patches, std::function<bool(PatchId)> wanted)
    : m_wanted(std::move(wanted)),
      m_entries(patches),
      m_state(patches, 0),
      m_finishedAt(new std::atomic<std::uint64_t>[patches]()),
      m_stripes(new std::mutex[kStripes]) {}

std::uint64_t PairExchange::open(PatchId receiver, std::vector<Entry>& entries) {
    // The clock is read before the row closes: an emitter stamped at or before this reading had
    // appended its entry (if it had one) before the close below.
    const std::uint64_t ticket = m_clock.load(std::memory_order_acquire);
    bool complete;
    {
        std::lock_guard<std::mutex> lock(stripeOf(receiver));
        // Opened before (a row listed twice): emitters that finished since kept nothing for it.
        complete = !(m_state[receiver] & (kSkipped | kClosed));
        m_state[receiver] |= kClosed;  // nobody appends again: the list's memory leaves with it
        entries = std::move(m_entries[receiver]);
        m_entries[receiver] = {};
    }
    m_held.fetch_sub(std::int64_t(entries.size()), std::memory_order_relaxed);
    // An emitter that skipped this row (not wanted then) finished without its entry: no absence
    // can be trusted, so no emitter counts as finished.
    return complete ? ticket : 0;
}

void PairExchange::publish(PatchId emitter, const std::vector<Entry>& entries) {
    // One lock per run of receivers in the same stripe, the last one released before the next is
    // taken (two at once could deadlock with a publish going the other way). Held by a unique_lock:
    // an entry that cannot be appended (out of memory) must not leave its stripe locked for the
    // other threads, which would wait for it forever.
    std::unique_lock<std::mutex> held;
    std::size_t added = 0;
    for (const Entry& entry : entries) {
        const PatchId r = entry.patch;
        std::mutex& stripe = stripeOf(r);
        if (held.mutex() != &stripe) {
            if (held) held.unlock();
            held = std::unique_lock<std::mutex>(stripe);
        }
        if (m_state[r] & kClosed) continue;
        if (!m_wanted(r)) {  // not to be opened here (or not known to be): its list is freed
            m_state[r] |= kSkipped;
            if (!m_entries[r].empty()) {
                m_held.fetch_sub(std::int64_t(m_entries[r].size()), std::memory_order_relaxed);
                m_entries[r] = {};
            }
            continue;
        }
        m_entries[r].push_back({emitter, entry.value});
        ++added;
    }
    if (held) held.unlock();
    m_held.fetch_add(std::int64_t(added), std::memory_order_relaxed);
    const std::uint64_t tick = m_clock.fetch_add(1, std::memory_order_acq_rel) + 1;
    m_finishedAt[emitter].store(tick, std::memory_order_release);
}

std::size_t PairExchange::held() const { return std::size_t(std::max<std::int64_t>(0, m_held.load(std::memory_order_relaxed))); }

}  // namespace hemirad
