// The test binary's global operator new and delete (allocation_failure.hpp): malloc and free, a
// thread-local countdown that makes one allocation of an armed thread throw std::bad_alloc, and a
// count of live blocks. Every form is replaced (sized, aligned, nothrow) so that new and delete
// always pair up (AddressSanitizer checks that they do).
#include "allocation_failure.hpp"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#include <link.h>

namespace {

constexpr int kMaxSpared = 16;  // loadable segments of the spared library

// Per thread, trivially constructed (no TLS initialiser runs inside operator new): allocations left
// up to the failing one (0: not armed), whether it came, and the code whose own calls are spared.
thread_local std::uint64_t t_countdown = 0;
thread_local bool t_fired = false;
thread_local int t_spared = 0;
thread_local std::uintptr_t t_sparedBegin[kMaxSpared], t_sparedEnd[kMaxSpared];
std::atomic<std::int64_t> g_live{0};

bool spared(const void* caller) {
    const auto at = reinterpret_cast<std::uintptr_t>(caller);
    for (int k = 0; k < t_spared; ++k)
        if (at >= t_sparedBegin[k] && at < t_sparedEnd[k]) return true;
    return false;
}

/// `caller`: the return address of operator new, i.e. the code that asked for the block.
void* allocate(std::size_t size, std::size_t alignment, const void* caller) {
    if (t_countdown != 0 && !spared(caller) && --t_countdown == 0) {
        t_fired = true;
        throw std::bad_alloc();
    }
    if (size == 0) size = 1;  // a distinct non-null pointer for every call
    void* p = nullptr;
    if (alignment <= alignof(std::max_align_t)) p = std::malloc(size);
    else if (::posix_memalign(&p, alignment, size) != 0) p = nullptr;
    if (!p) throw std::bad_alloc();
    g_live.fetch_add(1, std::memory_order_relaxed);
    return p;
}

void* allocateNoThrow(std::size_t size, std::size_t alignment, const void* caller) noexcept {
    try {
        return allocate(size, alignment, caller);
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}

void release(void* p) noexcept {
    if (!p) return;
    g_live.fetch_sub(1, std::memory_order_relaxed);
    std::free(p);
}

constexpr std::size_t kPlain = alignof(std::max_align_t);

/// The executable segments of the loaded library whose file name contains `name`, as this thread's
/// spared ranges; false when no library matches.
bool spareLibrary(const char* name) {
    struct Search {
        const char* name;
        bool found;
    } search{name, false};
    t_spared = 0;
    ::dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void* data) {
            auto* s = static_cast<Search*>(data);
            if (!info->dlpi_name || !std::strstr(info->dlpi_name, s->name)) return 0;
            s->found = true;
            for (int h = 0; h < info->dlpi_phnum && t_spared < kMaxSpared; ++h) {
                const ElfW(Phdr)& segment = info->dlpi_phdr[h];
                if (segment.p_type != PT_LOAD || !(segment.p_flags & PF_X)) continue;
                t_sparedBegin[t_spared] = info->dlpi_addr + segment.p_vaddr;
                t_sparedEnd[t_spared] = t_sparedBegin[t_spared] + segment.p_memsz;
                ++t_spared;
            }
            return 1;
        },
        &search);
    return search.found;
}

}  // namespace

namespace hemirad::test {

FailingAllocation::FailingAllocation(std::uint64_t n, const char* spare) {
    if (spare && !spareLibrary(spare))
        throw std::runtime_error(std::string("FailingAllocation: no loaded library is named like ") + spare);
    t_fired = false;
    t_countdown = n;
}

FailingAllocation::~FailingAllocation() {
    t_countdown = 0;
    t_spared = 0;
}

bool FailingAllocation::fired() const { return t_fired; }

std::int64_t liveAllocations() { return g_live.load(std::memory_order_relaxed); }

}  // namespace hemirad::test

// Each passes its own return address: the code that called it.
#define HEMIRAD_CALLER __builtin_return_address(0)

void* operator new(std::size_t size) { return allocate(size, kPlain, HEMIRAD_CALLER); }
void* operator new[](std::size_t size) { return allocate(size, kPlain, HEMIRAD_CALLER); }
void* operator new(std::size_t size, std::align_val_t a) { return allocate(size, std::size_t(a), HEMIRAD_CALLER); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocate(size, std::size_t(a), HEMIRAD_CALLER); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocateNoThrow(size, kPlain, HEMIRAD_CALLER); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocateNoThrow(size, kPlain, HEMIRAD_CALLER); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    return allocateNoThrow(size, std::size_t(a), HEMIRAD_CALLER);
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    return allocateNoThrow(size, std::size_t(a), HEMIRAD_CALLER);
}

void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
