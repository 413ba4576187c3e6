// isg-exrcheck FILE: OpenEXR's own file checker (checkOpenEXRFile, reduced memory and time),
// run by `isg` in a separate process so a file that crashes or hangs the library cannot take
// isg down with it. Exit 0: the file decodes; 1: damaged; 2: usage or an exception.
#include <OpenEXR/ImfCheckFile.h>
#include <OpenEXR/ImfThreading.h>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: isg-exrcheck FILE\n");
    return 2;
  }
  try {
    Imf::setGlobalThreadCount(0);
    return Imf::checkOpenEXRFile(argv[1], /*reduceMemory=*/true, /*reduceTime=*/true) ? 1 : 0;
  } catch (const std::exception&) {
    return 2;
  }
}
