// A doorbell for the requests of a remote session on one host (issue 16 §3, §6): the request and
// its reply pass through a shared-memory segment and each side is woken by a futex on a counter
// there, instead of through ZeroMQ, whose round trip (the caller's thread, an I/O thread in each
// process, a unix socket) cost 0.13–0.30 ms on a 2-vCPU virtual machine against 2.5–15 µs for a
// futex hand-over that spins briefly first (docs/performance.md, "Coupling exchange").
//
// The ZeroMQ connection stays: it opens the session, carries what does not fit the channel (a
// whole state, the close) and tells either side when the other is gone. One request at a time
// (the C ABI serialises calls on a handle), so one counter per direction is enough: the client
// bumps `doorbell` when a request is in the channel (or on the socket: `socket_posted` says how
// many went that way) and the server bumps `answer` when the reply is in.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "api/shared_memory.h"

namespace quarry::api {

class Channel {
 public:
  // Bytes each way: a request's fields and its arrays under 4 KiB (larger ones are in the
  // session's segment), a reply's likewise; more goes over the socket.
  static constexpr std::uint64_t kCapacity = 256 * 1024;
  // How long a side spins before it sleeps on the futex: a reply of a short call, or the next
  // call of a partner's exchange, usually comes sooner.
  static constexpr std::chrono::microseconds kSpin{100};
  // The longest either side waits in the channel before it looks at the ZeroMQ connection
  // again (a peer gone, another client, a call that goes over the socket).
  static constexpr std::chrono::milliseconds kWatchSlice{20};

  // The client's: a new segment. Throws std::runtime_error (no shared memory).
  static std::unique_ptr<Channel> create();
  // The server's: the client's segment by name (removed at once, as SharedSegment::attach).
  // Throws std::runtime_error naming what is wrong (not a channel, another layout).
  static std::unique_ptr<Channel> attach(const std::string& name);

  const std::string& name() const { return segment_->name(); }

  // Client: puts a request (≤ kCapacity bytes) in and rings.
  void post_request(const std::string& bytes);
  // Client: rings for a request about to go over the socket.
  void post_socket_request();
  // Client: waits at most `budget` for the reply (spinning kSpin first); true once it is in.
  bool wait_reply(std::chrono::milliseconds budget);
  std::span<const std::byte> reply() const;

  // Server: waits at most `budget` for the doorbell (spinning `spin` first); true if it rang.
  bool wait_request(std::chrono::microseconds spin, std::chrono::milliseconds budget);
  // Server, after the doorbell rang: the request, copied out of the segment (empty when it went
  // over the socket), or a size beyond the capacity (then `oversized` is set).
  std::string take_request(bool& oversized);
  // Server: requests the client sent over the socket so far.
  std::uint64_t socket_posted() const;
  // Server: puts the reply (≤ kCapacity bytes) in and rings.
  void post_reply(const std::string& bytes);

 private:
  struct Header;
  explicit Channel(std::unique_ptr<SharedSegment> segment);
  Header& header() const;
  std::byte* area(int which) const;  // 0 requests, 1 replies
  // Copies `bytes` into that area (std::length_error beyond its capacity) and rings.
  void put(int which, const std::string& bytes);

  std::unique_ptr<SharedSegment> segment_;
  std::uint32_t seen_ = 0;      // the server's: the doorbell count it has answered
  std::uint32_t answered_ = 0;  // the client's: the replies it has taken
};

}  // namespace quarry::api
