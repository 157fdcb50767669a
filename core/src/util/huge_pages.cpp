#include "rt/util/huge_pages.h"

#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rt {

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;

// Only where the kernel takes the hint: elsewhere (the web page's WebAssembly memory, say) the
// alignment and the rounding up would only waste memory.
#if defined(__linux__) && defined(MADV_HUGEPAGE)
constexpr bool kHugePages = true;
#else
constexpr bool kHugePages = false;
#endif

std::size_t round_up(std::size_t v, std::size_t to) { return (v + to - 1) / to * to; }

}  // namespace

void* huge_page_allocate(std::size_t bytes, std::size_t align) {
    if (kHugePages && bytes >= kHugePage) {
        // Whole huge pages: aligned_alloc needs a size that is a multiple of the alignment.
        void* p = std::aligned_alloc(kHugePage, round_up(bytes, kHugePage));
        if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        madvise(p, round_up(bytes, kHugePage), MADV_HUGEPAGE);  // a hint: failure is harmless
#endif
        return p;
    }
    return ::operator new (bytes, std::align_val_t{align});
}

void huge_page_free(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (!p) return;
    if (kHugePages && bytes >= kHugePage)
        std::free(p);
    else
        ::operator delete (p, std::align_val_t{align});
}

}  // namespace rt
