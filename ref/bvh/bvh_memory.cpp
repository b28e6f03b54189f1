// Raw memory for the traversal arrays (bvh.h: bvh_allocate, bvh_deallocate, used by
// BvhAllocator for Bvh::wide_nodes and Bvh::triangle_blocks): an allocation of 2 MiB or more is
// aligned to 2 MiB and, on Linux, marked for transparent huge pages (madvise MADV_HUGEPAGE).
// docs/bvh.md, "Memory" under "Build". Memory placement only: no result depends on it.
#include "ref/bvh/bvh.h"

#include <algorithm>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace fovref {

namespace {
constexpr std::size_t huge_page = std::size_t{2} << 20;
}

void* bvh_allocate(std::size_t bytes, std::size_t alignment) {
    if (bytes < huge_page)
        return ::operator new (bytes, std::align_val_t{std::max(alignment, alignof(void*))});
    const std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
    void* p = ::operator new (rounded, std::align_val_t{huge_page});
#if defined(__linux__)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: failure (no THP support) changes nothing
#endif
    return p;
}

void bvh_deallocate(void* p, std::size_t bytes, std::size_t alignment) {
    if (bytes < huge_page)
        ::operator delete (p, std::align_val_t{std::max(alignment, alignof(void*))});
    else
        ::operator delete (p, std::align_val_t{huge_page});
}

}  // namespace fovref
