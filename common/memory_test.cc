#include "common/memory.h"

#include <malloc.h>

#include <cstring>
#include <memory>

#include <gtest/gtest.h>

namespace {

// A 64 MB block (above glibc's largest mmap threshold) comes from the heap, not from a mapping of
// its own, and freeing it leaves the memory with the process for the next one.
TEST(KeepFreedMemory, LargeBlocksComeFromTheHeapAndStayThereWhenFreed) {
  ttz::KeepFreedMemory();
  constexpr size_t kBytes = size_t{64} << 20;
  const size_t mapped_before = mallinfo2().hblkhd;
  auto block = std::make_unique<char[]>(kBytes);
  std::memset(block.get(), 1, kBytes);
  EXPECT_LT(mallinfo2().hblkhd, mapped_before + kBytes);
  const size_t heap_with_block = mallinfo2().arena;
  EXPECT_GE(heap_with_block, kBytes);
  block.reset();
  EXPECT_EQ(mallinfo2().arena, heap_with_block);  // not trimmed: kept for reuse
  EXPECT_GE(mallinfo2().fordblks, kBytes);       // and free in the heap
}

}  // namespace
