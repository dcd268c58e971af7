// Test-only out-of-memory: the test binary replaces the global operator new (allocation_failure.cpp),
// so that a test can make one allocation of its own thread throw std::bad_alloc and count the blocks
// still alive, to check what an out-of-memory leaves behind (leaks, std::terminate).
#pragma once

#include "engine/error.hpp"

#include <cstdint>
#include <new>
#include <stdexcept>

namespace hemirad::test {

/// While alive, the n-th operator new (any form) of the thread that made it throws std::bad_alloc
/// (n = 1: the next one); the other allocations of that thread, and every allocation of other
/// threads, succeed. `spare` (optional) names a loaded library (a part of its file name, e.g.
/// "libembree3") whose code's own calls to operator new are neither counted nor failed. Unarmed,
/// operator new is malloc plus a thread-local test, so other tests run as before. Make and destroy
/// it on one thread, and put no doctest assertion inside its lifetime (assertions allocate, and one
/// could be the n-th). Throws std::runtime_error when no loaded library matches `spare`.
class FailingAllocation {
public:
    explicit FailingAllocation(std::uint64_t n, const char* spare = nullptr);
    ~FailingAllocation();
    FailingAllocation(const FailingAllocation&) = delete;
    FailingAllocation& operator=(const FailingAllocation&) = delete;

    /// Whether the n-th allocation came (and threw).
    bool fired() const;
};

/// Blocks from operator new not yet deleted, all threads together (a leak check where
/// LeakSanitizer is not there; other threads' allocations count too).
std::int64_t liveAllocations();

/// How runs of some work ended with one of their allocations failing (failEachAllocation).
struct FailureSweep {
    std::uint64_t failures = 0;     ///< runs whose n-th allocation failed (n = 1 .. failures)
    std::uint64_t errors = 0;       ///< of those, runs that threw hemirad::Error
    std::uint64_t outOfMemory = 0;  ///< std::bad_alloc
    std::uint64_t others = 0;       ///< another exception
    std::uint64_t absorbed = 0;     ///< none: the work handled the failure itself
};

/// Runs `work` with its n-th allocation on this thread failing (FailingAllocation, `spare` as there),
/// for n = 1, 2, ... until a run makes fewer than n allocations, and then `unarmed` (cleanup that
/// must not fail, e.g. a destructor that allocates) after each run. A failure that ends in
/// std::terminate aborts the test binary, which fails the test. Throws std::runtime_error past
/// `limit` runs.
template <class Work, class Unarmed>
FailureSweep failEachAllocation(Work&& work, Unarmed&& unarmed, const char* spare = nullptr,
                                std::uint64_t limit = 1000000) {
    FailureSweep sweep;
    for (std::uint64_t n = 1;; ++n) {
        if (n > limit) throw std::runtime_error("failEachAllocation: more than the limit of allocations");
        enum class Outcome { Done, Error, OutOfMemory, Other } outcome = Outcome::Done;
        bool fired = false;
        {
            FailingAllocation failing(n, spare);
            try {
                work();
            } catch (const hemirad::Error&) {
                outcome = Outcome::Error;
            } catch (const std::bad_alloc&) {
                outcome = Outcome::OutOfMemory;
            } catch (...) {
                outcome = Outcome::Other;
            }
            fired = failing.fired();
        }
        unarmed();
        if (!fired) return sweep;
        ++sweep.failures;
        sweep.errors += outcome == Outcome::Error;
        sweep.outOfMemory += outcome == Outcome::OutOfMemory;
        sweep.others += outcome == Outcome::Other;
        sweep.absorbed += outcome == Outcome::Done;
    }
}

template <class Work>
FailureSweep failEachAllocation(Work&& work) {
    return failEachAllocation(work, [] {});
}

}  // namespace hemirad::test
