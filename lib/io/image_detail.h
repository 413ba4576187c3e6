// Inside lib/io's EXR reading and writing (not a public header).
#pragma once

#include <sys/mman.h>

#include <cstdint>
#include <string>
#include <vector>

namespace isg::io::detail {

inline std::string first_line(std::string s) {
  auto nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

// Reserves `n` elements of fresh memory for a plane, faulted in up front. First touch of new
// memory costs a page fault per 4 KiB, which (on virtual machines especially) is a good part of
// reading or writing a frame: one madvise call populates the pages, in 2 MiB pages where the
// kernel allows. Both are hints; without them the pages fault in as usual.
template <class T>
inline void reserve_fresh(std::vector<T>& v, size_t n) {
  v.reserve(n);
  const uintptr_t page = 4096, huge = uintptr_t(2) << 20;
  const uintptr_t b = uintptr_t(v.data()), e = uintptr_t(v.data() + n);
  // Rounded inwards: the hints must not reach memory the vector does not own.
  const uintptr_t hb = (b + huge - 1) & ~(huge - 1), he = e & ~(huge - 1);
  if (he > hb) ::madvise(reinterpret_cast<void*>(hb), he - hb, MADV_HUGEPAGE);
  const uintptr_t pb = (b + page - 1) & ~(page - 1), pe = e & ~(page - 1);
  if (pe > pb) ::madvise(reinterpret_cast<void*>(pb), pe - pb, MADV_POPULATE_WRITE);
}

}  // namespace isg::io::detail
