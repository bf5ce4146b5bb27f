// The framing of `quarry serve`'s messages (api/wire.h): round trips of headers, fields and
// arrays (in the message and in shared memory), a reader that stops with WireError at every byte
// a message can be cut at (run under ASan: no read past the buffer), and lengths it refuses
// before allocating.
#include "api/wire.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "api/protocol.h"

namespace quarry::api::wire {
namespace {

// A segment in ordinary memory: the client's allocator and the server's view over the same bytes.
class FakeSegment final : public SegmentSpace {
 public:
  explicit FakeSegment(std::size_t size) : bytes_(size) {
    view_ = SegmentView{bytes_.data(), bytes_.size(), nullptr, nullptr};
  }
  std::uint64_t allocate(std::uint64_t bytes) override {
    const std::uint64_t offset = (next_ + 63) / 64 * 64;
    next_ = offset + bytes;
    if (next_ > bytes_.size()) throw std::runtime_error("fake segment full");
    return offset;
  }
  std::byte* at(std::uint64_t offset) override { return bytes_.data() + offset; }
  SegmentView& view() { return view_; }

 private:
  std::vector<std::byte> bytes_;
  std::uint64_t next_ = 0;
  SegmentView view_;
};

// A copy of the first `size` bytes on the heap, exactly that long (ASan sees any read past it).
std::vector<std::byte> cut(const std::string& message, std::size_t size) {
  std::vector<std::byte> bytes(size);
  if (size > 0) std::memcpy(bytes.data(), message.data(), size);
  return bytes;
}

quarry_settings example_settings() {
  quarry_settings s = {};
  s.time_step = 1e-5, s.rayleigh_fraction = 0.2, s.gravity[2] = -9.81;
  s.domain_min[0] = -1.5, s.domain_max[2] = 2.25, s.end_time = 3.0, s.impact_speed = 0.5,
  s.skin = -1.0;
  s.integrator = QUARRY_INTEGRATOR_SYMPLECTIC_EULER, s.sort_interval = 25,
  s.max_overlap_fraction = 0.1;
  s.seed = 0xfedcba9876543210ull;
  s.periodic[0] = 1, s.periodic[2] = 1;
  return s;
}

// A request with every kind of field: numbers, a struct with texts, arrays in and out.
struct Example {
  std::vector<double> force{1.5, -2.0, 3.25, 4.0, 5.0, 6.0};
  std::vector<std::uint32_t> types{0, 1};
  std::vector<double> positions = std::vector<double>(6, -1.0);
  quarry_material material{sizeof(quarry_material), "ore", 2500.0, 1e6, 0.3};
};

Request example(Example& e, SegmentSpace* segment, std::uint64_t shared_from) {
  Request r(Op::add_particles, segment, shared_from);
  r.fields().put(std::uint64_t{2});
  protocol::fields(r.fields(), e.material);
  r.input(e.force.data(), e.force.size());
  r.input<double>(nullptr, 0);
  r.input(e.types.data(), e.types.size());
  r.output(e.positions.data(), e.positions.size());
  r.fields().text("end");
  return r;
}

std::string example_request(Example& e, SegmentSpace* segment, std::uint64_t shared_from) {
  return example(e, segment, shared_from).message(7, 99);
}

// What example_request wrote, read back without judging it.
struct Parsed {
  std::uint64_t count = 0;
  quarry_material material{};
  const double* force = nullptr;
  const double* none = nullptr;
  const std::uint32_t* types = nullptr;
  double* out = nullptr;
  std::uint64_t n_force = 0, n_none = 7, n_types = 0, n_out = 0;
  std::string end;
};
Parsed parse_example(Reader& in) {
  Parsed p;
  p.count = in.get<std::uint64_t>();
  p.material = protocol::read<quarry_material>(in);
  p.force = in.input<double>(p.n_force);
  p.none = in.input<double>(p.n_none);
  p.types = in.input<std::uint32_t>(p.n_types);
  p.out = in.output<double>(p.n_out);
  p.end = in.text();
  in.expect_end();
  return p;
}

// Reads what example_request wrote and checks it; fills the output with 10, 11, ...
void read_example(Reader& in) {
  const Parsed p = parse_example(in);
  EXPECT_EQ(p.count, 2u);
  EXPECT_STREQ(p.material.name, "ore");
  EXPECT_EQ(p.material.density, 2500.0);
  EXPECT_EQ(p.none, nullptr);
  EXPECT_EQ(p.n_none, 0u);
  EXPECT_EQ(p.end, "end");
  ASSERT_EQ(p.n_force, 6u);
  ASSERT_EQ(p.n_types, 2u);
  ASSERT_EQ(p.n_out, 6u);
  EXPECT_EQ(p.force[0], 1.5);
  EXPECT_EQ(p.force[5], 6.0);
  EXPECT_EQ(p.types[1], 1u);
  for (int k = 0; k < 6; ++k) p.out[k] = 10.0 + k;
  in.set_used(0, 4);  // only four come back
}

TEST(Wire, RequestHeaderRoundTrip) {
  std::string message(kRequestHeaderBytes, '\0');
  message += "payload";
  RequestHeader header;
  header.op = static_cast<std::uint32_t>(Op::get_particles);
  header.request_id = 0x0102030405060708ull;
  header.session = 42;
  write_request_header(message, header);
  const RequestHeader read = read_request_header(message.data(), message.size());
  EXPECT_EQ(read.abi_version, QUARRY_ABI_VERSION);
  EXPECT_EQ(read.op, header.op);
  EXPECT_EQ(read.request_id, header.request_id);
  EXPECT_EQ(read.session, 42u);
  EXPECT_EQ(read.payload_length, 7u);
  EXPECT_EQ(message_abi_version(message.data(), message.size()), QUARRY_ABI_VERSION);
  // Little-endian on the wire: the magic's first byte is 'Q'.
  EXPECT_EQ(message[0], 'Q');
  EXPECT_EQ(message[3], 'W');
}

TEST(Wire, ReplyRoundTripWithErrorText) {
  const std::string reply =
      error_reply(9, QUARRY_ERROR_NOT_FOUND, "quarry_find_surface: no surface is named 'x'");
  const ReplyHeader header = read_reply_header(reply.data(), reply.size());
  EXPECT_EQ(header.status, QUARRY_ERROR_NOT_FOUND);
  EXPECT_EQ(header.request_id, 9u);
  EXPECT_EQ(header.payload_length, 0u);
  EXPECT_EQ(reply.substr(kReplyHeaderBytes, header.error_length),
            "quarry_find_surface: no surface is named 'x'");
}

TEST(Wire, StructFieldsRoundTrip) {
  const quarry_settings settings = example_settings();
  Writer out;
  protocol::fields(out, settings);
  Reader in(out.bytes().data(), out.bytes().size(), 0);
  const auto read = protocol::read<quarry_settings>(in);
  in.expect_end();
  EXPECT_EQ(read.struct_size, sizeof(quarry_settings));
  EXPECT_EQ(std::memcmp(&read.time_step, &settings.time_step,
                        sizeof settings - offsetof(quarry_settings, time_step)),
            0);
}

// quarry_settings between peers of different minors: each field list as far as the version
// knows it, read back with the version the message's header names.
TEST(Wire, SettingsCarryTheFieldsOfTheSendersMinor) {
  const quarry_settings settings = example_settings();
  const auto message_of = [&](std::uint32_t version) {
    Request r(Op::set_settings, nullptr);
    protocol::fields(r.fields(), settings, version);
    std::string m = r.message(1, 2);
    std::memcpy(m.data() + 4, &version, sizeof version);
    return m;
  };
  // This version's: periodic comes through.
  const std::string current = message_of(QUARRY_ABI_VERSION);
  Reader in(current.data(), current.size(), kRequestHeaderBytes);
  EXPECT_EQ(in.abi_version(), QUARRY_ABI_VERSION);
  quarry_settings read{};
  protocol::fields(in, read, in.abi_version());
  in.expect_end();
  EXPECT_EQ(std::memcmp(read.periodic, settings.periodic, sizeof read.periodic), 0);
  EXPECT_EQ(read.seed, settings.seed);
  // A 1.0 sender's: 12 bytes fewer, read to the end with periodic left as the reader had it.
  const std::string old = message_of(1u << 16);
  EXPECT_EQ(current.size() - old.size(), sizeof settings.periodic);
  Reader old_in(old.data(), old.size(), kRequestHeaderBytes);
  EXPECT_EQ(old_in.abi_version(), 1u << 16);
  quarry_settings defaults{};
  defaults.periodic[1] = 7;  // stays
  protocol::fields(old_in, defaults, old_in.abi_version());
  old_in.expect_end();
  EXPECT_EQ(defaults.seed, settings.seed);
  EXPECT_EQ(defaults.periodic[0], 0);
  EXPECT_EQ(defaults.periodic[1], 7);
  // A later minor's sender: this reader takes the fields it knows (the rest would be refused by
  // expect_end; a client sends only what the server's minor knows).
  Reader newer(current.data(), current.size(), kRequestHeaderBytes);
  quarry_settings later{};
  protocol::fields(newer, later, QUARRY_ABI_VERSION + 1);
  newer.expect_end();
  EXPECT_EQ(later.periodic[2], 1);
  // Bytes that are not a framed message have no version.
  const std::string bare = "payload";
  EXPECT_EQ(Reader(bare.data(), bare.size(), 0).abi_version(), 0u);
}

// The server reads the request and fills the output; the client's request copies it back.
void round_trip(Example& e, FakeSegment* segment, std::uint64_t shared_from) {
  Request client = example(e, segment, shared_from);
  const std::string& message = client.message(7, 99);
  const RequestHeader header = read_request_header(message.data(), message.size());
  EXPECT_EQ(header.request_id, 7u);
  EXPECT_EQ(header.session, 99u);
  Reader in(message.data(), message.size(), kRequestHeaderBytes,
            segment ? &segment->view() : nullptr);
  read_example(in);
  // The reply: the handler's own field, then the outputs.
  Writer reply;
  reply.bytes().assign(kReplyHeaderBytes, '\0');
  reply.put(std::uint64_t{123});
  in.write_outputs(reply);
  // A shared output sends only its count back.
  if (segment) {
    EXPECT_EQ(reply.bytes().size(), kReplyHeaderBytes + 2 * sizeof(std::uint64_t));
  }
  Reader back(reply.bytes().data(), reply.bytes().size(), kReplyHeaderBytes);
  EXPECT_EQ(back.get<std::uint64_t>(), 123u);
  EXPECT_EQ(client.read_outputs(back), std::vector<std::uint64_t>{4});
  back.expect_end();
  EXPECT_EQ(e.positions, (std::vector<double>{10, 11, 12, 13, -1, -1}));
}

TEST(Wire, ArraysInTheMessageRoundTrip) {
  Example e;
  round_trip(e, nullptr, 0);
}

TEST(Wire, ArraysInSharedMemoryRoundTrip) {
  Example e;
  FakeSegment segment(4096);
  // Only offsets travel: the message is shorter than the one that carries the arrays.
  EXPECT_LT(example_request(e, &segment, 1).size(), example_request(e, nullptr, 0).size());
  round_trip(e, &segment, 1);  // every array in the segment
}

TEST(Wire, EveryTruncationOfARequestIsRefused) {
  for (const bool shared : {false, true}) {
    FakeSegment segment(4096);
    Example e;
    const std::string message = example_request(e, shared ? &segment : nullptr, 1);
    for (std::size_t size = 0; size < message.size(); ++size) {
      const std::vector<std::byte> bytes = cut(message, size);
      EXPECT_THROW(read_request_header(bytes.data(), bytes.size()), WireError) << size;
      if (size < kRequestHeaderBytes) continue;
      // The payload parsed as if the header had said so: the reader stops at the cut.
      Reader in(bytes.data(), bytes.size(), kRequestHeaderBytes, &segment.view());
      EXPECT_THROW(read_example(in), WireError)
          << "cut at byte " << size << " of " << message.size();
    }
  }
}

TEST(Wire, EveryTruncationOfAReplyIsRefused) {
  const std::string reply = error_reply(3, QUARRY_ERROR_IO, "quarry_save_checkpoint: cannot write");
  for (std::size_t size = 0; size < reply.size(); ++size) {
    const std::vector<std::byte> bytes = cut(reply, size);
    EXPECT_THROW(read_reply_header(bytes.data(), bytes.size()), WireError) << size;
  }
}

TEST(Wire, WrongMagicAndWrongLengthsAreNamed) {
  std::string message(kRequestHeaderBytes, '\0');
  write_request_header(message, RequestHeader{});
  std::string other = message;
  other[0] = 'X';
  try {
    read_request_header(other.data(), other.size());
    FAIL();
  } catch (const WireError& e) {
    EXPECT_NE(std::string(e.what()).find("magic"), std::string::npos) << e.what();
  }
  EXPECT_EQ(message_abi_version(other.data(), other.size()), 0u);
  // A payload length that is not the message's: "huge announced length".
  const std::uint64_t huge = std::uint64_t{1} << 60;
  std::memcpy(message.data() + 32, &huge, sizeof huge);
  try {
    read_request_header(message.data(), message.size());
    FAIL();
  } catch (const WireError& e) {
    EXPECT_NE(std::string(e.what()).find("1152921504606846976"), std::string::npos) << e.what();
  }
}

// Lengths a reader refuses before it makes anything of them.
TEST(Wire, LengthsBeyondTheMessageAreRefusedBeforeAllocating) {
  const auto payload = [](auto write) {
    Writer w;
    write(w);
    return w.bytes();
  };
  const std::uint64_t huge = std::numeric_limits<std::uint64_t>::max() / 4;
  const auto refuses = [](const std::string& bytes, auto read) {
    Reader in(bytes.data(), bytes.size(), 0);
    EXPECT_THROW(read(in), WireError);
  };
  // An input array of 2^62 doubles in a message of a few bytes.
  refuses(payload([&](Writer& w) { w.put(Place::message), w.put(huge); }), [](Reader& in) {
    std::uint64_t n = 0;
    in.input<double>(n);
  });
  // A text longer than the message.
  refuses(payload([](Writer& w) { w.put(std::uint32_t{4000000000u}), w.raw("abc", 3); }),
          [](Reader& in) { in.text(); });
  // An output array larger than a reply may be.
  refuses(payload([&](Writer& w) { w.put(Place::message), w.put(kMaxMessageBytes); }),
          [](Reader& in) {
            std::uint64_t n = 0;
            in.output<double>(n);
          });
  // A shared array without a segment, or past its end, or misaligned.
  refuses(payload([](Writer& w) {
            w.put(Place::shared), w.put(std::uint64_t{1}), w.put(std::uint64_t{0});
          }),
          [](Reader& in) {
            std::uint64_t n = 0;
            in.input<double>(n);
          });
  FakeSegment segment(256);
  for (const auto& [count, offset] :
       {std::pair<std::uint64_t, std::uint64_t>{33, 0}, {1, 256}, {1, 4}, {huge, 8}}) {
    const std::string bytes =
        payload([&](Writer& w) { w.put(Place::shared), w.put(count), w.put(offset); });
    Reader in(bytes.data(), bytes.size(), 0, &segment.view());
    std::uint64_t n = 0;
    EXPECT_THROW(in.input<double>(n), WireError) << count << " at " << offset;
  }
  // Bytes that are no place, no presence flag.
  refuses(payload([](Writer& w) { w.put(std::uint8_t{7}); }), [](Reader& in) {
    std::uint64_t n = 0;
    in.input<double>(n);
  });
  refuses(payload([](Writer& w) { w.put(std::uint8_t{2}); }),
          [](Reader& in) { in.optional_text(); });
  // Bytes after the last field.
  refuses(payload([](Writer& w) { w.put(std::uint32_t{1}), w.put(std::uint8_t{0}); }),
          [](Reader& in) {
            in.get<std::uint32_t>();
            in.expect_end();
          });
}

TEST(Wire, RandomBytesNeverReadPastTheMessage) {
  std::mt19937_64 random(20261202);
  Example e;
  for (int trial = 0; trial < 2000; ++trial) {
    std::string message = example_request(e, nullptr, 0);
    for (int flips = 0; flips < 4; ++flips)
      message[kRequestHeaderBytes + random() % (message.size() - kRequestHeaderBytes)] =
          static_cast<char>(random());
    const std::vector<std::byte> bytes = cut(message, message.size());
    Reader in(bytes.data(), bytes.size(), kRequestHeaderBytes);
    try {
      parse_example(in);
    } catch (const WireError&) {
    }
  }
}

TEST(Wire, EveryOperationHasItsCallsName) {
  for (std::uint32_t op = kFirstOp; op <= kLastOp; ++op) {
    ASSERT_NE(op_name(op), nullptr) << op;
    EXPECT_EQ(std::string(op_name(op)).rfind("quarry_", 0), 0u) << op;
  }
  EXPECT_EQ(op_name(0), nullptr);
  EXPECT_EQ(op_name(kLastOp + 1), nullptr);
  EXPECT_STREQ(op_name(static_cast<std::uint32_t>(Op::get_particles)), "quarry_get_particles");
  EXPECT_EQ(version_text(1u << 16), "1.0");
  EXPECT_EQ(version_text(QUARRY_ABI_VERSION), "1.2");
}

}  // namespace
}  // namespace quarry::api::wire
