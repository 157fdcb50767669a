#include "rt/util/huge_pages.h"

#include <cstdint>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rt {

#if defined(__linux__) && defined(MADV_HUGEPAGE)
namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;

std::size_t round_up(std::size_t v, std::size_t to) { return (v + to - 1) / to * to; }

}  // namespace
#endif

// Blocks of 2 MB and more are mapped from the kernel directly and unmapped when freed, rather
// than taken from malloc: glibc raises its mmap threshold after each large free (up to 32 MB),
// so the blocks after it came from the heap, where a freed one stays in the process while later
// allocations of other sizes pass it by (the load of a 1M-triangle mesh peaked 50 MB higher).
void* huge_page_allocate(std::size_t bytes, std::size_t align) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= kHugePage) {
        // Whole huge pages at a 2 MB boundary: map one page more and unmap what is around them.
        const std::size_t size = round_up(bytes, kHugePage);
        void* m = mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) throw std::bad_alloc();
        char* const base = static_cast<char*>(m);
        char* const p =
            reinterpret_cast<char*>(round_up(reinterpret_cast<std::uintptr_t>(base), kHugePage));
        if (p > base) munmap(base, static_cast<std::size_t>(p - base));
        if (p + size < base + size + kHugePage)
            munmap(p + size, static_cast<std::size_t>(base + size + kHugePage - (p + size)));
        madvise(p, size, MADV_HUGEPAGE);  // a hint: failure is harmless
        return p;
    }
#endif
    return ::operator new (bytes, std::align_val_t{align});
}

void huge_page_free(void* p, [[maybe_unused]] std::size_t bytes, std::size_t align) noexcept {
    if (!p) return;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= kHugePage) {
        munmap(p, round_up(bytes, kHugePage));
        return;
    }
#endif
    ::operator delete (p, std::align_val_t{align});
}

}  // namespace rt
