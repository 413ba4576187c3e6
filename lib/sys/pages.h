// Page hints for large fresh allocations (header only; io and gpu both use it, neither knows
// the other). First touch of new memory costs a page fault per 4 KiB, which on virtual machines
// especially is a good part of filling a frame's planes: 2 MiB pages where the kernel allows
// (transparent huge pages in madvise mode, Debian's default), and optionally the pages faulted
// in by one call. Both are hints; where the kernel refuses, the pages fault in as usual.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>

namespace isg::sys {

inline void advise_fresh(void* data, size_t bytes, bool populate) {
  const uintptr_t page = 4096, huge = uintptr_t(2) << 20;
  const uintptr_t b = uintptr_t(data), e = b + bytes;
  // Rounded inwards: the hints must not reach memory the caller does not own.
  const uintptr_t hb = (b + huge - 1) & ~(huge - 1), he = e & ~(huge - 1);
  if (he > hb) ::madvise(reinterpret_cast<void*>(hb), he - hb, MADV_HUGEPAGE);
  if (!populate) return;
  const uintptr_t pb = (b + page - 1) & ~(page - 1), pe = e & ~(page - 1);
  if (pe > pb) ::madvise(reinterpret_cast<void*>(pb), pe - pb, MADV_POPULATE_WRITE);
}

}  // namespace isg::sys
