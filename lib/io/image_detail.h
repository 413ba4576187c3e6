// Inside lib/io's EXR reading and writing (not a public header).
#pragma once

#include "sys/pages.h"

#include <cstdint>
#include <string>
#include <vector>

namespace isg::io::detail {

inline std::string first_line(std::string s) {
  auto nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

// Reserves `n` elements of fresh memory for a plane, faulted in up front (sys/pages.h).
template <class T>
inline void reserve_fresh(std::vector<T>& v, size_t n) {
  v.reserve(n);
  sys::fault_in(v.data(), n * sizeof(T));
}

}  // namespace isg::io::detail
