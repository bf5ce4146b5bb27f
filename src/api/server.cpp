// `quarry serve` (api/server.h): the session rules (one client at a time, bound to its
// connection, a deck's simulation kept across sessions) and the socket loop. Every request is
// checked in this order — length and magic, ABI major, header, operation, session, fields — and
// anything wrong is answered with a status and a text, never with a crash.
#include "api/server.h"

#include <fmt/format.h>

#include <random>
#include <vector>

#include "api/protocol.h"
#include "api/transport.h"

namespace quarry::api {

namespace {

constexpr int kPollMs = 200;  // how often the loop looks at the stop flag when idle

// A reply with this status and text whose payload is what `out` holds after its header room
// (without a text, `out` becomes the reply: a payload of megabytes is not copied again).
std::string reply_with(wire::Writer& out, std::uint64_t request_id, quarry_status status,
                       const std::string& text) {
  wire::ReplyHeader header;
  header.status = status;
  header.request_id = request_id;
  header.error_length = static_cast<std::uint32_t>(text.size());
  if (text.empty()) {
    wire::write_reply_header(out.bytes(), header);
    return std::move(out.bytes());
  }
  std::string reply(wire::kReplyHeaderBytes, '\0');
  reply.append(text);
  reply.append(out.bytes(), wire::kReplyHeaderBytes);
  wire::write_reply_header(reply, header);
  return reply;
}

std::uint64_t new_token() {
  std::random_device random;
  std::uint64_t token = 0;
  while (token == 0) token = (static_cast<std::uint64_t>(random()) << 32) | random();
  return token;
}

}  // namespace

Server::Server(ServerOptions options) : options_(std::move(options)), endpoint_(options_.endpoint) {
  if (options_.deck_path.empty()) return;
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.deck_path = options_.deck_path.c_str();
  info.output_directory =
      options_.output_directory.empty() ? nullptr : options_.output_directory.c_str();
  info.threads = options_.threads;
  deck_ = std::make_unique<LocalBackend>(info);
  deck_->set_stop_flag(options_.stop);
}

Server::~Server() {
  if (session_) end_session("the server is stopping");
  if (deck_) {
    try {
      deck_->close();
    } catch (...) {
      log(current_failure("quarry serve").text);
    }
  }
}

void Server::log(const std::string& line) const {
  if (options_.log) options_.log(line);
}

Backend& Server::backend() {
  return deck_ ? static_cast<Backend&>(*deck_) : *opened_;
}

std::string Server::handle(const std::byte* request, std::size_t size, int connection) {
  std::uint64_t request_id = 0;
  try {
    // Another major may lay its header out otherwise: only magic and version are read first.
    const std::uint32_t version = wire::message_abi_version(request, size);
    if (version != 0 && (version >> 16) != QUARRY_ABI_MAJOR)
      return wire::error_reply(
          0, QUARRY_ERROR_VERSION,
          fmt::format("quarry serve: the client speaks ABI {}, this server {}: the majors "
                      "differ; use a client and a server of the same major version",
                      wire::version_text(version), wire::version_text(QUARRY_ABI_VERSION)));
    const wire::RequestHeader header = wire::read_request_header(request, size);
    request_id = header.request_id;
    const char* name = wire::op_name(header.op);
    if (!name)
      return wire::error_reply(
          request_id, QUARRY_ERROR_UNSUPPORTED,
          fmt::format("quarry serve: operation {} is not one this server (ABI {}) knows "
                      "(operations {} to {}); is the client of a newer version?",
                      header.op, wire::version_text(QUARRY_ABI_VERSION), wire::kFirstOp,
                      wire::kLastOp));
    if (header.op == static_cast<std::uint32_t>(wire::Op::open)) {
      wire::Reader in(request, size, wire::kRequestHeaderBytes);
      return open(header, in, connection);
    }
    if (!session_ || header.session != session_->token)
      return wire::error_reply(
          request_id, QUARRY_ERROR_WRONG_STATE,
          session_
              ? fmt::format(
                    "{}: the server at {} is busy with another client (session {}); this handle's "
                    "session has ended",
                    name, endpoint_, session_->number)
              : fmt::format(
                    "{}: no client is attached to the server at {} (this handle's session has "
                    "ended); open again",
                    name, endpoint_));
    return call(header, request, size);
  } catch (const wire::WireError& e) {
    return wire::error_reply(request_id, QUARRY_ERROR_TRANSPORT,
                             fmt::format("quarry serve: malformed request: {}", e.what()));
  } catch (...) {
    const Failure failure = current_failure("quarry serve");
    return wire::error_reply(request_id, failure.status, failure.text);
  }
}

std::string Server::call(const wire::RequestHeader& header, const std::byte* request,
                         std::size_t size) {
  const auto op = static_cast<wire::Op>(header.op);
  const char* name = wire::op_name(header.op);
  if (session_->segment)
    session_->segment->release_retired();  // the last request's arrays are done
  wire::SegmentView* segment = session_->segment ? &session_->segment->view() : nullptr;
  wire::Reader in(request, size, wire::kRequestHeaderBytes, segment, &session_->outputs);
  wire::Writer out;
  out.bytes().assign(wire::kReplyHeaderBytes, '\0');
  if (op == wire::Op::close) {
    in.expect_end();
    std::string failed;
    try {
      if (opened_) opened_->close();  // its outputs finished; a deck's simulation goes on
    } catch (...) {
      failed = current_failure(name).text;
    }
    opened_.reset();
    end_session("the client closed it");
    return failed.empty() ? reply_with(out, header.request_id, QUARRY_OK, "")
                          : wire::error_reply(header.request_id, QUARRY_ERROR_IO, failed);
  }
  try {
    if (op == wire::Op::view_particles_shared || op == wire::Op::view_property_shared ||
        op == wire::Op::view_next_step_loads_shared) {
      shared_view(op, in, out);
    } else if (op == wire::Op::put_next_step_loads_shared) {
      put_shared_loads(in);
    } else if (op == wire::Op::attach_channel) {
      const std::string channel = in.text();
      in.expect_end();
      try {
        session_->channel = Channel::attach(channel);
        session_->socket_requests = 0;
      } catch (const std::runtime_error& e) {
        throw ApiError(QUARRY_ERROR_IO,
                       fmt::format("quarry_open: the server cannot map the client's request "
                                   "channel: {}; the requests go over the socket",
                                   e.what()));
      }
      log(fmt::format("session {}: requests through shared memory", session_->number));
    } else
      call_handler(op)(backend(), in, out);
  } catch (const wire::WireError& e) {
    return wire::error_reply(header.request_id, QUARRY_ERROR_TRANSPORT,
                             fmt::format("{}: malformed request: {}", name, e.what()));
  } catch (...) {
    // What the handler wrote before the failure goes back (get_particles: the count needed).
    const Failure failure = current_failure(name);
    return reply_with(out, header.request_id, failure.status, failure.text);
  }
  in.write_outputs(out);
  return reply_with(out, header.request_id, QUARRY_OK, "");
}

void Server::shared_view(wire::Op op, wire::Reader& in, wire::Writer& out) {
  const auto which = in.get<std::uint32_t>();
  const std::string name = in.text();
  in.expect_end();
  const quarry_view view =
      op == wire::Op::view_particles_shared ? backend().view_particles(static_cast<std::int32_t>(which))
      : op == wire::Op::view_property_shared
          ? backend().view_property(which)
          : backend().view_next_step_loads(static_cast<std::int32_t>(which));
  // Attached only once the field or property is known to exist: a session holds at most one
  // segment per view there is.
  std::unique_ptr<SharedSegment>& segment =
      session_->views[wire::view_key(op, which)];
  if (!segment || segment->name() != name) {
    try {
      segment = SharedSegment::attach(name);
    } catch (const std::runtime_error& e) {
      segment.reset();
      throw ApiError(QUARRY_ERROR_IO,
                     fmt::format("{}: the server cannot map the client's shared memory for the "
                                 "view: {}",
                                 wire::op_name(static_cast<std::uint32_t>(op)), e.what()));
    }
  }
  const std::uint64_t bytes = view_bytes(view);
  const bool fits = bytes <= segment->size();
  if (fits && bytes > 0) copy_view(view, segment->at(0));
  protocol::fields(out, view);
  out.put(bytes);
  out.put(static_cast<std::uint8_t>(fits));
}

void Server::put_shared_loads(wire::Reader& in) {
  const auto count = in.get<std::uint64_t>();
  const auto fields = in.get<std::uint32_t>();  // how many field numbers follow
  if (fields > 2) throw wire::WireError(fmt::format("{} fields of loads", fields));
  std::vector<std::int32_t> which(fields);
  for (std::int32_t& field : which) field = in.get<std::int32_t>();
  in.expect_end();
  for (const std::int32_t field : which) {
    const auto found = session_->views.find(
        wire::view_key(wire::Op::view_next_step_loads_shared, static_cast<std::uint32_t>(field)));
    const bool mapped = found != session_->views.end() && found->second;
    if (!mapped || found->second->size() / (3 * sizeof(double)) < count) {
      backend().view_next_step_loads(field);  // an unknown field: BAD_VALUE, not a mapping missing
      throw ApiError(QUARRY_ERROR_WRONG_STATE,
                     fmt::format("quarry_view_next_step_loads: the loads sent back are of {} "
                                 "particles in shared memory the server {}",
                                 count, mapped ? "mapped for fewer" : "never mapped"));
    }
    write_next_step_loads(backend(), field, found->second->at(0), count);
  }
}

bool Server::serve_channel(std::chrono::microseconds spin, std::chrono::milliseconds budget) {
  if (!session_->channel->wait_request(spin, budget)) return false;
  bool oversized = false;
  const std::string request = session_->channel->take_request(oversized);
  if (request.empty() && !oversized) return false;  // it rang for a request on the socket
  // Held through the call: a close ends the session (and a second attach replaces it).
  std::unique_ptr<Channel> channel = std::move(session_->channel);
  std::string reply =
      oversized ? wire::error_reply(0, QUARRY_ERROR_TRANSPORT,
                                    fmt::format("quarry serve: a request of more than the "
                                                "channel's {} bytes",
                                                Channel::kCapacity))
                : handle(reinterpret_cast<const std::byte*>(request.data()), request.size(),
                         session_->connection);
  if (reply.size() > Channel::kCapacity) {
    const wire::RequestHeader header = wire::read_request_header(request.data(), request.size());
    reply = wire::error_reply(
        header.request_id, QUARRY_ERROR_INTERNAL,
        fmt::format("{}: its reply of {} bytes does not fit the request channel's {}; a client "
                    "of this version sends such calls over the socket",
                    wire::op_name(header.op) ? wire::op_name(header.op) : "a call", reply.size(),
                    Channel::kCapacity));
  }
  channel->post_reply(reply);
  if (session_ && !session_->channel) session_->channel = std::move(channel);
  return true;
}

bool Server::socket_request_due() const {
  return has_channel() && session_->channel->socket_posted() > session_->socket_requests;
}

void Server::settle_socket_requests() {
  if (has_channel()) session_->socket_requests = session_->channel->socket_posted();
}

void Server::count_socket_request(const std::byte* request, std::size_t size) {
  if (!has_channel()) return;
  try {
    if (wire::read_request_header(request, size).session == session_->token)
      ++session_->socket_requests;
  } catch (const wire::WireError&) {
    // not a request of the session's (handle() answers it)
  }
}

std::string Server::open(const wire::RequestHeader& header, wire::Reader& in, int connection) {
  const auto request = protocol::read<protocol::OpenRequest>(in);
  in.expect_end();
  const auto refuse = [&](quarry_status status, const std::string& text) {
    return wire::error_reply(header.request_id, status, "quarry_open: " + text);
  };
  if ((request.caller_abi_version >> 16) != QUARRY_ABI_MAJOR)
    return refuse(
        QUARRY_ERROR_VERSION,
        fmt::format(
            "the caller was built for ABI {}, the server at {} is {}; rebuild the caller against "
            "this quarry.h",
            wire::version_text(request.caller_abi_version), endpoint_,
            wire::version_text(QUARRY_ABI_VERSION)));
  if (session_)
    return refuse(
        QUARRY_ERROR_WRONG_STATE,
        fmt::format(
            "the server at {} is busy: session {} (client pid {}) is attached, and it serves one "
            "client at a time; wait until that one closes its handle, or start another "
            "quarry serve",
            endpoint_, session_->number, session_->client_pid));
  if (deck_ && (request.deck_path || request.checkpoint_path))
    return refuse(
        QUARRY_ERROR_WRONG_STATE,
        fmt::format(
            "the server at {} runs the deck {} given on its command line; open without deck_path "
            "and checkpoint_path to attach to it",
            endpoint_, options_.deck_path));
  std::string what = deck_ ? fmt::format("the deck {}", options_.deck_path) : "";
  if (!deck_) {
    quarry_open_info info = QUARRY_OPEN_INFO_INIT;
    info.deck_path = request.deck_path;
    info.checkpoint_path = request.checkpoint_path;
    info.output_directory = request.output_directory;
    if (!info.output_directory && !options_.output_directory.empty())
      info.output_directory = options_.output_directory.c_str();
    info.threads = request.threads > 0 ? request.threads : options_.threads;
    try {
      opened_ = std::make_unique<LocalBackend>(info);
    } catch (...) {
      const Failure failure = current_failure("quarry_open");
      return wire::error_reply(header.request_id, failure.status, failure.text);
    }
    opened_->set_stop_flag(options_.stop);
    what = request.deck_path         ? fmt::format("its deck {}", request.deck_path)
           : request.checkpoint_path ? fmt::format("its checkpoint {}", request.checkpoint_path)
                                     : "an empty simulation";
  }
  Session session;
  session.token = new_token();
  session.number = ++sessions_;
  session.connection = connection;
  session.client_pid = request.client_pid;
  std::string arrays = "arrays in the messages";
  if (request.segment) {
    try {
      session.segment = SharedSegment::attach(request.segment);
      arrays = "arrays in shared memory";
    } catch (const std::exception& e) {
      arrays = fmt::format("arrays in the messages (the client's shared memory: {})", e.what());
    }
  }
  protocol::OpenReply reply;
  reply.session = session.token;
  reply.shared_memory = session.segment ? 1 : 0;
  reply.server_version = kLibraryVersion;
  session_ = std::move(session);
  log(fmt::format("session {} attached: client pid {}, {}, {}", session_->number,
                  session_->client_pid, what, arrays));
  wire::Writer out;
  out.bytes().assign(wire::kReplyHeaderBytes, '\0');
  protocol::fields(out, reply);
  out.put(wire::kLastOp);  // the operations it may ask (a server before the shared views sent none)
  return reply_with(out, header.request_id, QUARRY_OK, "");
}

void Server::end_session(const std::string& reason) {
  if (opened_) {
    try {
      opened_->close();
    } catch (...) {
      log(current_failure("quarry serve").text);
    }
    opened_.reset();
  }
  log(fmt::format("session {} ended: {}", session_->number, reason));
  session_.reset();  // unmaps the segment (its name went at attach)
}

void Server::connection_closed(int connection) {
  if (session_ && connection >= 0 && session_->connection == connection)
    end_session("its connection closed (the client exited or was killed)");
}

void serve(const ServerOptions& options,
           const std::function<void(const std::string&)>& on_listening) {
  Server server(options);
  ServerSocket socket(options.endpoint);
  server.set_endpoint(socket.endpoint());
  on_listening(socket.endpoint());
  const auto stopping = [&] { return options.stop && options.stop->load() != 0; };
  bool answered = false;  // a request came through the channel just now: the next may follow
  while (!stopping()) {
    int wait = kPollMs;
    if (server.has_channel()) {
      // The session's requests come through its channel; the socket is looked at between
      // them and every slice (another client, a closed connection, a call too large).
      answered = server.serve_channel(answered ? Channel::kSpin : std::chrono::microseconds(0),
                                      Channel::kWatchSlice);
      if (answered) continue;
      wait = server.socket_request_due() ? kPollMs : 0;
    }
    Message request;
    int connection = -1;
    if (!socket.receive(request, connection, wait,
                        [&](int closed) { server.connection_closed(closed); })) {
      if (server.has_channel() && !ServerSocket::peer_alive(server.session_connection()))
        server.connection_closed(server.session_connection());
      // A request announced for the socket that never came must not keep the channel waiting.
      if (wait > 0 && server.has_channel()) server.settle_socket_requests();
      continue;
    }
    if (!ServerSocket::peer_alive(server.session_connection()))
      server.connection_closed(server.session_connection());
    server.count_socket_request(request.data(), request.size());
    socket.reply(server.handle(request.data(), request.size(), connection));
  }
}

}  // namespace quarry::api
