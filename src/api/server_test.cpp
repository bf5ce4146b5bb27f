// `quarry serve`'s request handling without a socket (api/server.h): the session rules (one
// client, busy for a second, a deck's simulation kept across sessions, a closed connection ends
// its session), and bad input of every kind — each cut of real requests, random bytes, another
// magic or ABI major, an unknown operation, lengths that do not match — answered with an error
// reply, after which the server still serves.
#include "api/server.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "api/protocol.h"
#include "api/struct_versions.h"

namespace quarry::api {
namespace {

using wire::Op;

struct Answer {
  quarry_status status = QUARRY_OK;
  std::string error;
  std::string payload;
};

Answer answer(const std::string& reply) {
  const wire::ReplyHeader header =
      wire::read_reply_header(reply.data(), reply.size());  // always a valid reply
  Answer a;
  a.status = header.status;
  a.error = reply.substr(wire::kReplyHeaderBytes, header.error_length);
  a.payload = reply.substr(wire::kReplyHeaderBytes + header.error_length);
  return a;
}

Answer send(Server& server, const std::string& request, int connection = 5) {
  return answer(server.handle(reinterpret_cast<const std::byte*>(request.data()), request.size(),
                              connection));
}

// A request of these fields (structs through their field lists).
template <class... T>
std::string request(Op op, std::uint64_t session, const T&... values) {
  wire::Request r(op, nullptr);
  protocol::write_values(r.fields(), values...);
  return r.message(1, session);
}

std::string open_request(const char* deck = nullptr, std::uint32_t caller = QUARRY_ABI_VERSION) {
  protocol::OpenRequest open;
  open.caller_abi_version = caller;
  open.deck_path = deck;
  open.client_pid = 4242;
  return request(Op::open, 0, open);
}

// Opens a session; returns its token.
std::uint64_t attach(Server& server, int connection = 5) {
  const Answer a = send(server, open_request(), connection);
  EXPECT_EQ(a.status, QUARRY_OK) << a.error;
  wire::Reader in(a.payload.data(), a.payload.size(), 0);
  return protocol::read<protocol::OpenReply>(in).session;
}

// The requests that build and run a two-particle simulation, in order.
std::vector<std::string> building_requests(std::uint64_t session, std::vector<double>& positions) {
  quarry_settings settings{};
  settings.time_step = 1e-4, settings.rayleigh_fraction = 0.2, settings.gravity[2] = -9.81;
  for (int k = 0; k < 3; ++k) settings.domain_min[k] = -1.0, settings.domain_max[k] = 1.0;
  settings.end_time = 1.0, settings.impact_speed = 0.1, settings.skin = -1.0,
  settings.sort_interval = 10;
  settings.max_overlap_fraction = 0.1, settings.seed = 1;
  const quarry_material ore{sizeof(quarry_material), "ore", 2500.0, 1e6, 0.3};
  const quarry_interaction contact{sizeof(quarry_interaction), "ore", "ore", 0.5, 0.5, 0.0, 0, 0.0};
  const quarry_particle_type grain{sizeof(quarry_particle_type), "grain", "ore", 1e-3, 0.0};
  std::vector<std::string> out = {
      request(Op::set_settings, session, settings), request(Op::add_material, session, ore),
      request(Op::add_interaction, session, contact),
      request(Op::add_particle_type, session, grain), request(Op::start, session)};
  wire::Request add(Op::add_particles, nullptr);
  add.fields().put(std::uint64_t{2});
  add.input<std::uint32_t>(nullptr, 0);
  add.fields().put(std::uint32_t{0});
  add.input(positions.data(), positions.size());
  for (int k = 0; k < 3; ++k) add.input<double>(nullptr, 0);
  add.output<std::uint64_t>(nullptr, 0);
  out.push_back(add.message(2, session));
  out.push_back(request(Op::step, session, std::uint64_t{3}));
  wire::Request loads(Op::set_external_loads, nullptr);
  const std::vector<double> force(6, 1e-3);
  loads.input(force.data(), force.size());
  loads.input<double>(nullptr, 0);
  loads.fields()(std::uint64_t{2}, std::int32_t{QUARRY_LOAD_REPLACE},
                 std::int32_t{QUARRY_HOLD_NEXT_STEP});
  out.push_back(loads.message(3, session));
  std::vector<double> room(6);
  wire::Request get(Op::get_particles, nullptr);
  get.fields().put(std::uint64_t{2});
  for (int k = 0; k < 10; ++k)
    if (k == 2)
      get.output(room.data(), room.size());
    else
      get.output<double>(nullptr, 0);
  out.push_back(get.message(4, session));
  out.push_back(request(Op::register_property, session, std::string("heat"), std::uint32_t{1},
                        std::string("K"), 300.0));
  out.push_back(request(Op::advance, session, 5e-4));
  return out;
}

TEST(Server, BuildsAndRunsASimulationForItsClient) {
  Server server(ServerOptions{});
  const std::uint64_t session = attach(server);
  std::vector<double> positions{0.0, 0.0, 0.5, 0.1, 0.0, 0.5};
  for (const std::string& r : building_requests(session, positions)) {
    const Answer a = send(server, r);
    EXPECT_EQ(a.status, QUARRY_OK) << a.error;
  }
  const Answer time = send(server, request(Op::get_time, session));
  ASSERT_EQ(time.status, QUARRY_OK);
  wire::Reader in(time.payload.data(), time.payload.size(), 0);
  in.get<double>(), in.get<double>();
  EXPECT_EQ(in.get<std::uint64_t>(), 3u + 5u);
  EXPECT_EQ(send(server, request(Op::close, session)).status, QUARRY_OK);
  EXPECT_FALSE(server.attached());
}

TEST(Server, EveryCutOfEveryRequestGetsAnErrorReplyAndTheServerServesOn) {
  Server server(ServerOptions{});
  const std::uint64_t session = attach(server);
  std::vector<double> positions{0.0, 0.0, 0.5, 0.1, 0.0, 0.5};
  std::size_t cuts = 0;
  for (const std::string& whole : building_requests(session, positions)) {
    for (std::size_t size = 0; size < whole.size(); ++size) {
      // As cut, and with the header's length made to agree (so the fields' reader meets the cut).
      for (const bool agree : {false, true}) {
        if (agree && size < wire::kRequestHeaderBytes) continue;
        std::vector<std::byte> bytes(size);  // exactly as long as the cut: ASan sees a read past it
        if (size > 0) std::memcpy(bytes.data(), whole.data(), size);
        const std::uint64_t length = size - wire::kRequestHeaderBytes;
        if (agree) std::memcpy(bytes.data() + 32, &length, sizeof length);
        const Answer a = answer(server.handle(bytes.data(), bytes.size(), 5));
        EXPECT_NE(a.status, QUARRY_OK) << "cut at " << size;
        EXPECT_FALSE(a.error.empty());
        ++cuts;
      }
    }
    // The whole request still works: nothing of the cuts was half done.
    const Answer a = send(server, whole);
    EXPECT_EQ(a.status, QUARRY_OK) << a.error;
  }
  EXPECT_GT(cuts, 500u);
  EXPECT_TRUE(server.attached());
}

TEST(Server, RandomBytesGetErrorReplies) {
  Server server(ServerOptions{});
  const std::uint64_t session = attach(server);
  std::vector<double> positions{0.0, 0.0, 0.5, 0.1, 0.0, 0.5};
  // Not step and advance: a changed count or duration could run for hours, rightly.
  std::vector<std::string> requests = building_requests(session, positions);
  std::erase_if(requests, [](const std::string& r) {
    const auto op = wire::read_request_header(r.data(), r.size()).op;
    return r.size() == wire::kRequestHeaderBytes || op == static_cast<std::uint32_t>(Op::step) ||
           op == static_cast<std::uint32_t>(Op::advance);
  });
  std::mt19937_64 random(16);
  for (int trial = 0; trial < 3000; ++trial) {
    std::string message;
    if (trial % 3 == 0) {
      message.resize(random() % 200);
      for (char& c : message) c = static_cast<char>(random());
    } else {
      // A real request with a few payload bytes changed: lengths, places, counts go wrong.
      message = requests[random() % requests.size()];
      for (int k = 0; k < 3; ++k)
        message[wire::kRequestHeaderBytes +
                random() % (message.size() - wire::kRequestHeaderBytes)] ^=
            static_cast<char>(1 + random() % 255);
    }
    std::vector<std::byte> bytes(message.size());
    if (!message.empty()) std::memcpy(bytes.data(), message.data(), message.size());
    answer(server.handle(bytes.data(), bytes.size(), 5));  // a valid reply, whatever its status
    if (!server.attached()) attach(server);  // a changed close or open byte may end the session
  }
  EXPECT_EQ(send(server, request(Op::num_types, 0)).status, QUARRY_ERROR_WRONG_STATE);  // no token
}

// Arrays in a real shared-memory segment that grows while one request is written: the server
// re-maps it for the later arrays while the earlier ones still point into the old mapping.
TEST(Server, SharedArraysThatGrowTheSegmentWithinOneRequest) {
  Server server(ServerOptions{});
  const auto segment = SharedSegment::create(1);  // one page to start
  protocol::OpenRequest open;
  open.client_pid = 1;
  open.segment = segment->name().c_str();
  const Answer opened = send(server, request(Op::open, 0, open));
  ASSERT_EQ(opened.status, QUARRY_OK) << opened.error;
  wire::Reader answer_in(opened.payload.data(), opened.payload.size(), 0);
  const auto reply = protocol::read<protocol::OpenReply>(answer_in);
  ASSERT_EQ(reply.shared_memory, 1);
  std::vector<double> unused{0.0, 0.0, 0.5, 0.1, 0.0, 0.5};
  const std::vector<std::string> building = building_requests(reply.session, unused);
  for (int k = 0; k < 5; ++k)
    ASSERT_EQ(send(server, building[k]).status, QUARRY_OK);  // up to quarry_start
  constexpr std::uint64_t n = 400;
  std::vector<double> positions(3 * n);
  for (std::uint64_t k = 0; k < n; ++k)
    positions[3 * k] = 3e-3 * static_cast<double>(k % 20),
                  positions[3 * k + 1] = 3e-3 * static_cast<double>(k / 20);
  std::vector<std::uint64_t> ids(n);
  const auto shared_request = [&](Op op) {
    segment->restart();
    return wire::Request(op, segment.get(), 1);  // every array in the segment
  };
  wire::Request add = shared_request(Op::add_particles);
  add.fields().put(n);
  add.input<std::uint32_t>(nullptr, 0);
  add.fields().put(std::uint32_t{0});
  add.input(positions.data(), positions.size());
  for (int k = 0; k < 3; ++k) add.input<double>(nullptr, 0);
  add.output(ids.data(), ids.size());
  const Answer added = send(server, add.message(2, reply.session));
  ASSERT_EQ(added.status, QUARRY_OK) << added.error;
  wire::Reader added_in(added.payload.data(), added.payload.size(), 0);
  add.read_outputs(added_in);
  // ids (3.2 kB), positions, velocities, forces, torques (9.6 kB each): 42 kB in a segment of
  // 24 kB, which grows at the forces while ids, positions and velocities sit in its old mapping.
  std::vector<std::uint64_t> got_ids(n);
  std::vector<double> got_positions(3 * n), got_velocities(3 * n, -1.0), forces(3 * n), torques(3 * n);
  const std::uint64_t size_before = segment->size();
  wire::Request get = shared_request(Op::get_particles);
  get.fields().put(n);
  get.output(got_ids.data(), n);
  get.output<std::uint32_t>(nullptr, 0);
  get.output(got_positions.data(), 3 * n);
  get.output(got_velocities.data(), 3 * n);
  for (int k = 0; k < 4; ++k) get.output<double>(nullptr, 0);
  get.output(forces.data(), 3 * n);
  get.output(torques.data(), 3 * n);
  const Answer got = send(server, get.message(3, reply.session));
  ASSERT_EQ(got.status, QUARRY_OK) << got.error;
  EXPECT_GT(segment->size(), size_before);
  wire::Reader in(got.payload.data(), got.payload.size(), 0);
  EXPECT_EQ(in.get<std::uint64_t>(), n);
  in.get<std::uint64_t>();
  get.read_outputs(in);
  EXPECT_EQ(got_ids, std::vector<std::uint64_t>(ids.begin(), ids.end()));
  EXPECT_EQ(got_positions, positions);
  EXPECT_EQ(got_velocities, std::vector<double>(3 * n, 0.0));
}

// A set_settings request as a client of ABI `version` writes it: that version in its header and
// the fields that version knows.
std::string settings_request(std::uint64_t session, const quarry_settings& settings,
                             std::uint32_t version) {
  wire::Request r(Op::set_settings, nullptr);
  protocol::fields(r.fields(), settings, version);
  std::string message = r.message(1, session);
  std::memcpy(message.data() + 4, &version, sizeof version);
  return message;
}

// One sphere (R = 5 mm) at x = 0.098 m moving at 1 m/s along +x in the box [0, 0.1]² × [−0.05,
// 0.05] m, periodic along x as the settings say, built through the server's requests with the
// settings of a client of ABI `version` and stepped 5 ms: where it is then (x, or NaN if it
// was removed).
double sphere_x_after_crossing(std::uint32_t version, int periodic_x) {
  Server server(ServerOptions{});
  const std::uint64_t session = attach(server);
  quarry_settings settings = default_settings();
  settings.time_step = 1e-5, settings.gravity[2] = 0.0, settings.impact_speed = 1.0;
  settings.domain_min[2] = -0.05, settings.domain_max[0] = settings.domain_max[1] = 0.1,
  settings.domain_max[2] = 0.05;
  settings.periodic[0] = periodic_x;
  const quarry_material glass{sizeof(quarry_material), "glass", 2500.0, 1e7, 0.3};
  const quarry_interaction contact{
      sizeof(quarry_interaction), "glass", "glass", 0.5, 0.5, 0.0, 0, 0.0};
  const quarry_particle_type bead{sizeof(quarry_particle_type), "bead", "glass", 5e-3, 0.0};
  for (const std::string& r :
       {settings_request(session, settings, version), request(Op::add_material, session, glass),
        request(Op::add_interaction, session, contact),
        request(Op::add_particle_type, session, bead), request(Op::start, session)}) {
    const Answer a = send(server, r);
    EXPECT_EQ(a.status, QUARRY_OK) << a.error;
  }
  const std::vector<double> position{0.098, 0.05, 0.0}, velocity{1.0, 0.0, 0.0};
  wire::Request add(Op::add_particles, nullptr);
  add.fields().put(std::uint64_t{1});
  add.input<std::uint32_t>(nullptr, 0);
  add.fields().put(std::uint32_t{0});
  add.input(position.data(), 3);
  add.input(velocity.data(), 3);
  for (int k = 0; k < 2; ++k) add.input<double>(nullptr, 0);
  add.output<std::uint64_t>(nullptr, 0);
  EXPECT_EQ(send(server, add.message(2, session)).status, QUARRY_OK);
  EXPECT_EQ(send(server, request(Op::step, session, std::uint64_t{500})).status, QUARRY_OK);
  std::vector<double> x(3, -1.0);
  wire::Request get(Op::get_particles, nullptr);
  get.fields().put(std::uint64_t{1});
  for (int k = 0; k < 10; ++k)
    if (k == 2)
      get.output(x.data(), x.size());
    else
      get.output<double>(nullptr, 0);
  const Answer got = send(server, get.message(3, session));
  EXPECT_EQ(got.status, QUARRY_OK) << got.error;
  wire::Reader in(got.payload.data(), got.payload.size(), 0);
  const auto count = in.get<std::uint64_t>();
  in.get<std::uint64_t>();
  get.read_outputs(in);
  return count == 1 ? x[0] : std::nan("");
}

TEST(Server, PeriodicAxesOfTheSettingsReachTheSimulation) {
  // Wrapped from 0.103 m to 0.003 m by the periodic x axis; removed without it.
  EXPECT_NEAR(sphere_x_after_crossing(QUARRY_ABI_VERSION, 1), 0.003, 1e-9);
  EXPECT_TRUE(std::isnan(sphere_x_after_crossing(QUARRY_ABI_VERSION, 0)));
}

TEST(Server, AClientOfAbi10SendsNoPeriodicAxesAndIsServed) {
  // Its request holds 1.0's fields only (12 bytes fewer): the server leaves the axes at their
  // default, none, even though this struct has x set (a 1.0 client has no such field).
  quarry_settings settings = default_settings();
  wire::Writer old_fields, new_fields;
  protocol::fields(old_fields, settings, 1u << 16);
  protocol::fields(new_fields, settings, QUARRY_ABI_VERSION);
  EXPECT_EQ(new_fields.bytes().size() - old_fields.bytes().size(), sizeof settings.periodic);
  EXPECT_TRUE(std::isnan(sphere_x_after_crossing(1u << 16, 1)));
  // A 1.1 request without its periodic entries is malformed, not taken for a 1.0 one.
  Server server(ServerOptions{});
  const std::uint64_t session = attach(server);
  std::string cut = settings_request(session, settings, QUARRY_ABI_VERSION);
  cut.resize(cut.size() - sizeof settings.periodic);
  const std::uint64_t length = cut.size() - wire::kRequestHeaderBytes;
  std::memcpy(cut.data() + 32, &length, sizeof length);
  const Answer a = send(server, cut);
  EXPECT_EQ(a.status, QUARRY_ERROR_TRANSPORT);
  EXPECT_NE(a.error.find("malformed"), std::string::npos) << a.error;
  // A bad entry travels back with the library's text.
  settings.periodic[2] = 5;
  const Answer bad = send(server, settings_request(session, settings, QUARRY_ABI_VERSION));
  EXPECT_EQ(bad.status, QUARRY_ERROR_BAD_VALUE);
  EXPECT_NE(bad.error.find("periodic[2] (axis z) is 5"), std::string::npos) << bad.error;
}

TEST(Server, ForeignMessagesAreNamed) {
  Server server(ServerOptions{});
  const std::uint64_t session = attach(server);
  const auto status_and_text = [&](std::string message) {
    const Answer a = send(server, message);
    return std::pair(a.status, a.error);
  };
  // Too short, another magic.
  EXPECT_EQ(status_and_text("").first, QUARRY_ERROR_TRANSPORT);
  EXPECT_EQ(status_and_text("abc").first, QUARRY_ERROR_TRANSPORT);
  std::string other = request(Op::num_types, session);
  other[0] = 'H';
  const auto magic = status_and_text(other);
  EXPECT_EQ(magic.first, QUARRY_ERROR_TRANSPORT);
  EXPECT_NE(magic.second.find("magic"), std::string::npos) << magic.second;
  // Another ABI major in the header: VERSION, both versions named.
  std::string major = request(Op::num_types, session);
  const std::uint32_t two = 2u << 16;
  std::memcpy(major.data() + 4, &two, sizeof two);
  const auto version = status_and_text(major);
  EXPECT_EQ(version.first, QUARRY_ERROR_VERSION);
  EXPECT_NE(version.second.find("2.0"), std::string::npos) << version.second;
  EXPECT_NE(version.second.find(wire::version_text(QUARRY_ABI_VERSION)), std::string::npos)
      << version.second;
  // An unknown operation.
  std::string unknown = request(Op::num_types, session);
  const std::uint32_t op = 999;
  std::memcpy(unknown.data() + 8, &op, sizeof op);
  const auto unsupported = status_and_text(unknown);
  EXPECT_EQ(unsupported.first, QUARRY_ERROR_UNSUPPORTED);
  EXPECT_NE(unsupported.second.find("999"), std::string::npos) << unsupported.second;
  // A huge announced payload.
  std::string huge = request(Op::num_types, session);
  const std::uint64_t length = std::uint64_t{1} << 62;
  std::memcpy(huge.data() + 32, &length, sizeof length);
  EXPECT_EQ(status_and_text(huge).first, QUARRY_ERROR_TRANSPORT);
  // A force array shorter than the count says (the backend would read past it).
  wire::Request loads(Op::set_external_loads, nullptr);
  const std::vector<double> force(3, 1.0);
  loads.input(force.data(), force.size());
  loads.input<double>(nullptr, 0);
  loads.fields()(std::uint64_t{1000}, std::int32_t{0}, std::int32_t{0});
  const auto short_array = status_and_text(loads.message(1, session));
  EXPECT_EQ(short_array.first, QUARRY_ERROR_TRANSPORT);
  EXPECT_NE(short_array.second.find("force holds 3 values, the call needs 3000"), std::string::npos)
      << short_array.second;
  // A caller of another major in the open request (its library's header is this one's).
  const Answer caller = send(server, open_request(nullptr, 3u << 16), 6);
  EXPECT_EQ(caller.status, QUARRY_ERROR_VERSION);
  EXPECT_NE(caller.error.find("3.0"), std::string::npos) << caller.error;
  // And after all that the session serves on.
  EXPECT_EQ(send(server, request(Op::num_types, session)).status, QUARRY_OK);
}

TEST(Server, OneClientAtATimeAndAClosedConnectionEndsItsSession) {
  Server server(ServerOptions{});
  const std::uint64_t first = attach(server, 5);
  const Answer busy = send(server, open_request(), 6);
  EXPECT_EQ(busy.status, QUARRY_ERROR_WRONG_STATE);
  EXPECT_NE(busy.error.find("busy"), std::string::npos) << busy.error;
  EXPECT_EQ(send(server, request(Op::num_types, first + 1), 6).status, QUARRY_ERROR_WRONG_STATE);
  server.connection_closed(6);  // not the session's
  EXPECT_TRUE(server.attached());
  server.connection_closed(5);
  EXPECT_FALSE(server.attached());
  const Answer ended = send(server, request(Op::num_types, first), 5);
  EXPECT_EQ(ended.status, QUARRY_ERROR_WRONG_STATE);
  EXPECT_NE(ended.error.find("no client is attached"), std::string::npos) << ended.error;
  const std::uint64_t second = attach(server, 6);
  EXPECT_NE(second, first);
}

TEST(Server, ADecksSimulationOutlivesItsSessions) {
  ServerOptions options;
  options.deck_path =
      std::string(QUARRY_SOURCE_DIR) + "/examples/bouncing_sphere/bouncing_sphere.yaml";
  Server server(options);
  const Answer named = send(server, open_request("other.yaml"));
  EXPECT_EQ(named.status, QUARRY_ERROR_WRONG_STATE);
  EXPECT_NE(named.error.find("given on its command line"), std::string::npos) << named.error;
  const auto steps_after = [&](std::uint64_t session) {
    EXPECT_EQ(send(server, request(Op::step, session, std::uint64_t{4})).status, QUARRY_OK);
    const Answer time = send(server, request(Op::get_time, session));
    wire::Reader in(time.payload.data(), time.payload.size(), 0);
    in.get<double>(), in.get<double>();
    return in.get<std::uint64_t>();
  };
  std::uint64_t session = attach(server);
  EXPECT_EQ(steps_after(session), 4u);
  EXPECT_EQ(send(server, request(Op::close, session)).status, QUARRY_OK);
  session = attach(server);
  EXPECT_EQ(steps_after(session), 8u);  // the same simulation, where the last client left it
}

}  // namespace
}  // namespace quarry::api
