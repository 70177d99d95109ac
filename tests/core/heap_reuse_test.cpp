#include "core/heap_reuse.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdlib>
#include <cstring>

namespace lt {
namespace {

// AddressSanitizer replaces malloc (its own allocator quarantines freed
// blocks), so the test exists only in builds on the C library's allocator.
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
long MinorFaults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

// A frame-sized block freed and allocated again is served from the heap,
// without mapping (and faulting in) its pages anew: 64 MiB is 16 384 pages.
TEST(HeapReuse, AFreedFrameBufferComesBackWithoutPageFaults) {
  RetainFreedMemory();
  constexpr size_t kBytes = size_t(64) << 20;
  char* a = static_cast<char*>(std::malloc(kBytes));
  ASSERT_NE(a, nullptr);
  std::memset(a, 1, kBytes);
  asm volatile("" : : "r"(a) : "memory");  // the stores happen before the free
  std::free(a);
  const long before = MinorFaults();
  char* b = static_cast<char*>(std::malloc(kBytes));
  ASSERT_NE(b, nullptr);
  std::memset(b, 2, kBytes);
  asm volatile("" : : "r"(b) : "memory");
  const long faults = MinorFaults() - before;
  EXPECT_EQ(b[kBytes - 1], 2);
  std::free(b);
  EXPECT_LT(faults, 1000) << "the block's pages were faulted in again";
}
#endif

}  // namespace
}  // namespace lt
