#include "common/memory.h"

#include <malloc.h>

#include <climits>

namespace ttz {

void KeepFreedMemory() {
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, INT_MAX);
}

}  // namespace ttz
