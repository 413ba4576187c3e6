// isg-exrcheck FILE X0 Y0 WIDTH HEIGHT PART NAME [PART NAME]...
// Decodes the named channels of an EXR with OpenEXR into the shared memory region `isg` passes
// as fd 3 (one plane of WIDTH * HEIGHT 4-byte values per channel, in the order given), in a
// process of its own so that a file that crashes, hangs or exhausts the library cannot take isg
// down with it. A separate executable rather than a bare fork: OpenEXR's thread pools do not
// survive fork. Exit 0: decoded; 1: damaged (the reason on stderr); 2: usage or the shared
// memory; 3: out of memory.
#include <malloc.h>
#include <sys/mman.h>
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "io/exr_decode.h"

namespace {

int number(const char* s) {
  char* end = nullptr;
  long v = std::strtol(s, &end, 10);
  if (*s == 0 || *end != 0 || v < -(1L << 30) || v > (1L << 30)) throw std::invalid_argument(s);
  return int(v);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 8 || (argc - 6) % 2 != 0) {
    std::fprintf(stderr, "usage: isg-exrcheck FILE X0 Y0 WIDTH HEIGHT PART NAME [PART NAME]...\n");
    return 2;
  }
  // Each decoding thread would get a malloc arena reserving 64 MiB of address space, which
  // counts against the memory limit isg sets; two arenas serve the pool as well.
  mallopt(M_ARENA_MAX, 2);
  isg::io::ExrDecodeRequest req;
  try {
    req.x0 = number(argv[2]);
    req.y0 = number(argv[3]);
    req.width = number(argv[4]);
    req.height = number(argv[5]);
    for (int a = 6; a + 1 < argc; a += 2) req.planes.push_back({number(argv[a]), argv[a + 1]});
  } catch (const std::exception&) {
    std::fprintf(stderr, "bad arguments\n");
    return 2;
  }
  const size_t plane_bytes = req.pixels() * 4;
  const size_t bytes = plane_bytes * req.planes.size();
  struct stat st {};
  if (req.width <= 0 || req.height <= 0 || ::fstat(3, &st) != 0 || uint64_t(st.st_size) != bytes) {
    std::fprintf(stderr, "the shared memory (fd 3) does not fit the request\n");
    return 2;
  }
  // Populated up front: one pass over the pages costs far less than a fault per page.
  void* mem = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_POPULATE, 3, 0);
  if (mem == MAP_FAILED) {
    std::fprintf(stderr, "cannot map the shared memory\n");
    return 3;
  }
  char* base = static_cast<char*>(mem);
  try {
    isg::io::decode_exr_planes(argv[1], req, [&](size_t i) { return base + i * plane_bytes; });
    return 0;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "out of memory\n");
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  } catch (...) {
    return 1;
  }
}
