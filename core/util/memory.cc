#include "core/util/memory.h"

#include <climits>  // also defines __GLIBC__ where glibc is the C library

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace sylva {

void KeepFreedMemoryForReuse() {
#ifdef __GLIBC__
  // M_MMAP_THRESHOLD's largest value on 64-bit systems: 4 x 1 MiB x sizeof(long).
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

}  // namespace sylva
