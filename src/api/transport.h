// ZeroMQ plumbing of the remote coupling (issue 16 §3): endpoints, messages sent without a copy,
// the client's REQ socket that watches its connection (socket monitor, ZMTP heartbeats) so that
// a dead server gives an error and never a hang, and the server's REP socket that tells which
// connection a request came from and when a connection closes.
#pragma once

#include <zmq.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace quarry::api {

// What is wrong with an endpoint that is neither "ipc://PATH" nor "tcp://HOST:PORT" (empty if
// it is one); check_endpoint throws it as ApiError(BAD_VALUE) prefixed with the call.
std::string endpoint_problem(const std::string& endpoint);
void check_endpoint(const std::string& endpoint, const char* call);
bool is_ipc(const std::string& endpoint);

// ZMTP heartbeats (ms): each side pings every interval and drops a peer that answers none for
// its timeout. ZeroMQ's own I/O thread answers them, so a server busy in a long advance (or a
// client busy in its own solver) still does; a killed, stopped or unreachable process does not.
// The client gives up on its server after 5 s; the server keeps a client's session for 60 s of
// silence (a killed client's connection closes at once: the timeout is for a lost host, or a
// partner held in a debugger).
inline constexpr int kHeartbeatIntervalMs = 1000;
inline constexpr int kClientHeartbeatTimeoutMs = 5000;
inline constexpr int kServerHeartbeatTimeoutMs = 60000;

// One received ZeroMQ message (RAII over zmq_msg_t).
class Message {
 public:
  Message() { zmq_msg_init(&message_); }
  ~Message() { zmq_msg_close(&message_); }
  Message(Message&& other) noexcept;
  Message& operator=(Message&&) = delete;
  Message(const Message&) = delete;
  const std::byte* data() const {
    return static_cast<const std::byte*>(zmq_msg_data(const_cast<zmq_msg_t*>(&message_)));
  }
  std::size_t size() const { return zmq_msg_size(&message_); }
  zmq_msg_t* get() { return &message_; }
  // A message holding a copy of `bytes` (a reply that came through the request channel).
  static Message copy_of(const std::byte* bytes, std::size_t size);

 private:
  zmq_msg_t message_;
};

// Hands `bytes` to ZeroMQ without copying them (they are freed when sent). False if the
// socket refused it (errno set).
bool send_message(void* socket, std::string&& bytes, int flags = 0);

// The client's connection to one `quarry serve`. Not thread-safe (the C ABI serialises calls
// on a handle).
class ClientConnection {
 public:
  explicit ClientConnection(const std::string& endpoint);
  ~ClientConnection();
  ClientConnection(const ClientConnection&) = delete;
  ClientConnection& operator=(const ClientConnection&) = delete;

  // Sends a request and waits for its reply: at most timeout_ms, or with timeout_ms < 0 as
  // long as the connection lives. Throws ApiError: TRANSPORT when the connection is lost (or
  // was lost before), TIMEOUT when the time is up — then the socket is closed and every later
  // call fails with TRANSPORT (a late reply must not be taken for another request's).
  Message exchange(std::string&& request, int timeout_ms, const char* call);
  // The same through the request channel of a session on this host (api/channel.h): the
  // connection is still watched, so a lost server gives TRANSPORT and a slow one TIMEOUT (then
  // this connection is closed, as above).
  Message exchange(class Channel& channel, const std::string& request, int timeout_ms,
                   const char* call);
  const std::string& endpoint() const { return endpoint_; }

 private:
  // Reads the monitor's events; returns false once the connection was lost.
  bool watch_events();
  [[noreturn]] void fail(int status, const std::string& text);
  [[noreturn]] void fail_timeout(const char* call, int timeout_ms);
  // Sends with `send`, then waits with receive(ms) — the reply once it is in, else nothing — in
  // slices of at most slice_ms, watching the connection, until the reply or the call's timeout.
  template <class Send, class Receive>
  Message round_trip(int timeout_ms, const char* call, int slice_ms, Send&& send,
                     Receive&& receive);

  std::string endpoint_;
  void* context_ = nullptr;
  void* socket_ = nullptr;
  void* monitor_ = nullptr;
  bool connected_ = false;  // the connection came up at least once
  std::string dead_;        // why the connection is unusable (empty while it is fine)
};

// The server's socket. Not thread-safe.
class ServerSocket {
 public:
  // Binds; throws std::runtime_error with a hint (address in use, another server listening on
  // that ipc path, a directory that does not exist).
  explicit ServerSocket(const std::string& endpoint);
  ~ServerSocket();
  ServerSocket(const ServerSocket&) = delete;
  ServerSocket& operator=(const ServerSocket&) = delete;

  // The endpoint as bound (a tcp port given as 0 or * resolved).
  const std::string& endpoint() const { return bound_; }

  // Waits up to timeout_ms for a request; on one, fills `request` and `connection` (the file
  // descriptor it arrived on, −1 if ZeroMQ does not say) and returns true. Connections that
  // closed meanwhile are reported first through on_closed(fd).
  template <class OnClosed>
  bool receive(Message& request, int& connection, int timeout_ms, OnClosed&& on_closed) {
    for (int fd : closed_connections(timeout_ms)) on_closed(fd);
    return receive_ready(request, connection);
  }
  // Sends the reply to the request received last.
  void reply(std::string&& bytes);
  // False once the peer of connection `fd` has hung up, even if ZeroMQ has not reported it yet
  // (its I/O thread may pass on a new client's request before the old one's disconnection).
  static bool peer_alive(int fd);

 private:
  std::vector<int> closed_connections(int timeout_ms);
  // A request of more than one frame is answered here (an error) and not returned.
  bool receive_ready(Message& request, int& connection);

  std::string bound_;
  std::string ipc_path_;  // the socket file this server made (removed at close)
  void* context_ = nullptr;
  void* socket_ = nullptr;
  void* monitor_ = nullptr;
  bool readable_ = false;
};

}  // namespace quarry::api
