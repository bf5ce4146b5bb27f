// Four doubles at a time with GCC's vector extension (AVX2 in the release build, SSE2 pairs in
// a baseline one): the types and the unaligned loads that the four-lane passes share
// (sim/particle_lanes.h, neighbor/pair_list.cpp). Internal linkage: include only from .cpp
// files or from headers of the same kind.
#pragma once

#include <cstdint>

// The vector types only cross inlined functions, so the note that their ABI differs without
// AVX does not concern any caller (GCC gives it at the end of the including file, so it stays
// off there).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace quarry {
namespace {

typedef double Lanes __attribute__((vector_size(32)));       // one value of four items
typedef std::int64_t Mask __attribute__((vector_size(32)));  // a comparison's lanes: 0 or -1

// The same four doubles read or written where they lie (8-byte aligned, any type): one vector
// move each. (A memcpy into a local went through the stack in pieces that the vector load then
// could not take from the store buffer: the pass ran slower than the scalar one.)
typedef double UnalignedLanes __attribute__((vector_size(32), aligned(8), may_alias));
typedef std::int64_t UnalignedMask __attribute__((vector_size(32), aligned(8), may_alias));

[[gnu::always_inline]] inline Lanes load_lanes(const double* s) {
  return *reinterpret_cast<const UnalignedLanes*>(s);
}
[[gnu::always_inline]] inline Mask load_mask(const std::uint64_t* s) {
  return *reinterpret_cast<const UnalignedMask*>(s);
}

}  // namespace
}  // namespace quarry
