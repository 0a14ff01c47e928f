// hbfriction — the allocator setting for long continuations (memory.hpp).
#include "hbf/memory.hpp"

#include <cstdlib>  // defines __GLIBC__ on glibc (through features.h)

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace hbf {

bool retain_freed_memory() {
#if defined(__GLIBC__)
    // mallopt returns 1 on success; glibc caps the mmap threshold at 32 MB on 64-bit systems
    // (HEAP_MAX_SIZE / 2) and refuses more.
    return mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1 && mallopt(M_TRIM_THRESHOLD, 512 << 20) == 1 &&
           mallopt(M_TOP_PAD, 64 << 20) == 1;
#else
    return false;
#endif
}

}  // namespace hbf
