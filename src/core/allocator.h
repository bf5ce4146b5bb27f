// Allocator settings for long runs with large arrays (core/allocator.cpp).
#pragma once

#include <cstddef>

namespace quarry {

// Particle and pair arrays (megabytes to gigabytes) are freed and allocated again at every
// neighbour-list rebuild. glibc raises its mmap threshold dynamically after the first such
// free (mallopt(3), M_MMAP_THRESHOLD), after which arrays up to 32 MiB come from the heap and
// their pages are not returned to the system on free: the peak resident size then creeps up
// rebuild after rebuild. A fixed threshold keeps every allocation of 1 MiB or more in its own
// mapping, given back when freed. Call once at program start.
//
// Calling it also links this program's operator new, which puts every block of
// huge_page_block_size() bytes or more on transparent huge pages (allocator.cpp says why).
void use_mapped_large_allocations();

// Blocks from operator new of at least this many bytes (one x86-64 huge page, 2 MiB) start on
// a multiple of it and are advised for transparent huge pages.
std::size_t huge_page_block_size();

}  // namespace quarry
