#include "core/memory.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace hw {

void fixMallocMmapThreshold() {
#if defined(__GLIBC__)
  if (!std::getenv("MALLOC_MMAP_THRESHOLD_")) mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  if (!std::getenv("MALLOC_TOP_PAD_")) mallopt(M_TOP_PAD, 4 * 1024 * 1024);
#endif
}

void returnFreeHeapPages() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

long long residentKiB() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return -1;
  long long sizePages = 0, residentPages = 0;
  const int n = std::fscanf(f, "%lld %lld", &sizePages, &residentPages);
  std::fclose(f);
  const long page = sysconf(_SC_PAGESIZE);
  if (n != 2 || page <= 0) return -1;
  return residentPages * (page / 1024);
}

}  // namespace hw
