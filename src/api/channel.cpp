// The request doorbell of a remote session (api/channel.h): a header of counters and sizes, then
// a request area and a reply area, in one shared-memory segment; Linux futexes on the counters.
#include "api/channel.h"

#include <fmt/format.h>
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "core/spin_pause.h"

namespace quarry::api {

namespace {

constexpr std::uint32_t kMagic = 0x4e484351;  // "QCHN"
constexpr std::uint32_t kLayout = 1;

// Process-shared futexes (the segment is mapped in two processes: no FUTEX_PRIVATE_FLAG).
void futex_wait(std::atomic<std::uint32_t>& word, std::uint32_t expected,
                std::chrono::milliseconds budget) {
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(budget);
  timespec timeout{static_cast<std::time_t>(seconds.count()),
                   static_cast<long>((budget - seconds).count() * 1000000)};
  ::syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAIT, expected, &timeout,
            nullptr, 0);
}

void futex_wake(std::atomic<std::uint32_t>& word) {
  ::syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAKE, 1, nullptr, nullptr,
            0);
}

// Waits until `word` differs from `seen` (spinning `spin` first, then asleep with `sleeping` set
// so that the other side wakes it), at most `budget` in all; the value it found.
std::uint32_t wait_change(std::atomic<std::uint32_t>& word, std::uint32_t seen,
                          std::atomic<std::uint32_t>& sleeping, std::chrono::microseconds spin,
                          std::chrono::milliseconds budget) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  for (unsigned k = 0;; ++k) {
    const std::uint32_t now = word.load(std::memory_order_acquire);
    if (now != seen) return now;
    if (k % 64 == 63 && Clock::now() - start >= spin) break;
    spin_pause();
  }
  const auto left = budget - std::chrono::duration_cast<std::chrono::milliseconds>(
                                 Clock::now() - start);
  // Announce the sleep, then look once more: the other side bumps the word before it reads
  // `sleeping` (both sequentially consistent), so one of the two sees the other.
  sleeping.store(1, std::memory_order_seq_cst);
  if (word.load(std::memory_order_seq_cst) == seen && left.count() > 0)
    futex_wait(word, seen, left);
  sleeping.store(0, std::memory_order_relaxed);
  return word.load(std::memory_order_acquire);
}

void ring(std::atomic<std::uint32_t>& word, std::atomic<std::uint32_t>& sleeping) {
  word.fetch_add(1, std::memory_order_seq_cst);
  if (sleeping.load(std::memory_order_seq_cst) != 0) futex_wake(word);
}

}  // namespace

// Written by the client: the first cache line; by the server: the second.
struct Channel::Header {
  std::uint32_t magic;
  std::uint32_t layout;
  std::uint64_t capacity;
  std::atomic<std::uint32_t> doorbell;       // requests rung (in the channel or on the socket)
  std::atomic<std::uint32_t> client_sleeps;  // 1 while the client sleeps on `answer`
  std::atomic<std::uint64_t> request_bytes;  // of the last request in the channel; 0: socket
  std::atomic<std::uint64_t> socket_posted;  // requests sent over the socket
  alignas(64) std::atomic<std::uint32_t> answer;  // replies put in the channel
  std::atomic<std::uint32_t> server_sleeps;       // 1 while the server sleeps on `doorbell`
  std::atomic<std::uint64_t> reply_bytes;
};
static_assert(std::atomic<std::uint32_t>::is_always_lock_free &&
              std::atomic<std::uint64_t>::is_always_lock_free);
static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));

namespace {
constexpr std::uint64_t kHeaderBytes = 128;
}

Channel::Channel(std::unique_ptr<SharedSegment> segment) : segment_(std::move(segment)) {}

Channel::Header& Channel::header() const {
  static_assert(sizeof(Header) <= kHeaderBytes);
  return *reinterpret_cast<Header*>(segment_->at(0));
}

std::byte* Channel::area(int which) const {
  return segment_->at(kHeaderBytes + static_cast<std::uint64_t>(which) * kCapacity);
}

std::unique_ptr<Channel> Channel::create() {
  std::unique_ptr<Channel> channel(
      new Channel(SharedSegment::create(kHeaderBytes + 2 * kCapacity)));
  Header& h = *new (channel->segment_->at(0)) Header{};  // the segment is zeroed
  h.magic = kMagic;
  h.layout = kLayout;
  h.capacity = kCapacity;
  return channel;
}

std::unique_ptr<Channel> Channel::attach(const std::string& name) {
  std::unique_ptr<SharedSegment> segment = SharedSegment::attach(name);
  if (segment->size() < kHeaderBytes + 2 * kCapacity)
    throw std::runtime_error(fmt::format("the channel {} has {} bytes, not {}", name,
                                         segment->size(), kHeaderBytes + 2 * kCapacity));
  std::unique_ptr<Channel> channel(new Channel(std::move(segment)));
  const Header& h = channel->header();
  if (h.magic != kMagic || h.layout != kLayout || h.capacity != kCapacity)
    throw std::runtime_error(fmt::format(
        "{} is not a request channel of this server's layout (magic {:#x}, layout {}, capacity "
        "{})",
        name, h.magic, h.layout, h.capacity));
  channel->seen_ = h.doorbell.load(std::memory_order_acquire);
  return channel;
}

void Channel::put(int which, const std::string& bytes) {
  if (bytes.size() > kCapacity)
    throw std::length_error(fmt::format("a {} of {} bytes in a channel of {}",
                                        which == 0 ? "request" : "reply", bytes.size(), kCapacity));
  std::memcpy(area(which), bytes.data(), bytes.size());
  Header& h = header();
  (which == 0 ? h.request_bytes : h.reply_bytes).store(bytes.size(), std::memory_order_relaxed);
  if (which == 0)
    ring(h.doorbell, h.server_sleeps);
  else
    ring(h.answer, h.client_sleeps);
}

void Channel::post_request(const std::string& bytes) {
  put(0, bytes);
}

void Channel::post_socket_request() {
  Header& h = header();
  h.request_bytes.store(0, std::memory_order_relaxed);
  h.socket_posted.fetch_add(1, std::memory_order_relaxed);
  ring(h.doorbell, h.server_sleeps);
}

bool Channel::wait_reply(std::chrono::milliseconds budget) {
  Header& h = header();
  const std::uint32_t now = wait_change(h.answer, answered_, h.client_sleeps, kSpin, budget);
  if (now == answered_) return false;
  answered_ = now;
  return true;
}

std::span<const std::byte> Channel::reply() const {
  const std::uint64_t bytes = header().reply_bytes.load(std::memory_order_relaxed);
  return {area(1), std::min(bytes, kCapacity)};
}

bool Channel::wait_request(std::chrono::microseconds spin, std::chrono::milliseconds budget) {
  Header& h = header();
  const std::uint32_t now = wait_change(h.doorbell, seen_, h.server_sleeps, spin, budget);
  if (now == seen_) return false;
  seen_ = now;
  return true;
}

std::string Channel::take_request(bool& oversized) {
  const std::uint64_t bytes = header().request_bytes.load(std::memory_order_relaxed);
  oversized = bytes > kCapacity;
  if (oversized || bytes == 0) return {};
  return std::string(reinterpret_cast<const char*>(area(0)), bytes);
}

std::uint64_t Channel::socket_posted() const {
  return header().socket_posted.load(std::memory_order_relaxed);
}

void Channel::post_reply(const std::string& bytes) {
  put(1, bytes);
}

}  // namespace quarry::api
