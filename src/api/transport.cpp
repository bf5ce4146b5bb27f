// ZeroMQ plumbing of the remote coupling (api/transport.h). The client never blocks without a
// bound: it polls its socket and a monitor of its connection together, so a killed server (the
// connection closes), a stopped one (heartbeats fail) and a slow one (the call's timeout) each
// end the wait with an error that names the endpoint.
#include "api/transport.h"

#include <fmt/format.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "api/backend.h"
#include "api/channel.h"
#include "api/wire.h"

namespace quarry::api {

namespace {

constexpr const char* kMonitor = "inproc://monitor";  // one per context, so one name serves
constexpr int kPollSliceMs = 1000;  // the longest a wait goes without looking at the clock

void set_option(void* socket, int option, int value) {
  zmq_setsockopt(socket, option, &value, sizeof value);
}

// timeout: how long this side waits for a pong; ttl: how long the peer waits for our traffic.
void set_common_options(void* socket, int timeout_ms, int ttl_ms) {
  set_option(socket, ZMQ_LINGER, 0);  // closing never waits for unsent messages
  set_option(socket, ZMQ_HEARTBEAT_IVL, kHeartbeatIntervalMs);
  set_option(socket, ZMQ_HEARTBEAT_TIMEOUT, timeout_ms);
  if (ttl_ms > 0) set_option(socket, ZMQ_HEARTBEAT_TTL, ttl_ms);
}

// A monitor socket on `socket` for these events (a PAIR socket connected to it).
void* start_monitor(void* context, void* socket, int events) {
  if (zmq_socket_monitor(socket, kMonitor, events) != 0)
    throw std::runtime_error(fmt::format("zmq_socket_monitor: {}", zmq_strerror(zmq_errno())));
  void* monitor = zmq_socket(context, ZMQ_PAIR);
  set_option(monitor, ZMQ_LINGER, 0);
  zmq_connect(monitor, kMonitor);
  return monitor;
}

// One monitor event (event id, value), or false if none is waiting.
bool next_event(void* monitor, std::uint16_t& event, std::uint32_t& value) {
  Message head;
  if (zmq_msg_recv(head.get(), monitor, ZMQ_DONTWAIT) < 0) return false;
  Message address;  // the second frame: the endpoint
  zmq_msg_recv(address.get(), monitor, 0);
  if (head.size() < 6) return false;
  std::memcpy(&event, head.data(), 2);
  std::memcpy(&value, head.data() + 2, 4);
  return true;
}

void close_sockets(void*& context, std::initializer_list<void**> sockets) {
  for (void** socket : sockets)
    if (*socket) zmq_close(*socket), *socket = nullptr;
  if (context) zmq_ctx_term(context), context = nullptr;
}

// True if a process accepts connections on the unix socket at `path`.
bool someone_listens(const std::string& path) {
  sockaddr_un address{};
  if (path.size() >= sizeof address.sun_path) return false;
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  if (fd < 0) return false;
  const bool listening =
      ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return listening;
}

}  // namespace

std::string endpoint_problem(const std::string& endpoint) {
  const bool ipc = endpoint.rfind("ipc://", 0) == 0 && endpoint.size() > 6;
  const std::size_t colon = endpoint.rfind(':');
  const bool tcp = endpoint.rfind("tcp://", 0) == 0 && colon != std::string::npos && colon > 6 &&
                   colon + 1 < endpoint.size();
  if (ipc || tcp) return "";
  return fmt::format(
      "endpoint '{}' is neither ipc://PATH (both processes on this host) nor tcp://HOST:PORT",
      endpoint);
}

void check_endpoint(const std::string& endpoint, const char* call) {
  if (const std::string problem = endpoint_problem(endpoint); !problem.empty())
    throw ApiError(QUARRY_ERROR_BAD_VALUE, fmt::format("{}: {}", call, problem));
}

bool is_ipc(const std::string& endpoint) {
  return endpoint.rfind("ipc://", 0) == 0;
}

Message Message::copy_of(const std::byte* bytes, std::size_t size) {
  Message message;
  zmq_msg_close(&message.message_);
  zmq_msg_init_size(&message.message_, size);
  if (size > 0) std::memcpy(zmq_msg_data(&message.message_), bytes, size);
  return message;
}

Message::Message(Message&& other) noexcept {
  zmq_msg_init(&message_);
  zmq_msg_move(&message_, &other.message_);
}

bool send_message(void* socket, std::string&& bytes, int flags) {
  auto* owned = new std::string(std::move(bytes));
  zmq_msg_t message;
  zmq_msg_init_data(
      &message, owned->data(), owned->size(),
      [](void*, void* hint) { delete static_cast<std::string*>(hint); }, owned);
  if (zmq_msg_send(&message, socket, flags) >= 0) return true;
  const int error = zmq_errno();
  zmq_msg_close(&message);  // frees `owned`
  errno = error;
  return false;
}

// ---- client ----

ClientConnection::ClientConnection(const std::string& endpoint) : endpoint_(endpoint) {
  context_ = zmq_ctx_new();
  socket_ = zmq_socket(context_, ZMQ_REQ);
  set_common_options(socket_, kClientHeartbeatTimeoutMs, kServerHeartbeatTimeoutMs);
  monitor_ =
      start_monitor(context_, socket_,
                    ZMQ_EVENT_CONNECTED | ZMQ_EVENT_DISCONNECTED |
                        ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL | ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL);
  if (zmq_connect(socket_, endpoint.c_str()) != 0) {
    const std::string reason = zmq_strerror(zmq_errno());
    close_sockets(context_, {&monitor_, &socket_});
    throw ApiError(QUARRY_ERROR_BAD_VALUE,
                   fmt::format("quarry_open: cannot connect to '{}': {}", endpoint, reason));
  }
}

ClientConnection::~ClientConnection() {
  if (socket_) zmq_socket_monitor(socket_, nullptr, 0);
  close_sockets(context_, {&monitor_, &socket_});
}

bool ClientConnection::watch_events() {
  std::uint16_t event = 0;
  std::uint32_t value = 0;
  while (dead_.empty() && monitor_ && next_event(monitor_, event, value)) {
    if (event == ZMQ_EVENT_CONNECTED) connected_ = true;
    if (event == ZMQ_EVENT_DISCONNECTED)
      dead_ = fmt::format(
          "the connection to the server at {} was lost (the server exited, was killed, or "
          "answered no heartbeat for {} s); the simulation there is gone for this handle: "
          "close it and open again",
          endpoint_, kClientHeartbeatTimeoutMs / 1000);
    if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL ||
        event == ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL)
      dead_ = fmt::format("the handshake with {} failed: what listens there is not a quarry serve",
                          endpoint_);
  }
  return dead_.empty();
}

void ClientConnection::fail(int status, const std::string& text) {
  // Nothing may answer on this socket any more: a late reply would be taken for the next request's.
  if (socket_) zmq_socket_monitor(socket_, nullptr, 0);
  close_sockets(context_, {&monitor_, &socket_});
  if (dead_.empty()) dead_ = text;
  throw ApiError(status, text);
}

template <class Send, class Receive>
Message ClientConnection::round_trip(int timeout_ms, const char* call, int slice_ms, Send&& send,
                                     Receive&& receive) {
  if (!socket_) throw ApiError(QUARRY_ERROR_TRANSPORT, fmt::format("{}: {}", call, dead_));
  if (!watch_events()) fail(QUARRY_ERROR_TRANSPORT, fmt::format("{}: {}", call, dead_));
  send();
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::milliseconds(std::max(timeout_ms, 0));
  for (;;) {
    int wait = slice_ms;
    if (timeout_ms >= 0) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      wait = static_cast<int>(std::clamp<long long>(left, 0, slice_ms));
    }
    if (std::optional<Message> reply = receive(wait)) return std::move(*reply);
    if (!watch_events()) fail(QUARRY_ERROR_TRANSPORT, fmt::format("{}: {}", call, dead_));
    if (timeout_ms >= 0 && Clock::now() >= deadline) fail_timeout(call, timeout_ms);
  }
}

Message ClientConnection::exchange(std::string&& request, int timeout_ms, const char* call) {
  const auto send = [&] {
    if (!send_message(socket_, std::move(request), ZMQ_DONTWAIT))
      fail(QUARRY_ERROR_TRANSPORT,
           fmt::format("{}: cannot send to {}: {}", call, endpoint_, zmq_strerror(errno)));
  };
  const auto receive = [&](int wait) -> std::optional<Message> {
    zmq_pollitem_t items[] = {{socket_, 0, ZMQ_POLLIN, 0}, {monitor_, 0, ZMQ_POLLIN, 0}};
    if (zmq_poll(items, 2, wait) < 0 && zmq_errno() != EINTR)
      fail(QUARRY_ERROR_TRANSPORT,
           fmt::format("{}: polling {}: {}", call, endpoint_, zmq_strerror(zmq_errno())));
    if (items[0].revents & ZMQ_POLLIN) {
      Message reply;
      if (zmq_msg_recv(reply.get(), socket_, 0) >= 0) return reply;
    }
    return std::nullopt;
  };
  return round_trip(timeout_ms, call, kPollSliceMs, send, receive);
}

Message ClientConnection::exchange(Channel& channel, const std::string& request, int timeout_ms,
                                   const char* call) {
  const auto send = [&] { channel.post_request(request); };
  const auto receive = [&](int wait) -> std::optional<Message> {
    if (!channel.wait_reply(std::chrono::milliseconds(wait))) return std::nullopt;
    const auto reply = channel.reply();
    return Message::copy_of(reply.data(), reply.size());
  };
  return round_trip(timeout_ms, call, static_cast<int>(Channel::kWatchSlice.count()), send, receive);
}

void ClientConnection::fail_timeout(const char* call, int timeout_ms) {
  fail(QUARRY_ERROR_TIMEOUT,
       fmt::format(
           "{}: no reply from the server at {} within {} ms{}; this handle is closed for calls "
           "now "
           "(close it and open again, with a longer quarry_open_info.timeout_ms if the server "
           "is slow)",
           call, endpoint_, timeout_ms,
           connected_ ? ""
                      : fmt::format(" (no connection was made: is `quarry serve --endpoint {}` "
                                    "running?)",
                                    endpoint_)));
}

// ---- server ----

ServerSocket::ServerSocket(const std::string& endpoint) {
  if (const std::string problem = endpoint_problem(endpoint); !problem.empty())
    throw std::runtime_error(problem);
  if (is_ipc(endpoint)) {
    const std::string path = endpoint.substr(6);
    if (someone_listens(path))
      throw std::runtime_error(
          fmt::format("another process listens at {} already (a second quarry serve?); "
                      "stop it or choose another path",
                      endpoint));
    const std::filesystem::path directory = std::filesystem::path(path).parent_path();
    if (!directory.empty() && !std::filesystem::is_directory(directory))
      throw std::runtime_error(fmt::format("cannot listen at {}: the directory {} does not exist",
                                           endpoint, directory.string()));
  }
  context_ = zmq_ctx_new();
  socket_ = zmq_socket(context_, ZMQ_REP);
  set_common_options(socket_, kServerHeartbeatTimeoutMs, 0);
  const std::int64_t largest = wire::kMaxMessageBytes;  // a peer sending more is disconnected
  zmq_setsockopt(socket_, ZMQ_MAXMSGSIZE, &largest, sizeof largest);
  monitor_ = start_monitor(context_, socket_, ZMQ_EVENT_DISCONNECTED);
  if (zmq_bind(socket_, endpoint.c_str()) != 0) {
    const int error = zmq_errno();
    zmq_socket_monitor(socket_, nullptr, 0);
    close_sockets(context_, {&monitor_, &socket_});
    throw std::runtime_error(fmt::format("cannot listen at {}: {}{}", endpoint, zmq_strerror(error),
                                         error == EADDRINUSE
                                             ? " (another process uses that port; choose another, "
                                               "or port 0 for a free one)"
                                             : ""));
  }
  char bound[512] = {};
  std::size_t size = sizeof bound;
  zmq_getsockopt(socket_, ZMQ_LAST_ENDPOINT, bound, &size);
  bound_ = bound;
  if (is_ipc(endpoint)) ipc_path_ = endpoint.substr(6);
}

ServerSocket::~ServerSocket() {
  if (socket_) zmq_socket_monitor(socket_, nullptr, 0);
  close_sockets(context_, {&monitor_, &socket_});
  // ZeroMQ removes the socket file when it closes the listener; make sure of it (the file is
  // ours: we bound it, and nobody can have bound it since while we listened).
  if (!ipc_path_.empty()) ::unlink(ipc_path_.c_str());
}

std::vector<int> ServerSocket::closed_connections(int timeout_ms) {
  std::vector<int> closed;
  zmq_pollitem_t items[] = {{socket_, 0, ZMQ_POLLIN, 0}, {monitor_, 0, ZMQ_POLLIN, 0}};
  readable_ = false;
  if (zmq_poll(items, 2, timeout_ms) < 0) return closed;  // a signal: the caller looks at its flag
  std::uint16_t event = 0;
  std::uint32_t value = 0;
  while (next_event(monitor_, event, value))
    if (event == ZMQ_EVENT_DISCONNECTED) closed.push_back(static_cast<int>(value));
  readable_ = (items[0].revents & ZMQ_POLLIN) != 0;
  return closed;
}

bool ServerSocket::receive_ready(Message& request, int& connection) {
  if (!readable_) return false;
  readable_ = false;
  if (zmq_msg_recv(request.get(), socket_, ZMQ_DONTWAIT) < 0) return false;
  connection = zmq_msg_get(request.get(), ZMQ_SRCFD);
  int frames = 1;
  for (bool more = zmq_msg_more(request.get()); more; ++frames) {
    Message extra;
    if (zmq_msg_recv(extra.get(), socket_, 0) < 0) break;
    more = zmq_msg_more(extra.get());
  }
  if (frames == 1) return true;
  reply(wire::error_reply(
      0, QUARRY_ERROR_TRANSPORT,
      fmt::format("quarry serve: a request is one frame; this one had {}", frames)));
  return false;
}

void ServerSocket::reply(std::string&& bytes) {
  send_message(socket_, std::move(bytes), 0);
}

bool ServerSocket::peer_alive(int fd) {
  if (fd < 0) return true;
  pollfd status{fd, POLLRDHUP, 0};
  if (::poll(&status, 1, 0) < 0) return true;
  return (status.revents & (POLLRDHUP | POLLHUP | POLLERR | POLLNVAL)) == 0;
}

}  // namespace quarry::api
