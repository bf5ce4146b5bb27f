// The framing of `quarry serve`'s messages (api/wire.h): headers, fields, and arrays in the
// message or in shared memory, with every length checked against what the message holds.
#include "api/wire.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <limits>

namespace quarry::api::wire {

namespace {

constexpr std::array<const char*, kLastOp + 1> kOpNames = {
    nullptr,
    "quarry_open",
    "quarry_close",
    "quarry_set_settings",
    "quarry_add_material",
    "quarry_add_interaction",
    "quarry_add_particle_type",
    "quarry_start",
    "quarry_get_time",
    "quarry_advance",
    "quarry_step",
    "quarry_save_checkpoint",
    "quarry_save_state",
    "quarry_restore_state",
    "quarry_num_types",
    "quarry_type_name",
    "quarry_num_particles",
    "quarry_epoch",
    "quarry_get_particles",
    "quarry_particle_index",
    "quarry_view_particles",
    "quarry_add_particles",
    "quarry_remove_particles",
    "quarry_set_external_loads",
    "quarry_set_external_loads_by_id",
    "quarry_clear_external_loads",
    "quarry_register_property",
    "quarry_num_properties",
    "quarry_property_info",
    "quarry_get_property",
    "quarry_set_property",
    "quarry_view_property",
    "quarry_sample_points",
    "quarry_sample_point_positions",
    "quarry_add_surface",
    "quarry_num_surfaces",
    "quarry_find_surface",
    "quarry_get_surface_info",
    "quarry_set_surface_driver",
    "quarry_set_surface_nodes",
    "quarry_get_surface_nodes",
    "quarry_get_surface_loads",
    "quarry_view_particles",
    "quarry_view_property",
    "quarry_open",  // the request channel, attached right after the open
    "quarry_view_next_step_loads",
    "quarry_view_next_step_loads",  // its values sent back before the next call
    "quarry_view_next_step_loads",  // in shared memory
    "quarry_view_next_step_loads",  // sent back from shared memory
};

template <class T>
void store(std::string& message, std::size_t at, T value) {
  std::memcpy(message.data() + at, &value, sizeof(T));
}

template <class T>
T load(const std::byte* data, std::size_t at) {
  T value;
  std::memcpy(&value, data + at, sizeof(T));
  return value;
}

// Checks the parts every header shares: long enough for magic and version, and the magic.
void check_magic(const std::byte* data, std::size_t size, std::size_t header_bytes,
                 const char* what) {
  if (size < 8)
    throw WireError(
        fmt::format("a message of {} bytes is too short for a Quarry {} ({} bytes of header)", size,
                    what, header_bytes));
  const auto magic = load<std::uint32_t>(data, 0);
  if (magic != kMagic)
    throw WireError(
        fmt::format("not a Quarry {}: its first 4 bytes are {:#010x}, not the magic {:#010x} "
                    "(is the other side a Quarry client and server?)",
                    what, magic, kMagic));
  if (size < header_bytes)
    throw WireError(fmt::format("a {} of {} bytes is shorter than its {}-byte header", what, size,
                                header_bytes));
}

// count × element in bytes, refused (not wrapped) when it cannot be.
std::uint64_t array_bytes(std::uint64_t count, std::size_t element, std::uint64_t limit,
                          const char* where) {
  if (count > limit / element)
    throw WireError(fmt::format(
        "{}: an array of {} elements of {} bytes is longer than the {} bytes it may have", where,
        count, element, limit));
  return count * element;
}

}  // namespace

const char* op_name(std::uint32_t op) {
  return op >= kFirstOp && op <= kLastOp ? kOpNames[op] : nullptr;
}

std::string version_text(std::uint32_t abi_version) {
  return fmt::format("{}.{}", abi_version >> 16, abi_version & 0xffffu);
}

// ---- Writer ----

void Writer::text(std::string_view text) {
  if (text.size() > std::numeric_limits<std::uint32_t>::max())
    throw WireError(
        fmt::format("a text of {} bytes is longer than a message may carry", text.size()));
  put(static_cast<std::uint32_t>(text.size()));
  raw(text.data(), text.size());
}

void Writer::optional_text(const char* text) {
  put(static_cast<std::uint8_t>(text != nullptr));
  if (text) this->text(text);
}

void Writer::raw(const void* data, std::size_t size) {
  if (size > 0) bytes_.append(static_cast<const char*>(data), size);
}

std::byte* Writer::extend(std::size_t size) {
  const std::size_t at = bytes_.size();
  bytes_.resize(at + size);
  return reinterpret_cast<std::byte*>(bytes_.data() + at);
}

void Writer::align() {
  bytes_.resize((bytes_.size() + 7) / 8 * 8, '\0');
}

// ---- Reader ----

const std::byte* Reader::take(std::size_t size, const char* what) {
  if (size > size_ - at_)
    throw WireError(fmt::format("the message ends at byte {}, inside {} ({} bytes from byte {})",
                                size_, what, size, at_));
  const std::byte* at = data_ + at_;
  at_ += size;
  return at;
}

std::string Reader::text() {
  const auto length = get<std::uint32_t>();
  const std::byte* bytes = take(length, "a text");
  return std::string(reinterpret_cast<const char*>(bytes), length);
}

const char* Reader::optional_text() {
  const auto present = get<std::uint8_t>();
  if (present > 1)
    throw WireError(
        fmt::format("byte {}: a text's presence flag is {}, not 0 or 1", at_ - 1, present));
  if (!present) return nullptr;
  texts_.push_back(text());
  return texts_.back().c_str();
}

std::span<const std::byte> Reader::raw(std::size_t size) {
  return {take(size, "raw bytes"), size};
}

void Reader::align() {
  const std::size_t padding = (8 - at_ % 8) % 8;
  take(padding, "the padding before an array");
}

std::byte* Reader::in_segment(std::uint64_t offset, std::uint64_t count, std::size_t element,
                              std::size_t alignment) {
  if (!segment_ || !segment_->data)
    throw WireError(
        fmt::format("byte {}: an array in shared memory, but this session has no segment", at_));
  if (offset % alignment != 0)
    throw WireError(fmt::format("byte {}: a shared array at offset {} is not aligned to {} bytes",
                                at_, offset, alignment));
  const std::uint64_t bytes =
      array_bytes(count, element, std::numeric_limits<std::uint64_t>::max(), "shared memory");
  const bool fits = offset <= segment_->size && bytes <= segment_->size - offset;
  if (!fits && !(segment_->grown && segment_->grown(segment_->owner, offset + bytes, *segment_) &&
                 offset <= segment_->size && bytes <= segment_->size - offset))
    throw WireError(fmt::format(
        "byte {}: a shared array of {} bytes at offset {} passes the segment's end ({} bytes)", at_,
        bytes, offset, segment_->size));
  return segment_->data + offset;
}

const void* Reader::input_bytes(std::size_t element, std::size_t alignment, std::uint64_t& count) {
  const auto place = get<std::uint8_t>();
  count = 0;
  switch (static_cast<Place>(place)) {
    case Place::none:
      return nullptr;
    case Place::message: {
      count = get<std::uint64_t>();
      align();
      const std::uint64_t bytes = array_bytes(count, element, remaining(), "message");
      const std::byte* at = take(bytes, "an array");
      if (reinterpret_cast<std::uintptr_t>(at) % alignment == 0) return at;
      copies_.push_back(std::make_unique_for_overwrite<std::byte[]>(bytes));
      std::memcpy(copies_.back().get(), at, bytes);
      return copies_.back().get();
    }
    case Place::shared: {
      count = get<std::uint64_t>();
      const auto offset = get<std::uint64_t>();
      return in_segment(offset, count, element, alignment);
    }
  }
  throw WireError(fmt::format(
      "byte {}: an array's place is {}, not 0 (none), 1 (message) or 2 (shared)", at_ - 1, place));
}

std::byte* Reader::output_bytes(std::size_t element, std::size_t alignment, std::uint64_t& count) {
  const auto place = get<std::uint8_t>();
  count = 0;
  OutputArray out;
  out.element_bytes = element;
  switch (static_cast<Place>(place)) {
    case Place::none:
      break;
    case Place::message: {
      count = get<std::uint64_t>();
      // What the reply may carry: the message limit less what the other outputs take.
      std::uint64_t taken = 0;
      for (const OutputArray& o : outputs_) taken += o.in_message ? o.count * o.element_bytes : 0;
      const std::uint64_t bytes = array_bytes(count, element, kMaxMessageBytes - taken, "reply");
      if (slots_) {
        out.data = slots_->get(outputs_.size(), bytes);
      } else {
        out.storage =
            std::make_unique_for_overwrite<std::byte[]>(bytes);  // untouched until written
        out.data = out.storage.get();
      }
      out.in_message = true;
      break;
    }
    case Place::shared: {
      count = get<std::uint64_t>();
      const auto offset = get<std::uint64_t>();
      out.data = in_segment(offset, count, element, alignment);
      break;
    }
    default:
      throw WireError(fmt::format(
          "byte {}: an output array's place is {}, not 0 (none), 1 (message) or 2 (shared)",
          at_ - 1, place));
  }
  out.count = out.used = count;
  outputs_.push_back(std::move(out));
  return outputs_.back().data;
}

void Reader::set_used(std::size_t k, std::uint64_t used) {
  if (k < outputs_.size() && !outputs_[k].data) return;
  if (k >= outputs_.size() || used > outputs_[k].count)
    throw std::logic_error(
        fmt::format("output {} of {}: {} elements used", k, outputs_.size(), used));
  outputs_[k].used = used;
}

std::byte* OutputSlots::get(std::size_t k, std::size_t bytes) {
  if (slots_.size() <= k) slots_.resize(k + 1);
  Slot& slot = slots_[k];
  if (slot.size < bytes || !slot.data) {
    slot.data = std::make_unique_for_overwrite<std::byte[]>(std::max<std::size_t>(bytes, 1));
    slot.size = bytes;
  }
  return slot.data.get();
}

void Reader::write_outputs(Writer& reply) const {
  std::size_t bytes = reply.bytes().size();
  // Arrays in shared memory take 8 bytes of the reply (their count), not their size: reserving
  // that too made every reply of a large get a fresh mapping of megabytes, zeroed by the kernel.
  for (const OutputArray& o : outputs_) bytes += o.data ? 16 + (o.in_message ? o.used * o.element_bytes : 0) : 0;
  reply.bytes().reserve(bytes);  // one allocation for the whole reply
  for (const OutputArray& o : outputs_) {
    if (!o.data) continue;  // absent: the client expects nothing for it
    reply.put(o.used);
    if (!o.in_message) continue;
    reply.align();
    reply.raw(o.data, o.used * o.element_bytes);
  }
}

void Reader::expect_end() const {
  if (at_ != size_)
    throw WireError(
        fmt::format("{} bytes follow the last field (byte {} of {})", size_ - at_, at_, size_));
}

// ---- Request ----

Request::Request(Op op, SegmentSpace* segment, std::uint64_t shared_from)
    : op_(op), segment_(segment), shared_from_(shared_from) {
  writer_.bytes().assign(kRequestHeaderBytes, '\0');
}

bool Request::shared(std::uint64_t count, std::size_t element) const {
  return segment_ && count * element >= shared_from_;
}

void Request::input_bytes(const void* data, std::uint64_t count, std::size_t element) {
  if (!data) return writer_.put(Place::none);
  const std::uint64_t bytes = count * element;
  if (shared(count, element)) {
    const std::uint64_t offset = segment_->allocate(bytes);
    std::memcpy(segment_->at(offset), data, bytes);
    writer_.put(Place::shared);
    writer_.put(count);
    writer_.put(offset);
    return;
  }
  writer_.put(Place::message);
  writer_.put(count);
  writer_.align();
  writer_.raw(data, bytes);
}

void Request::output_bytes(void* data, std::uint64_t count, std::size_t element) {
  if (!data) return writer_.put(Place::none);
  Pending pending{static_cast<std::byte*>(data), count, element, true, 0};
  if (shared(count, element)) {
    pending.in_message = false;
    pending.offset = segment_->allocate(count * element);
    writer_.put(Place::shared);
    writer_.put(count);
    writer_.put(pending.offset);
  } else {
    writer_.put(Place::message);
    writer_.put(count);
  }
  outputs_.push_back(pending);
}

std::string& Request::message(std::uint64_t request_id, std::uint64_t session) {
  RequestHeader header;
  header.op = static_cast<std::uint32_t>(op_);
  header.request_id = request_id;
  header.session = session;
  write_request_header(writer_.bytes(), header);
  return writer_.bytes();
}

std::vector<std::uint64_t> Request::read_outputs(Reader& reply) {
  std::vector<std::uint64_t> used;
  for (const Pending& o : outputs_) {
    const auto n = reply.get<std::uint64_t>();
    if (n > o.count)
      throw WireError(
          fmt::format("the reply sends {} elements back into an array of {}", n, o.count));
    const std::size_t bytes = n * o.element;
    if (o.in_message) {
      reply.align();
      std::memcpy(o.data, reply.raw(bytes).data(), bytes);
    } else if (bytes > 0) {
      std::memcpy(o.data, segment_->at(o.offset), bytes);
    }
    used.push_back(n);
  }
  return used;
}

// ---- headers ----

void write_request_header(std::string& message, const RequestHeader& header) {
  if (message.size() < kRequestHeaderBytes) message.resize(kRequestHeaderBytes, '\0');
  store(message, 0, kMagic);
  store(message, 4, header.abi_version);
  store(message, 8, header.op);
  store(message, 12, std::uint32_t{0});
  store(message, 16, header.request_id);
  store(message, 24, header.session);
  store(message, 32, static_cast<std::uint64_t>(message.size() - kRequestHeaderBytes));
}

void write_reply_header(std::string& message, const ReplyHeader& header) {
  if (message.size() < kReplyHeaderBytes + header.error_length)
    throw std::logic_error("a reply shorter than its header and error text");
  store(message, 0, kMagic);
  store(message, 4, header.abi_version);
  store(message, 8, header.status);
  store(message, 12, header.error_length);
  store(message, 16, header.request_id);
  store(message, 24,
        static_cast<std::uint64_t>(message.size() - kReplyHeaderBytes - header.error_length));
}

std::uint32_t message_abi_version(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::byte*>(data);
  if (size < 8 || load<std::uint32_t>(bytes, 0) != kMagic) return 0;
  return load<std::uint32_t>(bytes, 4);
}

std::uint32_t Reader::abi_version() const {
  return message_abi_version(data_, size_);
}

RequestHeader read_request_header(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::byte*>(data);
  check_magic(bytes, size, kRequestHeaderBytes, "request");
  RequestHeader header;
  header.abi_version = load<std::uint32_t>(bytes, 4);
  header.op = load<std::uint32_t>(bytes, 8);
  header.request_id = load<std::uint64_t>(bytes, 16);
  header.session = load<std::uint64_t>(bytes, 24);
  header.payload_length = load<std::uint64_t>(bytes, 32);
  if (header.payload_length != size - kRequestHeaderBytes)
    throw WireError(
        fmt::format("the request header announces {} payload bytes, the message carries {}",
                    header.payload_length, size - kRequestHeaderBytes));
  return header;
}

ReplyHeader read_reply_header(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::byte*>(data);
  check_magic(bytes, size, kReplyHeaderBytes, "reply");
  ReplyHeader header;
  header.abi_version = load<std::uint32_t>(bytes, 4);
  header.status = load<std::int32_t>(bytes, 8);
  header.error_length = load<std::uint32_t>(bytes, 12);
  header.request_id = load<std::uint64_t>(bytes, 16);
  header.payload_length = load<std::uint64_t>(bytes, 24);
  const std::uint64_t rest = size - kReplyHeaderBytes;
  if (header.error_length > rest || header.payload_length != rest - header.error_length)
    throw WireError(fmt::format(
        "the reply header announces {} bytes of error text and {} of payload, the message "
        "carries {} after its header",
        header.error_length, header.payload_length, rest));
  return header;
}

std::string error_reply(std::uint64_t request_id, quarry_status status, std::string_view text) {
  std::string message(kReplyHeaderBytes, '\0');
  message.append(text);
  ReplyHeader header;
  header.status = status;
  header.request_id = request_id;
  header.error_length = static_cast<std::uint32_t>(text.size());
  write_reply_header(message, header);
  return message;
}

}  // namespace quarry::api::wire
