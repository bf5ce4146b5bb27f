// `quarry serve` (issue 16 §3; EDEM's "Coupling Server"): one simulation behind a ZeroMQ REP
// socket, one client session at a time, each request answered by a LocalBackend. Bad input of
// any kind gets an error reply and the server serves on; a client that dies ends its session
// (its segment unmapped, a simulation it opened dropped) and the next one may attach.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "api/channel.h"
#include "api/local_backend.h"
#include "api/shared_memory.h"
#include "api/wire.h"

namespace quarry::api {

struct ServerOptions {
  std::string endpoint;          // ipc://PATH or tcp://HOST:PORT (port 0: any free one)
  std::string deck_path;         // opened at start; empty: each client's quarry_open decides
  std::string output_directory;  // the deck's outputs, and those of simulations clients open
                                 // without an output_directory of their own; empty: none
  int threads = 0;  // > 0: OpenMP threads (a client's own value wins for what it opens)
  const std::atomic<int>* stop = nullptr;       // non-zero (a signal number): stop serving
  std::function<void(const std::string&)> log;  // one line per event (session attached, ended)
};

// The requests' logic without the socket: what `serve` runs, and what the tests feed directly.
class Server {
 public:
  // Opens the deck if one is given (throws what quarry_open would: UserError, PhysicsError...).
  explicit Server(ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // The reply to one request; never throws. `connection` names the connection it came on (the
  // session is bound to it; −1: unknown).
  std::string handle(const std::byte* request, std::size_t size, int connection);
  // A connection closed: the session on it, if any, ends.
  void connection_closed(int connection);
  bool attached() const { return session_.has_value(); }
  // The connection the session is bound to (−1: none, or unknown).
  int session_connection() const { return session_ ? session_->connection : -1; }
  // The endpoint quoted in messages (set by serve once bound).
  void set_endpoint(const std::string& endpoint) { endpoint_ = endpoint; }

  // The session's request channel (api/channel.h), when its client attached one.
  bool has_channel() const { return session_ && session_->channel; }
  // Waits for the channel's doorbell (spinning `spin` first) at most `budget`; answers a request
  // that came through it and returns true. False when nothing came, or the doorbell rang for a
  // request on the socket.
  bool serve_channel(std::chrono::microseconds spin, std::chrono::milliseconds budget);
  // True while the session's client has sent more requests over the socket than came in.
  bool socket_request_due() const;
  // Counts a request that came over the socket for the session (socket_request_due).
  void count_socket_request(const std::byte* request, std::size_t size);
  // Takes the socket's requests announced so far as come (one waited for in vain).
  void settle_socket_requests();

 private:
  struct Session {
    std::uint64_t token = 0;   // the requests' session field
    std::uint64_t number = 0;  // 1, 2, ... for the log
    int connection = -1;
    std::int64_t client_pid = 0;
    std::unique_ptr<SharedSegment> segment;
    wire::OutputSlots outputs;  // what replies carry back, kept between requests
    // The client's segments its views are written into, by (op << 32 | field or property).
    std::map<std::uint64_t, std::unique_ptr<SharedSegment>> views;
    std::unique_ptr<Channel> channel;   // requests by shared memory (Op::attach_channel)
    std::uint64_t socket_requests = 0;  // came over the socket since the channel was attached
  };
  std::string open(const wire::RequestHeader& header, wire::Reader& in, int connection);
  std::string call(const wire::RequestHeader& header, const std::byte* request, std::size_t size);
  // Op::view_particles_shared / view_property_shared: u32 field or property index, the name of
  // the client's segment for that view; the reply: the view's fields, u64 the bytes its values
  // take, u8 1 if they were written at the segment's start (0: it is too small; the client makes
  // a larger one and asks again).
  void shared_view(wire::Op op, wire::Reader& in, wire::Writer& out);
  // The client's values of the next step's loads, from the segments of its shared views of them.
  void put_shared_loads(wire::Reader& in);
  void end_session(const std::string& reason);
  Backend& backend();
  void log(const std::string& line) const;

  ServerOptions options_;
  std::string endpoint_;
  std::unique_ptr<LocalBackend> deck_;    // the command line's simulation: kept across sessions
  std::unique_ptr<LocalBackend> opened_;  // the session's own: dropped when it ends
  std::optional<Session> session_;
  std::uint64_t sessions_ = 0;
};

// Binds options.endpoint and serves until *options.stop is set, then ends the session, closes
// the simulation (its outputs finished) and removes an ipc socket file it made. Calls
// on_listening(the bound endpoint) once it accepts clients. Throws std::runtime_error when it
// cannot bind, and what Server's constructor throws.
void serve(const ServerOptions& options,
           const std::function<void(const std::string&)>& on_listening);

// The handler of one operation (api/server_calls.cpp): reads the request's fields from `in`
// (all of them: it ends with in.expect_end()), calls the backend, writes the results to `out`.
// Throws wire::WireError for a malformed request (lengths that do not match included).
using CallHandler = void (*)(Backend& backend, wire::Reader& in, wire::Writer& out);
CallHandler call_handler(wire::Op op);

// A view's values packed (count × components, no stride) into `to`, which holds view_bytes.
std::uint64_t view_bytes(const quarry_view& view);
void copy_view(const quarry_view& view, std::byte* to);
// A client's copy of the next step's loads of `field` (count particles, 3 doubles each, packed)
// written into the engine's, as an in-process caller writes through the view; WRONG_STATE if
// count is not the simulation's particle count.
void write_next_step_loads(Backend& backend, std::int32_t field, const void* values, std::uint64_t count);

}  // namespace quarry::api
