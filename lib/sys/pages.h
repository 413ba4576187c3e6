// Page hints for large fresh allocations (header only). First touch of new memory costs a page
// fault per 4 KiB; a plane about to be filled is faulted in by one call (MADV_POPULATE_WRITE),
// a hint: where the kernel refuses, the pages fault in as usual.
// No 2 MiB pages (MADV_HUGEPAGE): on the lavapipe machines here (Firecracker VMs, transparent
// huge pages in madvise mode with defrag on madvise) they made the first touch 4.5x slower
// (256 MiB: 1.06 s against 0.23 s), and `isg run` at 1080p 1.1 s slower (read 1.2 -> 0.75 s,
// upload of the plan's buffers 1.14 -> 0.27 s) with no gain in the passes (issue 18).
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>

namespace isg::sys {

inline void fault_in(void* data, size_t bytes) {
  const uintptr_t page = 4096;
  const uintptr_t b = uintptr_t(data), e = b + bytes;
  // Rounded inwards: the hint must not reach memory the caller does not own.
  const uintptr_t pb = (b + page - 1) & ~(page - 1), pe = e & ~(page - 1);
  if (pe > pb) ::madvise(reinterpret_cast<void*>(pb), pe - pb, MADV_POPULATE_WRITE);
}

}  // namespace isg::sys
