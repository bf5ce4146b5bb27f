// Allocator settings for long runs with large arrays.
#pragma once

#include <malloc.h>

namespace quarry {

// Particle and pair arrays (megabytes to gigabytes) are freed and allocated again at every
// neighbour-list rebuild. glibc raises its mmap threshold dynamically after the first such
// free (mallopt(3), M_MMAP_THRESHOLD), after which arrays up to 32 MiB come from the heap and
// their pages are not returned to the system on free: the peak resident size then creeps up
// rebuild after rebuild. A fixed threshold keeps every allocation of 1 MiB or more in its own
// mapping, given back when freed. Call once at program start.
inline void use_mapped_large_allocations() { mallopt(M_MMAP_THRESHOLD, 1 << 20); }

}  // namespace quarry
