// The framing of `quarry serve`'s messages (one ZeroMQ frame each way, REQ/REP): a fixed header,
// then the operation's fields, little-endian. Arrays travel in the message or, when client and
// server share a host, in the client's shared-memory segment (only offset and count here).
// Reader never reads past the message and never allocates more than the message could hold.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <deque>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "quarry/quarry.h"

namespace quarry::api::wire {

// The framing writes the machine's bytes as they are: it is defined little-endian, so a
// big-endian port would swap in Writer::put / Reader::get and in the array copies.
static_assert(std::endian::native == std::endian::little, "the wire framing is little-endian");

// "QRYW" as the first four bytes. The first 8 bytes (magic, ABI version) of a request and of a
// reply keep this layout in every ABI major, so that any two versions can tell they differ.
inline constexpr std::uint32_t kMagic = 0x57595251;

// Request: magic u32, abi_version u32, operation u32, reserved u32 (0), request_id u64,
// session u64, payload_length u64; then the payload.
inline constexpr std::size_t kRequestHeaderBytes = 40;
// Reply: magic u32, abi_version u32, status i32, error_length u32, request_id u64,
// payload_length u64; then the error text (UTF-8, no NUL), then the payload.
inline constexpr std::size_t kReplyHeaderBytes = 32;
// The largest message either side accepts (bytes): a request or a reply over it is refused.
inline constexpr std::uint64_t kMaxMessageBytes = std::uint64_t{1} << 31;

// One operation per Backend call (api/backend.h); the values are part of the ABI major.
enum class Op : std::uint32_t {
  open = 1,
  close,
  set_settings,
  add_material,
  add_interaction,
  add_particle_type,
  start,
  get_time,
  advance,
  step,
  save_checkpoint,
  save_state,
  restore_state,
  num_types,
  type_name,
  num_particles,
  epoch,
  get_particles,
  particle_index,
  view_particles,
  add_particles,
  remove_particles,
  set_external_loads,
  set_external_loads_by_id,
  clear_external_loads,
  register_property,
  num_properties,
  property_info,
  get_property,
  set_property,
  view_property,
  sample_points,
  sample_point_positions,
  add_surface,
  num_surfaces,
  find_surface,
  surface_info,
  set_surface_driver,
  set_surface_nodes,
  get_surface_nodes,
  get_surface_loads,
  // Views written into a shared-memory segment of the client's own for that view (ipc with
  // shared memory only). The open reply names the last operation a server knows: a client asks
  // these, and the channel, only of a server that names them; others send views in the replies.
  view_particles_shared,
  view_property_shared,
  // The client's request channel (api/channel.h) for the session's further requests (ipc with
  // shared memory only; without it, the socket carries them).
  attach_channel,
  // ABI 1.2: the next step's external loads as a view (a copy on the client, written there) and
  // that copy sent back before the client's next call that is not a view.
  view_next_step_loads,
  put_next_step_loads,
  // The same through a shared-memory segment of the client's own for each field (ipc with shared
  // memory only): the server writes the loads there, the client writes its values over them,
  // and the server takes them back from there.
  view_next_step_loads_shared,
  put_next_step_loads_shared,
};
// The key of a shared view's segment in a session, on both sides: the operation (particles or
// property) and which field or property.
inline constexpr std::uint64_t view_key(Op op, std::uint32_t which) {
  return (static_cast<std::uint64_t>(op) << 32) | which;
}
inline constexpr std::uint32_t kFirstOp = static_cast<std::uint32_t>(Op::open);
inline constexpr std::uint32_t kLastOp = static_cast<std::uint32_t>(Op::put_next_step_loads_shared);

// The C function an operation stands for ("quarry_get_particles"), or nullptr if unknown.
const char* op_name(std::uint32_t op);

struct RequestHeader {
  std::uint32_t abi_version = QUARRY_ABI_VERSION;
  std::uint32_t op = 0;
  std::uint64_t request_id = 0;
  std::uint64_t session = 0;
  std::uint64_t payload_length = 0;
};

struct ReplyHeader {
  std::uint32_t abi_version = QUARRY_ABI_VERSION;
  std::int32_t status = QUARRY_OK;
  std::uint64_t request_id = 0;
  std::uint32_t error_length = 0;
  std::uint64_t payload_length = 0;
};

// A message that does not follow the framing: what is wrong and at which byte.
class WireError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where an array travels.
enum class Place : std::uint8_t {
  none = 0,     // not given (a NULL pointer)
  message = 1,  // its bytes follow in this message (inputs) or come back in the reply (outputs)
  shared = 2,   // in the session's shared-memory segment at an offset
};

// A mapped shared-memory segment as the reader sees it; `grown` re-maps it when an array reaches
// past the mapped size (the client grows the segment in place) and says whether it now fits.
struct SegmentView {
  std::byte* data = nullptr;
  std::uint64_t size = 0;
  bool (*grown)(void* owner, std::uint64_t needed, SegmentView& view) = nullptr;
  void* owner = nullptr;
};

// Appends fields to a message.
class Writer {
 public:
  template <class T>
  requires std::is_arithmetic_v<T> || std::is_enum_v<T>
  void put(T value) {
    const std::size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &value, sizeof(T));
  }
  void put(const double (&vector)[3]) { raw(vector, sizeof vector); }
  // u32 length, then the bytes.
  void text(std::string_view text);
  // u8 present (0/1), then the text if present.
  void optional_text(const char* text);
  void raw(const void* data, std::size_t size);
  // Room for `size` bytes at the end, to be filled by the caller.
  std::byte* extend(std::size_t size);
  // Zero bytes up to a multiple of 8 from the message's start, so that arrays in it are aligned.
  void align();

  // Variadic form used by the struct field lists (api/protocol.h).
  template <class... T>
  void operator()(const T&... values) {
    (field(values), ...);
  }

  std::string& bytes() { return bytes_; }
  const std::string& bytes() const { return bytes_; }

 private:
  template <class T>
  void field(const T& value) {
    put(value);
  }
  template <class T, std::size_t N>
  void field(const T (&values)[N]) {  // a fixed array: its elements in order
    for (const T& value : values) put(value);
  }
  void field(const char* const& text) { optional_text(text); }
  void field(const std::string& text) { this->text(text); }
  std::string bytes_;
};

// Memory for the outputs a reply carries, kept from request to request (a request's k-th output
// uses slot k): a partner asks for the same arrays every step, and fresh ones of megabytes would
// be mapped and faulted in every time.
class OutputSlots {
 public:
  std::byte* get(std::size_t k, std::size_t bytes);

 private:
  struct Slot {
    std::unique_ptr<std::byte[]> data;
    std::size_t size = 0;
  };
  std::vector<Slot> slots_;
};

// An array a request names as an output: where the server writes it.
struct OutputArray {
  std::byte* data = nullptr;  // nullptr: not wanted
  std::uint64_t count = 0;    // elements the caller has room for
  std::uint64_t used = 0;     // elements to send back (set by the handler; starts at count)
  std::size_t element_bytes = 0;
  bool in_message = false;  // comes back in the reply (else it is in shared memory)
  std::unique_ptr<std::byte[]> storage;
};

// The client's side of its shared-memory segment: room for `bytes` (the segment grows when it
// must), at an offset aligned to 64 bytes, and the address of an offset.
class SegmentSpace {
 public:
  virtual ~SegmentSpace() = default;
  virtual std::uint64_t allocate(std::uint64_t bytes) = 0;
  virtual std::byte* at(std::uint64_t offset) = 0;
};

// A request as the client builds it: the header, the fields, and arrays placed in the message
// or (at or above `shared_from` bytes, when there is a segment) in the segment. After the reply,
// read_outputs copies the output arrays to the caller's memory.
class Request {
 public:
  Request(Op op, SegmentSpace* segment, std::uint64_t shared_from = 4096);
  Writer& fields() { return writer_; }
  template <class T>
  void input(const T* data, std::uint64_t count) {
    input_bytes(data, count, sizeof(T));
  }
  template <class T>
  void output(T* data, std::uint64_t count) {
    output_bytes(data, count, sizeof(T));
  }
  // The finished message (header lengths filled in).
  std::string& message(std::uint64_t request_id, std::uint64_t session);
  // Reads, after the reply's own fields, each output's count and bytes; returns the counts.
  std::vector<std::uint64_t> read_outputs(class Reader& reply);
  Op op() const { return op_; }

 private:
  void input_bytes(const void* data, std::uint64_t count, std::size_t element);
  void output_bytes(void* data, std::uint64_t count, std::size_t element);
  bool shared(std::uint64_t count, std::size_t element) const;
  struct Pending {
    std::byte* data;
    std::uint64_t count;
    std::size_t element;
    bool in_message;
    std::uint64_t offset;
  };
  Op op_;
  SegmentSpace* segment_;
  std::uint64_t shared_from_;
  Writer writer_;
  std::vector<Pending> outputs_;
};

// Reads fields from one message, bounds-checked: every read that would pass the end throws
// WireError, and an array's length is checked against the bytes left before anything is made.
class Reader {
 public:
  // Reads message[start, size); alignment (align, arrays) counts from the message's first byte.
  // Outputs for the reply go into `slots` if given (else into memory of this reader's own).
  Reader(const void* message, std::size_t size, std::size_t start, SegmentView* segment = nullptr,
         OutputSlots* slots = nullptr)
      : data_(static_cast<const std::byte*>(message)),
        size_(size),
        at_(start),
        segment_(segment),
        slots_(slots) {}

  template <class T>
  requires std::is_arithmetic_v<T> || std::is_enum_v<T> T get() {
    T value;
    std::memcpy(&value, take(sizeof(T), "a number"), sizeof(T));
    return value;
  }
  void get(double (&vector)[3]) {
    std::memcpy(vector, take(sizeof vector, "a vector"), sizeof vector);
  }
  std::string text();
  // nullptr if absent; else a NUL-terminated copy that lives as long as the reader.
  const char* optional_text();
  std::span<const std::byte> raw(std::size_t size);
  void align();

  // An input array of T: nullptr with count 0 for Place::none. Points into the message or the
  // segment when aligned, else into a copy held by the reader.
  template <class T>
  const T* input(std::uint64_t& count) {
    return static_cast<const T*>(input_bytes(sizeof(T), alignof(T), count));
  }
  // An output array of T: where the handler writes (nullptr: not wanted). Message outputs are
  // kept by the reader until the reply is written (write_outputs).
  template <class T>
  T* output(std::uint64_t& count) {
    return reinterpret_cast<T*>(output_bytes(sizeof(T), alignof(T), count));
  }
  // Sets how many elements of the k-th output array (in request order, absent ones counted) go
  // back; ignored for an absent one.
  void set_used(std::size_t k, std::uint64_t used);
  std::size_t outputs() const { return outputs_.size(); }
  // Appends the message outputs to a reply: for each, u64 count then its bytes (aligned).
  void write_outputs(Writer& reply) const;

  std::size_t remaining() const { return size_ - at_; }
  std::size_t position() const { return at_; }
  // The ABI version in the header of the message being read (its sender's; 0 when the bytes
  // from the first on are not a Quarry message): which fields a struct of it carries.
  std::uint32_t abi_version() const;
  // Throws unless every byte was read.
  void expect_end() const;

  template <class... T>
  void operator()(T&... values) {
    (field(values), ...);
  }

 private:
  template <class T>
  void field(T& value) {
    value = get<T>();
  }
  template <class T, std::size_t N>
  void field(T (&values)[N]) {
    for (T& value : values) value = get<T>();
  }
  void field(double (&vector)[3]) { get(vector); }
  void field(const char*& text) { text = optional_text(); }
  void field(std::string& text) { text = this->text(); }
  const std::byte* take(std::size_t size, const char* what);
  const void* input_bytes(std::size_t element, std::size_t alignment, std::uint64_t& count);
  std::byte* output_bytes(std::size_t element, std::size_t alignment, std::uint64_t& count);
  std::byte* in_segment(std::uint64_t offset, std::uint64_t count, std::size_t element,
                        std::size_t alignment);

  const std::byte* data_;
  std::size_t size_;
  std::size_t at_;
  SegmentView* segment_;
  OutputSlots* slots_;
  std::deque<std::string> texts_;                     // optional_text copies
  std::vector<std::unique_ptr<std::byte[]>> copies_;  // unaligned input arrays
  std::vector<OutputArray> outputs_;
};

// Headers. write_* put one at the start of a message whose payload is already written (the
// length fields come from the message's size); read_* throw WireError, naming what is wrong, for
// a short message, another magic, or lengths that are not the message's.
void write_request_header(std::string& message, const RequestHeader& header);
void write_reply_header(std::string& message, const ReplyHeader& header);
RequestHeader read_request_header(const void* data, std::size_t size);
ReplyHeader read_reply_header(const void* data, std::size_t size);
// The ABI version in any message's bytes 4..7 (0 if shorter than 8 bytes or not a Quarry one).
std::uint32_t message_abi_version(const void* data, std::size_t size);

// A whole reply: header, error text, payload.
std::string error_reply(std::uint64_t request_id, quarry_status status, std::string_view text);

// "1.0" for (1 << 16) | 0.
std::string version_text(std::uint32_t abi_version);

}  // namespace quarry::api::wire
