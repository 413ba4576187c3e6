// Shared by C++ and GLSL: each pass's <pass>_io.h declares its push constants and local size
// between ISG_IO_BEGIN / ISG_IO_END, so both sides read the same layout.
#ifndef ISG_IO_H
#define ISG_IO_H
#ifdef __cplusplus
#include <cstdint>
#define ISG_IO_BEGIN \
  namespace isg::shaders { \
  using uint = std::uint32_t;
#define ISG_IO_END }
#else
#define ISG_IO_BEGIN
#define ISG_IO_END
#endif
// Contract: background where alpha is 0, or depth <= 0, or depth >= 1e9.
#define ISG_BACKGROUND_DEPTH 1e9
#endif
