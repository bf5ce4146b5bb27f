// Tests for the program's operator new (core/allocator.cpp): large blocks on a huge-page
// boundary and advised for transparent huge pages, small ones as before, usable and freed.
#include "core/allocator.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <memory>
#include <new>
#include <sstream>
#include <string>
#include <vector>

namespace quarry {

namespace {

// The VmFlags line of the mapping of /proc/self/smaps that holds `address`; "" if none.
std::string vm_flags_of(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= at && at < hi;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

bool kernel_has_thp() { return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good(); }

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kOwnOperatorNew = false;  // the sanitizer's stays (allocator.cpp)
#else
constexpr bool kOwnOperatorNew = true;
#endif

}  // namespace

TEST(Allocator, LargeVectorStartsOnAHugePageAndIsAdvised) {
  if (!kOwnOperatorNew) GTEST_SKIP() << "AddressSanitizer keeps its own operator new";
  use_mapped_large_allocations();
  const std::size_t huge = huge_page_block_size();
  EXPECT_EQ(huge, std::size_t{2} << 20);
  std::vector<double> values(5 * huge / sizeof(double) + 123, 1.5);  // 5 huge pages and a bit
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(values.data()) % huge, 0u);
  double sum = 0.0;
  for (double v : values) sum += v;
  EXPECT_EQ(sum, 1.5 * static_cast<double>(values.size()));
  // madvise(MADV_HUGEPAGE) marks the mapping "hg", whatever the system-wide THP mode.
  if (kernel_has_thp()) {
    EXPECT_NE(vm_flags_of(values.data()).find(" hg"), std::string::npos) << vm_flags_of(values.data());
  }
}

TEST(Allocator, SmallBlocksAreOrdinaryAndNotAdvised) {
  if (!kOwnOperatorNew) GTEST_SKIP() << "AddressSanitizer keeps its own operator new";
  auto small = std::make_unique<char[]>(1000);
  small[999] = 'x';
  EXPECT_EQ(small[999], 'x');
  // A block just under one huge page keeps small pages: no advice, no over-alignment.
  std::vector<char> below(huge_page_block_size() - 64, 'y');
  if (kernel_has_thp()) {
    EXPECT_EQ(vm_flags_of(below.data()).find(" hg"), std::string::npos) << vm_flags_of(below.data());
  }
}

TEST(Allocator, ImpossibleRequestThrowsBadAlloc) {
  if (!kOwnOperatorNew) GTEST_SKIP() << "AddressSanitizer aborts on such a request by default";
  // More than the address space: the new-handler loop ends in std::bad_alloc, not nullptr.
  const std::size_t impossible = std::size_t{1} << 62;
  EXPECT_THROW(
      {
        void* block = ::operator new(impossible);
        ::operator delete(block);
      },
      std::bad_alloc);
}

}  // namespace quarry
