// An allocator for the arrays rays walk at random (BVH nodes, packed triangles): blocks of 2 MB
// and more are aligned to 2 MB and marked for transparent huge pages, so a walk over a large
// mesh misses the TLB far less often (Embree does the same). Smaller blocks, and systems
// without madvise, get ordinary memory.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace rt {

void* huge_page_allocate(std::size_t bytes, std::size_t align);
void huge_page_free(void* p, std::size_t bytes, std::size_t align) noexcept;

template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) {
#if defined(__cpp_exceptions)
            throw std::bad_array_new_length();
#else  // the web build's SIMD kernels (core/CMakeLists.txt)
            std::abort();
#endif
        }
        return static_cast<T*>(huge_page_allocate(n * sizeof(T), alignof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { huge_page_free(p, n * sizeof(T), alignof(T)); }
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace rt
