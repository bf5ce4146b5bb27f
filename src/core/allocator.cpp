// Allocation of the large arrays: their own mappings (a fixed mmap threshold) on transparent
// huge pages (a replacement of the global operator new for blocks of 2 MiB and more).
//
// Why huge pages: the particle and pair arrays of a 200k bed are some 80 MB, far beyond what
// the TLB maps with 4 KiB pages (Zen 3: 2,048 entries, 8 MB), and in a virtual machine every
// TLB miss is a two-level page walk. The crossing pairs and the surface candidates scatter
// through the whole arrays. Debian's kernels ship THP in "madvise" mode, so the blocks ask for
// them with madvise(MADV_HUGEPAGE). Measured on the settled 200k bed (2 vCPU AMD EPYC Zen 3
// under KVM, 2026-12-01, 10 interleaved pairs of 300-step runs; docs/performance.md): median
// run time 13.00 -> 11.88 s on one thread and 7.25 -> 6.79 s on two, the same peak RSS.
#include "core/allocator.h"

#include <malloc.h>
#include <sys/mman.h>

#include <cstdlib>
#include <new>

namespace quarry {

std::size_t huge_page_block_size() { return std::size_t{2} << 20; }  // a transparent huge page on x86-64

void use_mapped_large_allocations() {
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // Setting the mmap threshold also fixes the trim threshold at glibc's 128 KiB: the blocks
  // under 1 MiB that a list rebuild frees (about 1 MB at 30k particles) were handed back to
  // the system at every rebuild and faulted in, zeroed, at the next (two brk calls a
  // rebuild; the 30k pour of bench/run_flowing.sh took 102,000 page faults in its 681
  // rebuilds, 47,000 now, and its neighbour stage 6.6 -> 5.8 s on one thread). Up to 2 MiB of
  // free heap top is kept instead (the peak RSS of a 200k lattice did not change).
  mallopt(M_TRIM_THRESHOLD, 2 << 20);
}

}  // namespace quarry

// Under AddressSanitizer its own operator new stays (it checks new/delete pairing).
#if !defined(__SANITIZE_ADDRESS__)

namespace {

// A block of at least one whole huge page starts on a huge-page boundary, and its whole huge
// pages are advised; the part of the last one past the block's end keeps 4 KiB pages, so the
// resident size grows by no more than the block itself. glibc maps such a block on its own
// (the mmap threshold) and frees it with free(), as any other.
void* allocate(std::size_t size) noexcept {
  const std::size_t huge = quarry::huge_page_block_size();
  if (size < huge) return std::malloc(size == 0 ? 1 : size);
  void* block = nullptr;
  if (posix_memalign(&block, huge, size) != 0) return nullptr;
  // Advice only: where the kernel has no THP, the block simply keeps small pages.
  madvise(block, size / huge * huge, MADV_HUGEPAGE);
  return block;
}

}  // namespace

// The replaceable allocation functions ([new.delete.single]): the standard's loop over the
// new-handler, then std::bad_alloc. The array, nothrow and sized forms of the library call
// these; the aligned forms keep the library's (aligned_alloc / free).
void* operator new(std::size_t size) {
  for (;;) {
    if (void* block = allocate(size)) return block;
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void operator delete(void* block) noexcept { std::free(block); }
void operator delete(void* block, std::size_t) noexcept { std::free(block); }

#endif
