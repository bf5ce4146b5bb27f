// RemoteBackend (api/remote.h): each Backend call is one request to `quarry serve` and its reply,
// the fields in the order the server's handlers read them (api/server_calls.cpp). Arrays of 4 KiB
// and more go through the session's shared-memory segment over ipc://, in the messages over tcp://.
#include "api/remote.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "api/channel.h"
#include "api/protocol.h"
#include "api/shared_memory.h"
#include "api/transport.h"
#include "api/wire.h"

namespace quarry::api {

namespace {

using wire::Op;

constexpr int kDefaultTimeoutMs = 60000;               // quarry_open_info.timeout_ms = 0
constexpr std::uint64_t kFirstSegmentBytes = 1 << 20;  // grown on demand
constexpr std::uint64_t kFirstViewBytes = 1 << 16;     // a view's segment: replaced when short

// A reply, checked: its header read, the server's ABI major compared, the request it answers
// matched; `in` stands at the payload. An error status is thrown (ApiError with the server's
// text) after on_error has read what came with it. Not movable (`in` points into `message`).
struct Reply {
  Reply(Message&& received, std::uint64_t request_id, const std::string& endpoint, const char* call,
        const std::function<void(wire::Reader&)>& on_error)
      : message(std::move(received)), in(message.data(), message.size(), 0) {
    const std::uint32_t version = wire::message_abi_version(message.data(), message.size());
    if (version != 0 && (version >> 16) != QUARRY_ABI_MAJOR)
      throw ApiError(
          QUARRY_ERROR_VERSION,
          fmt::format(
              "{}: the server at {} speaks ABI {}, this client {}: the majors differ; use a client "
              "library and a quarry serve of the same major version",
              call, endpoint, wire::version_text(version), wire::version_text(QUARRY_ABI_VERSION)));
    try {
      header = wire::read_reply_header(message.data(), message.size());
    } catch (const wire::WireError& e) {
      throw ApiError(
          QUARRY_ERROR_TRANSPORT,
          fmt::format("{}: the server at {} answered garbage: {}", call, endpoint, e.what()));
    }
    if (header.request_id != request_id && header.request_id != 0)
      throw ApiError(QUARRY_ERROR_TRANSPORT,
                     fmt::format("{}: the server at {} answered request {}, not {}", call, endpoint,
                                 header.request_id, request_id));
    error = std::string(reinterpret_cast<const char*>(message.data()) + wire::kReplyHeaderBytes,
                        header.error_length);
    in =
        wire::Reader(message.data(), message.size(), wire::kReplyHeaderBytes + header.error_length);
    if (header.status == QUARRY_OK) return;
    if (on_error && in.remaining() > 0) on_error(in);
    throw ApiError(header.status, error);
  }
  Reply(Reply&&) = delete;

  Message message;
  wire::Reader in;
  wire::ReplyHeader header;
  std::string error;
};

// A view of values copied to the client (`data`: its first, dense rows of `row` bytes).
quarry_view copied_view(quarry_view view, void* data, std::size_t row) {
  view.data = view.count > 0 ? data : nullptr;
  view.stride = static_cast<std::int64_t>(row);
  view.writable = 0;  // a copy: writes would not reach the server (quarry_set_property does)
  return view;
}

// The values of a view that came in a reply, kept in `buffer` (the handle's copy).
quarry_view read_view(wire::Reader& in, std::vector<std::byte>& buffer) {
  quarry_view view = protocol::read<quarry_view>(in);
  const std::size_t element = protocol::dtype_bytes(view.dtype);
  if (element == 0) throw wire::WireError(fmt::format("a view of dtype {}", view.dtype));
  in.align();
  const auto bytes = in.raw(view.count * view.components * element);
  buffer.assign(bytes.begin(), bytes.end());
  return copied_view(view, buffer.data(), view.components * element);
}

std::uint64_t vectors(const void* data, std::uint64_t count) {
  return data ? 3 * count : 0;
}

class RemoteBackend final : public Backend {
 public:
  explicit RemoteBackend(const quarry_open_info& info);
  bool remote() const override { return true; }

  void close() override { ask(Op::close); }
  void set_settings(const quarry_settings& settings) override;
  std::uint32_t add_material(const quarry_material& material) override {
    return ask<std::uint32_t>(Op::add_material, material);
  }
  void add_interaction(const quarry_interaction& interaction) override {
    ask(Op::add_interaction, interaction);
  }
  std::uint32_t add_particle_type(const quarry_particle_type& type) override {
    return ask<std::uint32_t>(Op::add_particle_type, type);
  }
  void start() override { ask(Op::start); }

  void get_time(double* time, double* time_step, std::uint64_t* steps) override;
  quarry_advance_result advance(double duration) override {
    return ask<quarry_advance_result>(Op::advance, duration);
  }
  void step(std::uint64_t steps) override { ask(Op::step, steps); }

  void save_checkpoint(const std::string& path) override { ask(Op::save_checkpoint, path); }
  std::string save_state() override;
  void restore_state(const void* bytes, std::uint64_t size) override;

  std::uint32_t num_types() override { return ask<std::uint32_t>(Op::num_types); }
  std::string type_name(std::uint32_t type) override {
    return ask<std::string>(Op::type_name, type);
  }
  std::uint64_t num_particles(std::int32_t type) override {
    return ask<std::uint64_t>(Op::num_particles, type);
  }
  std::uint64_t epoch() override { return ask<std::uint64_t>(Op::epoch); }
  void get_particles(quarry_particle_data& data) override;
  std::uint64_t particle_index(std::uint64_t id) override {
    return ask<std::uint64_t>(Op::particle_index, id);
  }
  quarry_view view_particles(std::int32_t field) override;
  quarry_view view_next_step_loads(std::int32_t field) override;
  void add_particles(const quarry_new_particles& particles) override;
  void remove_particles(const std::uint64_t* ids, std::uint64_t count) override;

  void set_external_loads(const double* force, const double* torque, std::uint64_t count,
                          std::int32_t mode, std::int32_t hold) override;
  void set_external_loads_by_id(const std::uint64_t* ids, std::uint64_t count, const double* force,
                                const double* torque, std::int32_t mode,
                                std::int32_t hold) override;
  void clear_external_loads() override { ask(Op::clear_external_loads); }

  std::uint32_t register_property(const std::string& name, std::uint32_t components,
                                  const std::string& unit, double initial) override {
    return ask<std::uint32_t>(Op::register_property, name, components, unit, initial);
  }
  std::uint32_t num_properties() override { return ask<std::uint32_t>(Op::num_properties); }
  void property_info(std::uint32_t index, std::string& name, std::uint32_t& components,
                     std::string& unit) override;
  void get_property(std::uint32_t index, double* values, std::uint64_t count) override;
  void set_property(std::uint32_t index, const double* values, std::uint64_t count) override;
  quarry_view view_property(std::uint32_t index) override;

  void sample_points(std::uint32_t type, std::uint32_t points, std::uint64_t seed,
                     double* unit_points) override;
  std::uint64_t sample_point_positions(std::uint32_t type, std::uint32_t points, std::uint64_t seed,
                                       double* positions, std::uint64_t capacity) override;

  std::uint32_t add_surface(const quarry_surface_desc& surface) override;
  std::uint32_t num_surfaces() override { return ask<std::uint32_t>(Op::num_surfaces); }
  std::uint32_t find_surface(const std::string& name) override {
    return ask<std::uint32_t>(Op::find_surface, name);
  }
  quarry_surface_info surface_info(std::uint32_t surface) override {
    return ask<quarry_surface_info>(Op::surface_info, surface);
  }
  void set_surface_driver(std::uint32_t surface, std::int32_t driver) override {
    ask(Op::set_surface_driver, surface, driver);
  }
  void set_surface_nodes(std::uint32_t surface, const double* positions, const double* velocities,
                         std::uint64_t count) override;
  void get_surface_nodes(std::uint32_t surface, double* positions, double* velocities,
                         std::uint64_t count) override;
  void get_surface_loads(std::uint32_t surface, quarry_surface_loads& loads) override;

  void set_hook(quarry_sim, std::int32_t, quarry_hook_fn, void*) override {
    no_hooks("quarry_set_hook");
  }
  void add_hook_forces(const double*, const double*, std::uint64_t) override {
    no_hooks("quarry_add_hook_forces");
  }

 private:
  [[noreturn]] static void no_hooks(const char* call) {
    throw ApiError(
        QUARRY_ERROR_UNSUPPORTED,
        fmt::format(
            "{}: step hooks run inside the engine's step and cannot reach another process; on a "
            "remote handle set the forces between steps instead (quarry_set_external_loads with "
            "QUARRY_HOLD_NEXT_STEP, then quarry_step(sim, 1)), or open the simulation in process",
            call));
  }

  wire::Request request(Op op) {
    if (loads_viewed_[0] || loads_viewed_[1])
      if (op != Op::view_next_step_loads && op != Op::view_next_step_loads_shared && op != Op::close)
        send_next_step_loads();
    if (segment_) segment_->restart();
    return wire::Request(op, segment_.get());
  }

  // Sends the request and waits for the reply (an advance or step as long as the server lives,
  // anything else at most the open's timeout). A reply with an error status throws it, after
  // on_error has read what came with it.
  Reply send(wire::Request& request, const std::function<void(wire::Reader&)>& on_error = {}) {
    const Op op = request.op();
    const char* call = wire::op_name(static_cast<std::uint32_t>(op));
    const int wait = op == Op::advance || op == Op::step ? -1 : timeout_ms_;
    const std::uint64_t id = next_request_++;
    std::string& message = request.message(id, session_);
    // Through the channel, but for the calls whose reply may outgrow it (a whole state, views
    // taken into the reply) and the close (which ends the session the channel belongs to).
    if (channel_ && op != Op::close && op != Op::save_state && op != Op::view_particles &&
        op != Op::view_property && op != Op::view_next_step_loads &&
        message.size() <= Channel::kCapacity)
      return Reply(connection_.exchange(*channel_, message, wait, call), id,
                   connection_.endpoint(), call, on_error);
    if (channel_) channel_->post_socket_request();
    return Reply(connection_.exchange(std::move(message), wait, call), id, connection_.endpoint(),
                 call, on_error);
  }

  // A request of these fields whose reply begins with a value of R (void: nothing).
  template <class R = void, class... A>
  R ask(Op op, const A&... values) {
    wire::Request r = request(op);
    protocol::write_values(r.fields(), values...);
    Reply reply = send(r);
    if constexpr (!std::is_void_v<R>) return protocol::read_value<R>(reply.in);
  }

  ClientConnection connection_;
  std::unique_ptr<SharedSegment> segment_;
  std::unique_ptr<Channel> channel_;  // the requests through shared memory (api/channel.h)
  std::uint64_t session_ = 0;
  std::uint32_t server_abi_version_ = 0;  // from the open reply's header
  std::uint64_t next_request_ = 1;
  int timeout_ms_;
  std::map<std::int32_t, std::vector<std::byte>> particle_views_;  // field → its copy
  std::map<std::uint32_t, std::vector<std::byte>> property_views_;
  // The next step's loads as the handle's copies (force, torque), and which of them were viewed
  // (and so maybe written) since they were last sent: they go to the server before the next
  // request of any other kind.
  std::array<std::vector<std::byte>, 2> load_views_;
  std::array<bool, 2> loads_viewed_{};
  std::array<bool, 2> loads_shared_{};  // the copy is in the field's shared view segment
  std::uint64_t load_view_count_ = 0;
  void send_next_step_loads();
  // Over ipc with shared memory a view is written by the server into a segment of its own (one
  // copy, none through the socket), kept until the next view of the same field or property.
  std::optional<quarry_view> shared_view(Op op, std::uint32_t which);
  std::map<std::uint64_t, std::unique_ptr<SharedSegment>> view_segments_;
  // The highest operation the server knows (its open reply's; 0 from a server before the
  // shared views, which sent none): later ones are not asked of it.
  std::uint32_t server_last_op_ = 0;
  bool server_knows(Op op) const { return static_cast<std::uint32_t>(op) <= server_last_op_; }
};

RemoteBackend::RemoteBackend(const quarry_open_info& info)
    : connection_(info.endpoint),
      timeout_ms_(info.timeout_ms > 0 ? info.timeout_ms : kDefaultTimeoutMs) {
  if (is_ipc(info.endpoint)) {
    try {
      segment_ = SharedSegment::create(kFirstSegmentBytes);
    } catch (const std::runtime_error&) {
      segment_.reset();  // no shared memory here: the arrays go in the messages
    }
  }
  protocol::OpenRequest open;
  open.caller_abi_version = info.abi_version;
  open.deck_path = info.deck_path;
  open.checkpoint_path = info.checkpoint_path;
  open.output_directory = info.output_directory;
  open.threads = info.threads;
  open.client_pid = ::getpid();
  open.segment = segment_ ? segment_->name().c_str() : nullptr;
  wire::Request r(Op::open, nullptr);
  protocol::fields(r.fields(), open);
  Reply reply = send(r);
  const auto answer = protocol::read<protocol::OpenReply>(reply.in);
  session_ = answer.session;
  server_abi_version_ = reply.header.abi_version;
  server_last_op_ = reply.in.remaining() >= sizeof(std::uint32_t) ? reply.in.get<std::uint32_t>() : 0;
  if (!answer.shared_memory) segment_.reset();
  if (!segment_ || !server_knows(Op::attach_channel)) return;
  // Where the server maps our segment it can take requests through shared memory too.
  try {
    std::unique_ptr<Channel> channel = Channel::create();
    wire::Request attach(Op::attach_channel, segment_.get());
    attach.fields().text(channel->name());
    send(attach);
    channel_ = std::move(channel);
  } catch (const ApiError& e) {
    // A server that cannot map it: the socket.
    if (e.status() != QUARRY_ERROR_IO) throw;
  } catch (const std::runtime_error&) {
    // No shared memory to spare for it here: the socket.
  }
}

// The fields the server's minor knows (an older server refuses trailing bytes as malformed); a
// setting it cannot honour is refused here rather than dropped on the way.
void RemoteBackend::set_settings(const quarry_settings& settings) {
  const std::uint32_t version = std::min(server_abi_version_, QUARRY_ABI_VERSION);
  const bool periodic =
      settings.periodic[0] != 0 || settings.periodic[1] != 0 || settings.periodic[2] != 0;
  if ((version & 0xffffu) < 1 && periodic)
    throw ApiError(
        QUARRY_ERROR_UNSUPPORTED,
        fmt::format("quarry_set_settings: the server at {} speaks ABI {}, which has no periodic "
                    "axes (ABI 1.1); run a quarry serve of this library's version ({}), or leave "
                    "periodic all 0",
                    connection_.endpoint(), wire::version_text(server_abi_version_),
                    wire::version_text(QUARRY_ABI_VERSION)));
  wire::Request r = request(Op::set_settings);
  protocol::fields(r.fields(), settings, version);
  send(r);
}

void RemoteBackend::get_time(double* time, double* time_step, std::uint64_t* steps) {
  wire::Request r = request(Op::get_time);
  Reply reply = send(r);
  double t = 0.0, dt = 0.0;
  std::uint64_t n = 0;
  reply.in(t, dt, n);
  if (time) *time = t;
  if (time_step) *time_step = dt;
  if (steps) *steps = n;
}

std::string RemoteBackend::save_state() {
  wire::Request r = request(Op::save_state);
  Reply reply = send(r);
  const auto size = reply.in.get<std::uint64_t>();
  reply.in.align();
  const auto bytes = reply.in.raw(size);
  return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

void RemoteBackend::restore_state(const void* bytes, std::uint64_t size) {
  wire::Request r = request(Op::restore_state);
  r.input(static_cast<const std::byte*>(bytes), size);
  send(r);
}

void RemoteBackend::get_particles(quarry_particle_data& d) {
  wire::Request r = request(Op::get_particles);
  const std::uint64_t n = d.capacity, n3 = 3 * d.capacity;
  r.fields().put(n);
  r.output(d.id, n);
  r.output(d.type, n);
  r.output(d.position, n3);
  r.output(d.velocity, n3);
  r.output(d.angular_velocity, n3);
  r.output(d.radius, n);
  r.output(d.mass, n);
  r.output(d.volume, n);
  r.output(d.force, n3);
  r.output(d.torque, n3);
  Reply reply = send(r, [&d](wire::Reader& in) { in(d.count, d.epoch); });
  reply.in(d.count, d.epoch);
  r.read_outputs(reply.in);
}

std::optional<quarry_view> RemoteBackend::shared_view(Op op, std::uint32_t which) {
  if (!segment_ || !server_knows(op)) return std::nullopt;
  std::unique_ptr<SharedSegment>& segment =
      view_segments_[wire::view_key(op, which)];
  std::uint64_t wanted = kFirstViewBytes;
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (!segment || segment->size() < wanted) {
      try {
        segment = SharedSegment::create(wanted);
      } catch (const std::runtime_error&) {
        segment.reset();
        return std::nullopt;  // no shared memory to spare: this view comes in the reply
      }
    }
    wire::Request r = request(op);
    r.fields().put(which);
    r.fields().text(segment->name());
    Reply reply = send(r);
    quarry_view view = protocol::read<quarry_view>(reply.in);
    const auto bytes = reply.in.get<std::uint64_t>();
    const auto written = reply.in.get<std::uint8_t>();
    const std::size_t row = protocol::dtype_bytes(view.dtype) * view.components;
    if (row == 0 || bytes != view.count * row || (written && bytes > segment->size()))
      throw ApiError(QUARRY_ERROR_TRANSPORT,
                     fmt::format("{}: the server at {} describes a view of {} bytes as {} "
                                 "particles of {} bytes",
                                 wire::op_name(static_cast<std::uint32_t>(op)),
                                 connection_.endpoint(), bytes, view.count, row));
    if (written) return copied_view(view, segment->at(0), row);
    wanted = bytes + bytes / 4;  // a larger segment, with room for some growth, and once more
  }
  return std::nullopt;
}

quarry_view RemoteBackend::view_particles(std::int32_t field) {
  if (auto view = shared_view(Op::view_particles_shared, static_cast<std::uint32_t>(field)))
    return *view;
  wire::Request r = request(Op::view_particles);
  r.fields().put(field);
  Reply reply = send(r);
  return read_view(reply.in, particle_views_[field]);
}

quarry_view RemoteBackend::view_next_step_loads(std::int32_t field) {
  if (!server_knows(Op::view_next_step_loads))
    throw ApiError(QUARRY_ERROR_UNSUPPORTED,
                   fmt::format("quarry_view_next_step_loads: the server at {} speaks ABI {}, which "
                               "has no such view (ABI 1.2); run a quarry serve of this library's "
                               "version ({}), or set the loads with quarry_set_external_loads",
                               connection_.endpoint(), wire::version_text(server_abi_version_),
                               wire::version_text(QUARRY_ABI_VERSION)));
  const std::size_t which = field == QUARRY_FIELD_TORQUE ? 1 : 0;
  quarry_view view;
  if (auto shared = shared_view(Op::view_next_step_loads_shared, static_cast<std::uint32_t>(field))) {
    view = *shared;
    loads_shared_[which] = true;
  } else {
    wire::Request r = request(Op::view_next_step_loads);
    r.fields().put(field);
    Reply reply = send(r);  // the server refuses another field
    view = read_view(reply.in, load_views_[which]);
    loads_shared_[which] = false;
  }
  loads_viewed_[which] = true;
  load_view_count_ = view.count;
  view.writable = 1;
  return view;
}

void RemoteBackend::send_next_step_loads() {
  const std::array<bool, 2> viewed = loads_viewed_;
  loads_viewed_ = {};
  const std::uint64_t n = load_view_count_;
  // Those in shared memory by naming their fields (the server reads the segments), the others
  // as arrays.
  std::vector<std::int32_t> shared;
  for (std::size_t k = 0; k < 2; ++k)
    if (viewed[k] && loads_shared_[k]) shared.push_back(k == 0 ? QUARRY_FIELD_FORCE : QUARRY_FIELD_TORQUE);
  if (!shared.empty()) {
    wire::Request r = request(Op::put_next_step_loads_shared);
    r.fields().put(n);
    r.fields().put(static_cast<std::uint32_t>(shared.size()));
    for (const std::int32_t field : shared) r.fields().put(field);
    send(r);
  }
  const bool force = viewed[0] && !loads_shared_[0], torque = viewed[1] && !loads_shared_[1];
  if (!force && !torque) return;
  wire::Request r = request(Op::put_next_step_loads);
  r.input(force ? reinterpret_cast<const double*>(load_views_[0].data()) : nullptr, force ? 3 * n : 0);
  r.input(torque ? reinterpret_cast<const double*>(load_views_[1].data()) : nullptr, torque ? 3 * n : 0);
  r.fields().put(n);
  send(r);
}

void RemoteBackend::add_particles(const quarry_new_particles& q) {
  wire::Request r = request(Op::add_particles);
  r.fields().put(q.count);
  r.input(q.types, q.count);
  r.fields().put(q.type);
  r.input(q.position, 3 * q.count);
  r.input(q.velocity, 3 * q.count);
  r.input(q.angular_velocity, 3 * q.count);
  r.input(q.radius, q.count);
  r.output(q.ids, q.count);
  Reply reply = send(r);
  r.read_outputs(reply.in);
}

void RemoteBackend::remove_particles(const std::uint64_t* ids, std::uint64_t count) {
  wire::Request r = request(Op::remove_particles);
  r.input(count > 0 ? ids : nullptr, count);
  send(r);
}

void RemoteBackend::set_external_loads(const double* force, const double* torque,
                                       std::uint64_t count, std::int32_t mode, std::int32_t hold) {
  wire::Request r = request(Op::set_external_loads);
  r.input(force, vectors(force, count));
  r.input(torque, vectors(torque, count));
  r.fields()(count, mode, hold);
  send(r);
}

void RemoteBackend::set_external_loads_by_id(const std::uint64_t* ids, std::uint64_t count,
                                             const double* force, const double* torque,
                                             std::int32_t mode, std::int32_t hold) {
  wire::Request r = request(Op::set_external_loads_by_id);
  r.input(count > 0 ? ids : nullptr, count);
  r.input(force, vectors(force, count));
  r.input(torque, vectors(torque, count));
  r.fields()(mode, hold);
  send(r);
}

void RemoteBackend::property_info(std::uint32_t index, std::string& name, std::uint32_t& components,
                                  std::string& unit) {
  wire::Request r = request(Op::property_info);
  r.fields().put(index);
  Reply reply = send(r);
  reply.in(name, components, unit);
}

void RemoteBackend::get_property(std::uint32_t index, double* values, std::uint64_t count) {
  wire::Request r = request(Op::get_property);
  r.fields().put(index);
  r.output(count > 0 ? values : nullptr, count);
  Reply reply = send(r);
  r.read_outputs(reply.in);
}

void RemoteBackend::set_property(std::uint32_t index, const double* values, std::uint64_t count) {
  wire::Request r = request(Op::set_property);
  r.fields().put(index);
  r.input(count > 0 ? values : nullptr, count);
  send(r);
}

quarry_view RemoteBackend::view_property(std::uint32_t index) {
  if (auto view = shared_view(Op::view_property_shared, index)) return *view;
  wire::Request r = request(Op::view_property);
  r.fields().put(index);
  Reply reply = send(r);
  return read_view(reply.in, property_views_[index]);
}

void RemoteBackend::sample_points(std::uint32_t type, std::uint32_t points, std::uint64_t seed,
                                  double* unit_points) {
  wire::Request r = request(Op::sample_points);
  r.fields()(type, points, seed);
  r.output(unit_points, 3 * std::uint64_t{points});
  Reply reply = send(r);
  r.read_outputs(reply.in);
}

std::uint64_t RemoteBackend::sample_point_positions(std::uint32_t type, std::uint32_t points,
                                                    std::uint64_t seed, double* positions,
                                                    std::uint64_t capacity) {
  wire::Request r = request(Op::sample_point_positions);
  r.fields()(type, points, seed);
  r.output(capacity > 0 ? positions : nullptr, capacity);
  Reply reply = send(r);
  const auto particles = reply.in.get<std::uint64_t>();
  r.read_outputs(reply.in);
  return particles;
}

std::uint32_t RemoteBackend::add_surface(const quarry_surface_desc& d) {
  wire::Request r = request(Op::add_surface);
  r.fields()(d.name, d.material, d.node_count);
  r.input(d.nodes, 3 * d.node_count);
  r.fields().put(d.triangle_count);
  r.input(d.triangles, 3 * d.triangle_count);
  r.fields().put(d.quad_count);
  r.input(d.quads, 4 * d.quad_count);
  r.fields().put(d.driver);
  Reply reply = send(r);
  return reply.in.get<std::uint32_t>();
}

void RemoteBackend::set_surface_nodes(std::uint32_t surface, const double* positions,
                                      const double* velocities, std::uint64_t count) {
  wire::Request r = request(Op::set_surface_nodes);
  r.fields().put(surface);
  r.input(positions, 3 * count);
  r.input(velocities, vectors(velocities, count));
  r.fields().put(count);
  send(r);
}

void RemoteBackend::get_surface_nodes(std::uint32_t surface, double* positions, double* velocities,
                                      std::uint64_t count) {
  wire::Request r = request(Op::get_surface_nodes);
  r.fields().put(surface);
  r.output(positions, vectors(positions, count));
  r.output(velocities, vectors(velocities, count));
  r.fields().put(count);
  Reply reply = send(r);
  r.read_outputs(reply.in);
}

void RemoteBackend::get_surface_loads(std::uint32_t surface, quarry_surface_loads& loads) {
  wire::Request r = request(Op::get_surface_loads);
  r.fields()(surface, loads.node_count, loads.element_count);
  r.output(loads.nodal_force, vectors(loads.nodal_force, loads.node_count));
  r.output(loads.pressure, loads.pressure ? loads.element_count : 0);
  r.output(loads.shear_stress, vectors(loads.shear_stress, loads.element_count));
  r.output(loads.element_force, vectors(loads.element_force, loads.element_count));
  Reply reply = send(r);
  reply.in(loads.window, loads.time);
  r.read_outputs(reply.in);
}

}  // namespace

std::unique_ptr<Backend> open_remote(const quarry_open_info& info) {
  check_endpoint(info.endpoint, "quarry_open");
  return std::make_unique<RemoteBackend>(info);
}

}  // namespace quarry::api
