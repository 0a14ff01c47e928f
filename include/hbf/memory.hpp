// hbfriction — the process's allocator, for long continuations at many harmonics.
//
// Every correction hands Ceres a fresh solve: Ceres builds its evaluator, Jacobian and
// normal matrix anew on each ceres::Solve (its API offers no reuse across solves), and at
// H = 49 these blocks are ~300 KB each. glibc serves blocks above its mmap threshold by
// mmap, or grows the heap and trims it again on free, so the pages are faulted in afresh on
// every correction: measured on the absorber (exact Coulomb, H = 49, N_t = 2048, 623 branch
// points), 445,000 page faults, 3.1 s of kernel time and 8.6 s in all, against 2,400 faults
// and 2.5 s with the blocks kept (benchmarks/hb_branch prints both). The library's own
// buffers (the HB Jacobian, the AFT scratch, the Ceres problem) are allocated once per
// HarmonicBalance / Corrector and reused.
#pragma once

namespace hbf {

/// Makes glibc keep freed memory for reuse instead of returning it to the system: blocks up to
/// 32 MB come from the heap (glibc's largest mmap threshold), the heap top is trimmed only above
/// 512 MB free,
/// and it grows in 64 MB steps. Process-wide (mallopt) and idempotent; the `hbf` command calls
/// it at start. The price: up to ~0.5 GB of freed heap may stay mapped to the process. Returns
/// false, doing nothing, where the C library is not glibc.
bool retain_freed_memory();

}  // namespace hbf
