// spin_pause: the processor's hint inside a spin-wait loop (x86 PAUSE: the waiting thread gives
// the core's pipeline to its sibling thread, and the loop ends without a memory-order
// mis-speculation); nothing on other processors. The spins of WorkerThread, SharedLoop and the
// API's shared-memory channel.
#pragma once

namespace quarry {

inline void spin_pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace quarry
