// `quarry serve` as a process, through the C ABI (issue 16 §3, §5): malformed messages answered
// and a client served after them; the server killed (SIGKILL) during an advance and while idle,
// or stopped (SIGSTOP), gives the client TRANSPORT or TIMEOUT within seconds, never a hang;
// another ABI major gives VERSION on either side; a second client is told the server is busy; a
// killed client's session ends; SIGTERM stops the server cleanly. Every process a test starts is
// killed when the test ends, also on failure (and dies with the test process).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zmq.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "api/protocol.h"
#include "api/wire.h"
#include "quarry/quarry.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
namespace wire = quarry::api::wire;
namespace protocol = quarry::api::protocol;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A process of the test's: SIGKILLed and reaped when the object goes, and by the kernel when
// the test process dies (PR_SET_PDEATHSIG).
class Child {
 public:
  // Runs argv with stdout and stderr into `log`.
  Child(const std::vector<std::string>& argv, const fs::path& log) {
    pid_ = ::fork();
    if (pid_ == 0) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1), ::dup2(fd, 2);
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execv(args[0], args.data());
      ::_exit(127);
    }
  }
  // Runs `body` in a forked copy of the test (which must have no other threads yet), then waits
  // to be killed.
  template <class Body>
  static Child forked(Body body) {
    Child child;
    child.pid_ = ::fork();
    if (child.pid_ == 0) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      body();
      for (;;) ::pause();
    }
    return child;
  }
  Child(Child&& other) noexcept : pid_(std::exchange(other.pid_, -1)) {}
  ~Child() { kill(SIGKILL), wait_exit(5000); }

  pid_t pid() const { return pid_; }
  void kill(int signal_number) const {
    if (pid_ > 0) ::kill(pid_, signal_number);
  }
  // Its exit code (128 + signal if killed), or −1 if it runs on after timeout_ms.
  int wait_exit(int timeout_ms) {
    if (pid_ <= 0) return exit_code_;
    for (const auto start = Clock::now(); seconds_since(start) * 1000 < timeout_ms;
         std::this_thread::sleep_for(10ms)) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        return exit_code_;
      }
    }
    return -1;
  }

 private:
  Child() = default;
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A unique ipc endpoint in the temporary directory (short: a unix socket path has 107 bytes).
std::string ipc_endpoint() {
  static int counter = 0;
  return "ipc://" +
         (fs::temp_directory_path() / ("quarry-serve-test-" + std::to_string(::getpid()) + "-" +
                                       std::to_string(counter++) + ".ipc"))
             .string();
}

// `quarry serve` running at an endpoint (tcp: a free loopback port), its log in the build folder.
class Server {
 public:
  explicit Server(const std::string& wanted = ipc_endpoint(), std::vector<std::string> extra = {})
      : log_(fs::current_path() / ("serve_test_" + std::to_string(::getpid()) + "_" +
                                   std::to_string(count_++) + ".log")),
        child_(arguments(wanted, extra), log_) {
    EXPECT_TRUE(wait_for("listening on ", 20000)) << log();
    const std::string text = log();
    const std::size_t at = text.find("listening on ");
    if (at != std::string::npos)
      endpoint_ = text.substr(at + 13, text.find(' ', at + 13) - at - 13);
  }
  // A killed server leaves its socket file behind: it goes here.
  ~Server() {
    child_.kill(SIGKILL);
    child_.wait_exit(5000);
    if (endpoint_.rfind("ipc://", 0) == 0) fs::remove(endpoint_.substr(6));
  }
  const std::string& endpoint() const { return endpoint_; }
  Child& process() { return child_; }
  std::string log() const { return read_file(log_); }
  bool wait_for(const std::string& text, int timeout_ms) const {
    for (const auto start = Clock::now(); seconds_since(start) * 1000 < timeout_ms;
         std::this_thread::sleep_for(20ms))
      if (log().find(text) != std::string::npos) return true;
    return false;
  }

 private:
  static std::vector<std::string> arguments(const std::string& endpoint,
                                            const std::vector<std::string>& extra) {
    std::vector<std::string> argv{QUARRY_BIN, "serve", "--endpoint", endpoint, "--threads", "1"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return argv;
  }
  static inline int count_ = 0;
  fs::path log_;
  Child child_;
  std::string endpoint_;
};

std::string last_error(quarry_sim sim) {
  char text[2048] = {};
  quarry_last_error(sim, text, sizeof text, nullptr);
  return text;
}

quarry_status open(const std::string& endpoint, quarry_sim& sim, int timeout_ms = 0,
                   const char* deck = nullptr) {
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  info.endpoint = endpoint.c_str();
  info.timeout_ms = timeout_ms;
  info.deck_path = deck;
  return quarry_open(&info, &sim);
}

// An empty simulation with one particle at rest, built through the handle (dt = 1e-4 s).
void build_one_particle(quarry_sim sim) {
  quarry_settings settings = quarry_default_settings();
  settings.time_step = 1e-4;
  for (int k = 0; k < 3; ++k) settings.domain_min[k] = -1e6, settings.domain_max[k] = 1e6;
  settings.gravity[2] = 0.0;
  settings.impact_speed = 0.1;
  ASSERT_EQ(quarry_set_settings(sim, &settings), QUARRY_OK) << last_error(sim);
  quarry_material ore = {sizeof ore, "ore", 2500.0, 1e6, 0.3};
  ASSERT_EQ(quarry_add_material(sim, &ore, nullptr), QUARRY_OK) << last_error(sim);
  quarry_interaction contact = {sizeof contact,      "ore", "ore", 0.5, 0.5, 0.0,
                                QUARRY_ROLLING_NONE, 0.0};
  ASSERT_EQ(quarry_add_interaction(sim, &contact), QUARRY_OK) << last_error(sim);
  quarry_particle_type grain = {sizeof grain, "grain", "ore", 1e-3, 0.0};
  ASSERT_EQ(quarry_add_particle_type(sim, &grain, nullptr), QUARRY_OK) << last_error(sim);
  ASSERT_EQ(quarry_start(sim), QUARRY_OK) << last_error(sim);
  double position[3] = {0.0, 0.0, 0.0};
  quarry_new_particles add = {sizeof add, 1,       nullptr, 0,      position,
                              nullptr,    nullptr, nullptr, nullptr};
  ASSERT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << last_error(sim);
}

// A raw REQ socket: sends bytes as they are, returns the reply's status and text.
class RawClient {
 public:
  explicit RawClient(const std::string& endpoint) {
    context_ = zmq_ctx_new();
    socket_ = zmq_socket(context_, ZMQ_REQ);
    const int linger = 0, wait_ms = 10000;
    zmq_setsockopt(socket_, ZMQ_LINGER, &linger, sizeof linger);
    zmq_setsockopt(socket_, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
    zmq_connect(socket_, endpoint.c_str());
  }
  ~RawClient() {
    zmq_close(socket_);
    zmq_ctx_term(context_);
  }
  // Sends the frames (one, or more to break the one-frame rule) and reads the reply.
  std::pair<quarry_status, std::string> send(const std::vector<std::string>& frames) {
    for (std::size_t k = 0; k < frames.size(); ++k)
      zmq_send(socket_, frames[k].data(), frames[k].size(),
               k + 1 < frames.size() ? ZMQ_SNDMORE : 0);
    zmq_msg_t reply;
    zmq_msg_init(&reply);
    if (zmq_msg_recv(&reply, socket_, 0) < 0) {
      zmq_msg_close(&reply);
      return {QUARRY_OK, "no reply within 10 s"};
    }
    const std::string bytes(static_cast<const char*>(zmq_msg_data(&reply)), zmq_msg_size(&reply));
    zmq_msg_close(&reply);
    const wire::ReplyHeader header = wire::read_reply_header(bytes.data(), bytes.size());
    return {header.status, bytes.substr(wire::kReplyHeaderBytes, header.error_length)};
  }
  std::pair<quarry_status, std::string> send(const std::string& message) {
    return send(std::vector{message});
  }

 private:
  void* context_;
  void* socket_;
};

std::string open_message(std::uint32_t header_version, std::uint32_t caller_version) {
  protocol::OpenRequest open;
  open.caller_abi_version = caller_version;
  open.client_pid = ::getpid();
  wire::Request r(wire::Op::open, nullptr);
  protocol::fields(r.fields(), open);
  std::string message = r.message(1, 0);
  std::memcpy(message.data() + 4, &header_version, sizeof header_version);
  return message;
}

std::string header_only(std::uint32_t op) {
  std::string message(wire::kRequestHeaderBytes, '\0');
  wire::RequestHeader header;
  header.op = op;
  wire::write_request_header(message, header);
  return message;
}

TEST(Serve, MalformedMessagesGetErrorRepliesAndAClientIsServedAfter) {
  Server server;
  {
    RawClient raw(server.endpoint());
    std::mt19937_64 random(7);
    std::string noise(1000, '\0');
    for (char& c : noise) c = static_cast<char>(random());
    std::string magic = header_only(static_cast<std::uint32_t>(wire::Op::num_types));
    magic[0] = 'Z';
    std::string huge = header_only(static_cast<std::uint32_t>(wire::Op::num_types));
    const std::uint64_t length = std::uint64_t{1} << 50;
    std::memcpy(huge.data() + 32, &length, sizeof length);
    const std::string open = open_message(QUARRY_ABI_VERSION, QUARRY_ABI_VERSION);
    for (const std::string& bad :
         {std::string(), std::string("abc"), noise, magic, huge, open.substr(0, open.size() - 3),
          header_only(999), header_only(static_cast<std::uint32_t>(wire::Op::step))}) {
      const auto [status, text] = raw.send(bad);
      EXPECT_NE(status, QUARRY_OK) << bad.size() << " bytes";
      EXPECT_FALSE(text.empty());
    }
    EXPECT_EQ(raw.send(header_only(999)).first, QUARRY_ERROR_UNSUPPORTED);
    EXPECT_EQ(raw.send(magic).first, QUARRY_ERROR_TRANSPORT);
    const auto [status, text] = raw.send(std::vector<std::string>{"one", "two"});
    EXPECT_EQ(status, QUARRY_ERROR_TRANSPORT);
    EXPECT_NE(text.find("one frame"), std::string::npos) << text;
  }
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  build_one_particle(sim);
  EXPECT_EQ(quarry_step(sim, 10), QUARRY_OK) << last_error(sim);
  std::uint64_t steps = 0;
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, &steps), QUARRY_OK);
  EXPECT_EQ(steps, 10u);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK) << last_error(QUARRY_NO_SIM);
}

class ServeKilled : public testing::TestWithParam<const char*> {};

// The parameter "ipc" stands for a fresh ipc endpoint.
std::string endpoint_of(const char* parameter) {
  return std::string(parameter) == "ipc" ? ipc_endpoint() : parameter;
}

TEST_P(ServeKilled, DuringAnAdvanceTheClientGetsTransportWithinSeconds) {
  Server server(endpoint_of(GetParam()));
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  build_one_particle(sim);
  std::atomic<quarry_status> status{QUARRY_OK};
  std::thread advance([&] { status = quarry_advance(sim, 1e5, nullptr); });  // 1e9 steps: hours
  std::this_thread::sleep_for(500ms);
  const auto killed = Clock::now();
  server.process().kill(SIGKILL);
  advance.join();
  const double waited = seconds_since(killed);
  EXPECT_EQ(status.load(), QUARRY_ERROR_TRANSPORT);
  EXPECT_LT(waited, 5.0);
  const std::string text = last_error(sim);
  EXPECT_NE(text.find(server.endpoint()), std::string::npos) << text;
  EXPECT_NE(text.find("quarry_advance"), std::string::npos) << text;
  // The handle is clearly dead: every call says so at once; close still releases it.
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, nullptr), QUARRY_ERROR_TRANSPORT);
  EXPECT_EQ(quarry_close(sim), QUARRY_ERROR_TRANSPORT);
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, nullptr), QUARRY_ERROR_INVALID_HANDLE);
  std::printf("the advance returned %.3f s after the server was killed\n", waited);
}

TEST_P(ServeKilled, WhileIdleTheNextCallGetsTransport) {
  Server server(endpoint_of(GetParam()));
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, nullptr), QUARRY_OK) << last_error(sim);
  server.process().kill(SIGKILL);
  EXPECT_NE(server.process().wait_exit(5000), -1);
  const auto start = Clock::now();
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, nullptr), QUARRY_ERROR_TRANSPORT)
      << last_error(sim);
  EXPECT_LT(seconds_since(start), 5.0);
  EXPECT_EQ(quarry_close(sim), QUARRY_ERROR_TRANSPORT);
}

INSTANTIATE_TEST_SUITE_P(Endpoints, ServeKilled, testing::Values("ipc", "tcp://127.0.0.1:0"),
                         [](const auto& parameter) {
                           return std::string(parameter.param).substr(0, 3);
                         });

TEST(Serve, AStoppedServerGivesTimeoutAndTheNextClientIsServedOnceItRuns) {
  Server server;
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 500), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  server.process().kill(SIGSTOP);
  const auto start = Clock::now();
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, nullptr), QUARRY_ERROR_TIMEOUT);
  const double waited = seconds_since(start);
  EXPECT_GE(waited, 0.45);
  EXPECT_LT(waited, 3.0);
  EXPECT_NE(last_error(sim).find("within 500 ms"), std::string::npos) << last_error(sim);
  // Its socket is closed: no late reply can be taken for another request's.
  EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, nullptr), QUARRY_ERROR_TRANSPORT);
  EXPECT_EQ(quarry_close(sim), QUARRY_ERROR_TRANSPORT);
  server.process().kill(SIGCONT);
  quarry_sim next;
  ASSERT_EQ(open(server.endpoint(), next, 5000), QUARRY_OK)
      << last_error(QUARRY_NO_SIM) << server.log();
  EXPECT_EQ(quarry_close(next), QUARRY_OK);
  EXPECT_TRUE(server.wait_for("session 1 ended: its connection closed", 2000)) << server.log();
}

TEST(Serve, NothingListeningGivesTimeoutWithAHint) {
  quarry_sim sim;
  const std::string endpoint = ipc_endpoint();
  EXPECT_EQ(open(endpoint, sim, 300), QUARRY_ERROR_TIMEOUT);
  const std::string text = last_error(QUARRY_NO_SIM);
  EXPECT_NE(text.find("quarry serve --endpoint " + endpoint), std::string::npos) << text;
}

TEST(Serve, AnotherAbiMajorGivesVersionOnEitherSide) {
  const std::string kThisVersion = wire::version_text(QUARRY_ABI_VERSION);
  Server server;
  {
    RawClient raw(server.endpoint());
    // A client library of major 2 (its header says so).
    const auto [header_status, header_text] = raw.send(open_message(2u << 16, 2u << 16));
    EXPECT_EQ(header_status, QUARRY_ERROR_VERSION);
    EXPECT_NE(header_text.find("2.0"), std::string::npos) << header_text;
    EXPECT_NE(header_text.find(kThisVersion), std::string::npos) << header_text;
    // A caller compiled for major 2 against a library of major 1.
    const auto [caller_status, caller_text] =
        raw.send(open_message(QUARRY_ABI_VERSION, (2u << 16) | 3));
    EXPECT_EQ(caller_status, QUARRY_ERROR_VERSION);
    EXPECT_NE(caller_text.find("2.3"), std::string::npos) << caller_text;
    EXPECT_NE(caller_text.find(kThisVersion), std::string::npos) << caller_text;
  }
  // A server of major 3 answering: the client names both versions.
  const std::string endpoint = ipc_endpoint();
  void* context = zmq_ctx_new();
  void* rep = zmq_socket(context, ZMQ_REP);
  ASSERT_EQ(zmq_bind(rep, endpoint.c_str()), 0);
  std::thread fake([rep] {
    char buffer[4096];
    const int wait_ms = 5000;
    zmq_setsockopt(rep, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
    if (zmq_recv(rep, buffer, sizeof buffer, 0) < 0) return;
    std::string reply = wire::error_reply(1, QUARRY_OK, "");
    const std::uint32_t three = 3u << 16;
    std::memcpy(reply.data() + 4, &three, sizeof three);
    zmq_send(rep, reply.data(), reply.size(), 0);
  });
  quarry_sim sim;
  EXPECT_EQ(open(endpoint, sim, 5000), QUARRY_ERROR_VERSION);
  fake.join();
  const std::string text = last_error(QUARRY_NO_SIM);
  EXPECT_NE(text.find("3.0"), std::string::npos) << text;
  EXPECT_NE(text.find(kThisVersion), std::string::npos) << text;
  zmq_close(rep);
  zmq_ctx_term(context);
  fs::remove(endpoint.substr(6));
}

// A server that answers the open properly and the next request with a reply too short for it:
// the client reports TRANSPORT (the server's reply is malformed), not an internal error.
TEST(Serve, AMalformedReplyGivesTransport) {
  const std::string endpoint = ipc_endpoint();
  void* context = zmq_ctx_new();
  void* rep = zmq_socket(context, ZMQ_REP);
  ASSERT_EQ(zmq_bind(rep, endpoint.c_str()), 0);
  std::thread fake([rep] {
    const int wait_ms = 5000;
    zmq_setsockopt(rep, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
    char buffer[4096];
    for (int k = 0; k < 2; ++k) {
      if (zmq_recv(rep, buffer, sizeof buffer, 0) < 0) return;
      std::uint64_t id = 0;
      std::memcpy(&id, buffer + 16, sizeof id);
      wire::Writer out;
      out.bytes().assign(wire::kReplyHeaderBytes, '\0');
      if (k == 0)
        protocol::write_values(out, protocol::OpenReply{7, 0, "fake"});  // none for num_types
      wire::ReplyHeader header;
      header.request_id = id;
      wire::write_reply_header(out.bytes(), header);
      zmq_send(rep, out.bytes().data(), out.bytes().size(), 0);
    }
  });
  quarry_sim sim;
  ASSERT_EQ(open(endpoint, sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  std::uint32_t types = 0;
  EXPECT_EQ(quarry_num_types(sim, &types), QUARRY_ERROR_TRANSPORT);
  EXPECT_NE(last_error(sim).find("malformed"), std::string::npos) << last_error(sim);
  fake.join();
  zmq_close(rep);
  zmq_ctx_term(context);
  EXPECT_EQ(quarry_close(sim), QUARRY_ERROR_TRANSPORT);  // nothing behind it now; still released
  fs::remove(endpoint.substr(6));
}

TEST(Serve, ASecondClientIsToldTheServerIsBusy) {
  Server server;
  quarry_sim first, second;
  ASSERT_EQ(open(server.endpoint(), first, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  EXPECT_EQ(open(server.endpoint(), second, 5000), QUARRY_ERROR_WRONG_STATE);
  const std::string text = last_error(QUARRY_NO_SIM);
  EXPECT_NE(text.find("busy"), std::string::npos) << text;
  EXPECT_EQ(quarry_close(first), QUARRY_OK);
  ASSERT_EQ(open(server.endpoint(), second, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  EXPECT_EQ(quarry_close(second), QUARRY_OK);
}

TEST(Serve, AKilledClientsSessionEndsAndItsSegmentIsGone) {
  Server server;
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const std::string endpoint = server.endpoint();
  Child client = Child::forked([&] {
    quarry_sim sim;
    const bool ok = open(endpoint, sim, 5000) == QUARRY_OK;
    if (ok) build_one_particle(sim);
    const char answer = ok ? 'y' : 'n';
    [[maybe_unused]] const auto written = ::write(ready[1], &answer, 1);
  });
  char answer = 0;
  ASSERT_EQ(::read(ready[0], &answer, 1), 1);
  ASSERT_EQ(answer, 'y');
  EXPECT_TRUE(server.wait_for("arrays in shared memory", 2000)) << server.log();
  // The server removed the segment's name when it mapped it: nothing of the client's in /dev/shm.
  const std::string prefix = "quarry-" + std::to_string(client.pid()) + "-";
  const auto named = [&] {
    for (const auto& entry : fs::directory_iterator("/dev/shm"))
      if (entry.path().filename().string().rfind(prefix, 0) == 0) return true;
    return false;
  };
  EXPECT_FALSE(named());
  client.kill(SIGKILL);
  EXPECT_TRUE(server.wait_for("session 1 ended: its connection closed", 3000)) << server.log();
  EXPECT_FALSE(named());
  quarry_sim next;
  ASSERT_EQ(open(server.endpoint(), next, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  EXPECT_EQ(quarry_close(next), QUARRY_OK);
  ::close(ready[0]), ::close(ready[1]);
}

TEST(Serve, ADeckGivenToTheServerIsKeptAcrossClients) {
  const std::string deck =
      std::string(QUARRY_SOURCE_DIR) + "/examples/bouncing_sphere/bouncing_sphere.yaml";
  Server server(ipc_endpoint(), {deck});
  quarry_sim sim;
  EXPECT_EQ(open(server.endpoint(), sim, 5000, deck.c_str()), QUARRY_ERROR_WRONG_STATE);
  EXPECT_NE(last_error(QUARRY_NO_SIM).find("given on its command line"), std::string::npos);
  for (std::uint64_t expected : {3u, 6u}) {
    ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
    std::uint64_t particles = 0, steps = 0;
    EXPECT_EQ(quarry_num_particles(sim, -1, &particles), QUARRY_OK);
    EXPECT_GT(particles, 0u);
    EXPECT_EQ(quarry_step(sim, 3), QUARRY_OK) << last_error(sim);
    EXPECT_EQ(quarry_get_time(sim, nullptr, nullptr, &steps), QUARRY_OK);
    EXPECT_EQ(steps, expected);
    EXPECT_EQ(quarry_close(sim), QUARRY_OK);
  }
}

TEST(Serve, HooksAreUnsupportedAndViewsAreCopies) {
  Server server;
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  build_one_particle(sim);
  EXPECT_EQ(quarry_set_hook(
                sim, QUARRY_HOOK_POST_FORCE, [](quarry_sim, int32_t, void*) { return 0; }, nullptr),
            QUARRY_ERROR_UNSUPPORTED);
  EXPECT_NE(last_error(sim).find("quarry_set_external_loads"), std::string::npos)
      << last_error(sim);
  double velocity[3] = {1.0, 2.0, 3.0};
  EXPECT_EQ(quarry_set_external_loads(sim, velocity, nullptr, 1, QUARRY_LOAD_REPLACE,
                                      QUARRY_HOLD_NEXT_STEP),
            QUARRY_OK);
  EXPECT_EQ(quarry_step(sim, 2), QUARRY_OK);
  double position[3];
  quarry_particle_data data = {sizeof data, 1,       nullptr, nullptr, position, nullptr, nullptr,
                               nullptr,     nullptr, nullptr, nullptr, nullptr,  0,       0};
  ASSERT_EQ(quarry_get_particles(sim, &data), QUARRY_OK);
  quarry_view view;
  ASSERT_EQ(quarry_view_particles(sim, QUARRY_FIELD_POSITION, &view), QUARRY_OK);
  ASSERT_EQ(view.count, 1u);
  EXPECT_EQ(view.components, 3u);
  EXPECT_EQ(view.writable, 0u);
  EXPECT_EQ(std::memcmp(view.data, position, sizeof position), 0);
  EXPECT_GT(position[0], 0.0);  // the force moved it
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

// Over ipc the session's requests come through its channel in shared memory, and the calls
// that go over the socket instead (a whole state) fit in between: a state saved (socket),
// steps (channel), the state restored (channel) and the same steps again give the same bits.
TEST(Serve, RequestsGoThroughTheChannelAndTheSocketInTurn) {
  Server server;
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  build_one_particle(sim);
  double velocity[3] = {0.1, -0.2, 0.3};
  EXPECT_EQ(quarry_set_external_loads(sim, velocity, nullptr, 1, QUARRY_LOAD_REPLACE,
                                      QUARRY_HOLD_UNTIL_CHANGED),
            QUARRY_OK);
  EXPECT_TRUE(server.wait_for("requests through shared memory", 2000)) << server.log();
  std::uint64_t needed = 0;
  ASSERT_EQ(quarry_save_state(sim, nullptr, 0, &needed), QUARRY_OK) << last_error(sim);
  std::vector<char> state(needed);
  ASSERT_EQ(quarry_save_state(sim, state.data(), state.size(), &needed), QUARRY_OK);
  const auto run = [&] {
    std::array<double, 3> position{};
    for (int k = 0; k < 20; ++k) EXPECT_EQ(quarry_step(sim, 5), QUARRY_OK) << last_error(sim);
    quarry_particle_data data = {sizeof data, 1,       nullptr, nullptr,         position.data(),
                                 nullptr,     nullptr, nullptr, nullptr,         nullptr,
                                 nullptr,     nullptr, 0,       0};
    EXPECT_EQ(quarry_get_particles(sim, &data), QUARRY_OK) << last_error(sim);
    return position;
  };
  const std::array<double, 3> first = run();
  ASSERT_EQ(quarry_restore_state(sim, state.data(), state.size()), QUARRY_OK) << last_error(sim);
  const std::array<double, 3> again = run();
  EXPECT_EQ(std::memcmp(first.data(), again.data(), sizeof first), 0);
  EXPECT_GT(first[0], 0.0);  // the held load moved it
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
  EXPECT_TRUE(server.wait_for("session 1 ended: the client closed it", 2000)) << server.log();
}

// Mappings of this process of files under /dev/shm whose name starts with `prefix` (a shared
// segment's name is removed once the server maps it: the mapping then reads "(deleted)").
int shared_mappings(const std::string& prefix) {
  std::ifstream maps("/proc/self/maps");
  int found = 0;
  for (std::string line; std::getline(maps, line);)
    found += line.find("/dev/shm/" + prefix) != std::string::npos;
  return found;
}

// Over ipc a view is written by the server into a segment of the client's own for that field
// (one copy, none through the socket): the same values as the copies, also for a view larger
// than the first segment (64 KiB: 3000 positions are 72 kB), after steps, for every field and a
// custom property, and the pointer of a field's view stays put from one view to the next.
TEST(Serve, ViewsOverIpcAreWrittenIntoSharedMemoryAndMatchTheCopies) {
  Server server;
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  build_one_particle(sim);
  constexpr std::uint64_t added = 2999, n = added + 1;
  std::vector<double> position(3 * added), velocity(3 * added);
  for (std::uint64_t k = 0; k < added; ++k) {
    position[3 * k] = 3e-3 * static_cast<double>(k % 50 + 1);  // m: spheres of 1 mm, apart
    position[3 * k + 1] = 3e-3 * static_cast<double>(k / 50);
    velocity[3 * k + 2] = 1e-3 * static_cast<double>(k % 7);  // m/s
  }
  quarry_new_particles add = {sizeof add, added,   nullptr, 0,      position.data(),
                              velocity.data(), nullptr, nullptr, nullptr};
  ASSERT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << last_error(sim);
  const std::string prefix = "quarry-" + std::to_string(::getpid()) + "-";
  const int mapped_before = shared_mappings(prefix);
  ASSERT_EQ(quarry_register_property(sim, "charge", 2, "C", 0.5, nullptr), QUARRY_OK)
      << last_error(sim);
  const void* first_position = nullptr;
  for (int round = 0; round < 2; ++round) {
    ASSERT_EQ(quarry_step(sim, 3), QUARRY_OK) << last_error(sim);
    std::vector<std::uint64_t> ids(n);
    std::vector<std::uint32_t> types(n);
    std::vector<double> x(3 * n), v(3 * n), radius(n);
    quarry_particle_data data = {sizeof data, n,      ids.data(), types.data(), x.data(),
                                 v.data(),    nullptr, radius.data(), nullptr,  nullptr,
                                 nullptr,     nullptr, 0,       0};
    ASSERT_EQ(quarry_get_particles(sim, &data), QUARRY_OK) << last_error(sim);
    ASSERT_EQ(data.count, n);
    quarry_view view;
    const auto same = [&](int field, const void* expected, std::size_t bytes) {
      ASSERT_EQ(quarry_view_particles(sim, field, &view), QUARRY_OK) << last_error(sim);
      ASSERT_EQ(view.count, n);
      EXPECT_EQ(view.writable, 0u);
      EXPECT_EQ(view.stride * static_cast<std::int64_t>(n), static_cast<std::int64_t>(bytes));
      EXPECT_EQ(std::memcmp(view.data, expected, bytes), 0) << "field " << field;
    };
    same(QUARRY_FIELD_POSITION, x.data(), x.size() * sizeof(double));  // one type: same order
    if (round == 0) first_position = view.data;
    EXPECT_EQ(view.data, first_position);  // the field's segment is written again in place
    same(QUARRY_FIELD_VELOCITY, v.data(), v.size() * sizeof(double));
    same(QUARRY_FIELD_ID, ids.data(), ids.size() * sizeof(std::uint64_t));
    same(QUARRY_FIELD_RADIUS, radius.data(), radius.size() * sizeof(double));
    ASSERT_EQ(quarry_view_particles(sim, QUARRY_FIELD_TYPE, &view), QUARRY_OK);
    EXPECT_EQ(view.dtype, static_cast<std::uint32_t>(QUARRY_DTYPE_UINT16));
    for (std::uint64_t k = 0; k < n; ++k)
      EXPECT_EQ(static_cast<const std::uint16_t*>(view.data)[k], 0u);
    ASSERT_EQ(quarry_view_property(sim, 0, &view), QUARRY_OK) << last_error(sim);
    ASSERT_EQ(view.count, n);
    EXPECT_EQ(view.components, 2u);
    for (std::uint64_t k = 0; k < 2 * n; ++k)
      EXPECT_EQ(static_cast<const double*>(view.data)[k], 0.5);
  }
  // Five views (position, velocity, id, radius, type) and a property view: each in a segment
  // the client mapped, none of them the session's segment for the requests' arrays.
  EXPECT_GE(shared_mappings(prefix) - mapped_before, 6);
  // A view after the particles changed (as many again, 0.5 m higher): the count follows.
  std::vector<double> higher = position;
  for (std::uint64_t k = 0; k < added; ++k) higher[3 * k + 2] += 0.5;
  add.position = higher.data();
  ASSERT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << last_error(sim);
  quarry_view grown;
  ASSERT_EQ(quarry_view_particles(sim, QUARRY_FIELD_POSITION, &grown), QUARRY_OK)
      << last_error(sim);
  EXPECT_EQ(grown.count, n + added);
  EXPECT_EQ(std::memcmp(static_cast<const double*>(grown.data) + 3 * n, higher.data(),
                        higher.size() * sizeof(double)),
            0);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
  EXPECT_EQ(shared_mappings(prefix), 0);  // every segment unmapped with the handle
}

// The next step's loads written in place on a remote handle: the view's values come from the
// server (more than the request channel holds: through the socket) and go back before the next
// call; 15,000 particles move to the same bits as in process.
TEST(Serve, NextStepLoadsWrittenInPlaceReachTheServerAsInProcess) {
  Server server;
  quarry_sim remote, local;
  ASSERT_EQ(open(server.endpoint(), remote, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  quarry_open_info info = QUARRY_OPEN_INFO_INIT;
  ASSERT_EQ(quarry_open(&info, &local), QUARRY_OK);
  constexpr std::uint64_t added = 14999, n = added + 1;  // 360 kB of loads a field
  std::vector<double> position(3 * added);
  for (std::uint64_t k = 0; k < added; ++k) {
    position[3 * k] = 3e-3 * static_cast<double>(k % 100 + 1);  // m: spheres of 1 mm, apart
    position[3 * k + 1] = 3e-3 * static_cast<double>(k / 100);
  }
  for (quarry_sim sim : {remote, local}) {
    build_one_particle(sim);
    quarry_new_particles add = {sizeof add, added,   nullptr, 0,      position.data(),
                                nullptr,    nullptr, nullptr, nullptr};
    ASSERT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << last_error(sim);
  }
  for (int round = 0; round < 3; ++round) {
    for (quarry_sim sim : {remote, local}) {
      for (int field : {QUARRY_FIELD_FORCE, QUARRY_FIELD_TORQUE}) {
        quarry_view view;
        ASSERT_EQ(quarry_view_next_step_loads(sim, field, &view), QUARRY_OK) << last_error(sim);
        ASSERT_EQ(view.count, n);
        ASSERT_EQ(view.writable, 1u);
        auto* loads = static_cast<double*>(view.data);
        for (std::uint64_t k = 0; k < 3 * n; ++k) {
          ASSERT_EQ(loads[k], 0.0) << "round " << round << ": the loads after a step";
          loads[k] = (field == QUARRY_FIELD_FORCE ? 1e-6 : 1e-12) * static_cast<double>(k % 5 + round);
        }
      }
      ASSERT_EQ(quarry_step(sim, 1), QUARRY_OK) << last_error(sim);
    }
  }
  std::vector<double> x[2], v[2], w[2];
  for (int s = 0; s < 2; ++s) {
    x[s].resize(3 * n), v[s].resize(3 * n), w[s].resize(3 * n);
    quarry_particle_data data = {sizeof data, n,       nullptr, nullptr, x[s].data(),
                                 v[s].data(), w[s].data(), nullptr, nullptr, nullptr,
                                 nullptr,     nullptr, 0,       0};
    ASSERT_EQ(quarry_get_particles(s == 0 ? remote : local, &data), QUARRY_OK);
  }
  EXPECT_EQ(x[0], x[1]);
  EXPECT_EQ(v[0], v[1]);
  EXPECT_EQ(w[0], w[1]);
  EXPECT_GT(v[0][3 * 7], 0.0) << "the loads moved the particles";
  EXPECT_EQ(quarry_close(remote), QUARRY_OK);
  EXPECT_EQ(quarry_close(local), QUARRY_OK);
}

// The open reply names the last operation the server knows. A server from before the shared
// views (and the request channel) names none, or one that knows them not: the client asks neither
// of it (such a server would answer UNSUPPORTED) and takes each view from the reply.
void views_from_an_older_server(std::optional<wire::Op> last_op) {
  const std::string endpoint = ipc_endpoint();
  void* context = zmq_ctx_new();
  void* rep = zmq_socket(context, ZMQ_REP);
  ASSERT_EQ(zmq_bind(rep, endpoint.c_str()), 0);
  std::atomic<int> newer_asked{0}, plain_asked{0};
  const double values[6] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  std::thread fake([rep, last_op, &newer_asked, &plain_asked, &values] {
    const int wait_ms = 5000;
    zmq_setsockopt(rep, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
    std::vector<char> buffer(1 << 16);
    // open, view, view, close
    for (int k = 0; k < 4; ++k) {
      const int size = zmq_recv(rep, buffer.data(), buffer.size(), 0);
      if (size < 0) return;
      const wire::RequestHeader request = wire::read_request_header(buffer.data(), size);
      wire::Writer out;
      out.bytes().assign(wire::kReplyHeaderBytes, '\0');
      const auto op = static_cast<wire::Op>(request.op);
      std::string reply;
      if (op == wire::Op::open) {
        protocol::write_values(out, protocol::OpenReply{7, 1, "0.1.0"});
        if (last_op) out.put(static_cast<std::uint32_t>(*last_op));
      } else if (op == wire::Op::view_particles_shared || op == wire::Op::attach_channel) {
        newer_asked += 1;  // as a server before them answers
        reply = wire::error_reply(request.request_id, QUARRY_ERROR_UNSUPPORTED,
                                  "quarry serve: operation 42 is not one this server (ABI 1.1) "
                                  "knows (operations 1 to 41); is the client of a newer version?");
      } else if (op == wire::Op::view_particles) {
        plain_asked += 1;
        quarry_view view{};
        view.count = 2;
        view.dtype = QUARRY_DTYPE_FLOAT64;
        view.components = 3;
        view.stride = 24;
        view.epoch = 1;
        protocol::fields(out, view);
        out.align();
        out.raw(values, sizeof values);
      }
      if (reply.empty()) {
        wire::ReplyHeader header;
        header.request_id = request.request_id;
        wire::write_reply_header(out.bytes(), header);
        reply = out.bytes();
      }
      zmq_send(rep, reply.data(), reply.size(), 0);
    }
  });
  quarry_sim sim;
  ASSERT_EQ(open(endpoint, sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  for (int k = 0; k < 2; ++k) {
    quarry_view view;
    ASSERT_EQ(quarry_view_particles(sim, QUARRY_FIELD_POSITION, &view), QUARRY_OK)
        << last_error(sim);
    ASSERT_EQ(view.count, 2u);
    EXPECT_EQ(std::memcmp(view.data, values, sizeof values), 0);
  }
  EXPECT_EQ(quarry_close(sim), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  fake.join();
  EXPECT_EQ(newer_asked.load(), 0);
  EXPECT_EQ(plain_asked.load(), 2);
  zmq_close(rep);
  zmq_ctx_term(context);
  fs::remove(endpoint.substr(6));
}

TEST(Serve, AServerWithoutSharedViewsSendsThemInTheReply) {
  views_from_an_older_server(std::nullopt);                      // no last operation in its reply
  views_from_an_older_server(wire::Op::get_surface_loads);       // one before the shared views
}

// A server of ABI 1.1 (its open reply names attach_channel as its last operation) has no view of
// the next step's loads: the client refuses the call itself, UNSUPPORTED with both versions and
// the way out, and asks the server nothing.
TEST(Serve, AnAbi11ServerHasNoNextStepLoadsView) {
  const std::string endpoint = ipc_endpoint();
  void* context = zmq_ctx_new();
  void* rep = zmq_socket(context, ZMQ_REP);
  ASSERT_EQ(zmq_bind(rep, endpoint.c_str()), 0);
  std::vector<std::uint32_t> asked;
  std::thread fake([rep, &asked] {
    const int wait_ms = 5000;
    zmq_setsockopt(rep, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
    std::vector<char> buffer(1 << 16);
    for (int k = 0; k < 2; ++k) {  // open, close
      const int size = zmq_recv(rep, buffer.data(), buffer.size(), 0);
      if (size < 0) return;
      const wire::RequestHeader request = wire::read_request_header(buffer.data(), size);
      asked.push_back(request.op);
      wire::Writer out;
      out.bytes().assign(wire::kReplyHeaderBytes, '\0');
      if (static_cast<wire::Op>(request.op) == wire::Op::open) {
        protocol::write_values(out, protocol::OpenReply{7, 0, "0.1.0"});
        out.put(static_cast<std::uint32_t>(wire::Op::attach_channel));
      }
      wire::ReplyHeader header;
      header.request_id = request.request_id;
      header.abi_version = (1u << 16) | 1u;
      wire::write_reply_header(out.bytes(), header);
      zmq_send(rep, out.bytes().data(), out.bytes().size(), 0);
    }
  });
  quarry_sim sim;
  ASSERT_EQ(open(endpoint, sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  quarry_view view;
  EXPECT_EQ(quarry_view_next_step_loads(sim, QUARRY_FIELD_FORCE, &view), QUARRY_ERROR_UNSUPPORTED);
  const std::string text = last_error(sim);
  EXPECT_NE(text.find("ABI 1.1"), std::string::npos) << text;
  EXPECT_NE(text.find("ABI 1.2"), std::string::npos) << text;
  EXPECT_NE(text.find("quarry_set_external_loads"), std::string::npos) << text;
  EXPECT_EQ(quarry_close(sim), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  fake.join();
  EXPECT_EQ(asked, (std::vector<std::uint32_t>{static_cast<std::uint32_t>(wire::Op::open),
                                               static_cast<std::uint32_t>(wire::Op::close)}));
  zmq_close(rep);
  zmq_ctx_term(context);
  fs::remove(endpoint.substr(6));
}

// Periodic axes (ABI 1.1) set through a remote handle reach the server's simulation: a sphere
// leaving through the x face re-enters at the other; the server's checks come back as texts.
TEST(Serve, PeriodicSettingsReachTheServersSimulation) {
  Server server;
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  quarry_material glass = {sizeof glass, "glass", 2500.0, 1e7, 0.3};
  ASSERT_EQ(quarry_add_material(sim, &glass, nullptr), QUARRY_OK) << last_error(sim);
  quarry_interaction contact = {sizeof contact,      "glass", "glass", 0.5, 0.5, 0.0,
                                QUARRY_ROLLING_NONE, 0.0};
  ASSERT_EQ(quarry_add_interaction(sim, &contact), QUARRY_OK) << last_error(sim);
  quarry_particle_type bead = {sizeof bead, "bead", "glass", 5e-3, 0.0};
  ASSERT_EQ(quarry_add_particle_type(sim, &bead, nullptr), QUARRY_OK) << last_error(sim);
  quarry_settings settings = quarry_default_settings();
  settings.time_step = 1e-5, settings.gravity[2] = 0.0, settings.impact_speed = 1.0;
  settings.domain_min[2] = -0.05;
  settings.domain_max[0] = settings.domain_max[1] = 0.1, settings.domain_max[2] = 0.05;
  settings.periodic[0] = settings.periodic[1] = 1;
  quarry_settings short_x = settings;
  short_x.domain_max[0] = 0.03;  // 3 × (2 × 5 mm + 1 mm) = 33 mm needed
  EXPECT_EQ(quarry_set_settings(sim, &short_x), QUARRY_ERROR_BAD_VALUE);
  EXPECT_NE(last_error(sim).find("the period along x (0.03 m) is shorter"), std::string::npos)
      << last_error(sim);
  ASSERT_EQ(quarry_set_settings(sim, &settings), QUARRY_OK) << last_error(sim);
  ASSERT_EQ(quarry_start(sim), QUARRY_OK) << last_error(sim);
  double position[3] = {0.098, 0.05, 0.0}, velocity[3] = {1.0, 0.0, 0.0};
  quarry_new_particles add = {sizeof add, 1,       nullptr, 0,      position,
                              velocity,   nullptr, nullptr, nullptr};
  ASSERT_EQ(quarry_add_particles(sim, &add), QUARRY_OK) << last_error(sim);
  ASSERT_EQ(quarry_step(sim, 500), QUARRY_OK) << last_error(sim);  // 5 mm along +x
  quarry_particle_data data = {sizeof data, 1,       nullptr, nullptr, position, velocity, nullptr,
                               nullptr,     nullptr, nullptr, nullptr, nullptr,  0,        0};
  ASSERT_EQ(quarry_get_particles(sim, &data), QUARRY_OK) << last_error(sim);
  EXPECT_EQ(data.count, 1u);
  EXPECT_NEAR(position[0], 0.003, 1e-9);
  EXPECT_EQ(velocity[0], 1.0);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK);
}

// A server of ABI 1.0 (faked: 1.0 in its replies' headers, 1.0's settings read to the end): the
// client sends it the fields 1.0 knows, and refuses periodic axes that server would not honour
// instead of letting them drop.
TEST(Serve, AnAbi10ServerGetsItsOwnFieldsAndNoPeriodicAxes) {
  const std::string endpoint = ipc_endpoint();
  void* context = zmq_ctx_new();
  void* rep = zmq_socket(context, ZMQ_REP);
  ASSERT_EQ(zmq_bind(rep, endpoint.c_str()), 0);
  std::atomic<int> settings_read{0};
  std::thread fake([rep, &settings_read] {
    const int wait_ms = 5000;
    zmq_setsockopt(rep, ZMQ_RCVTIMEO, &wait_ms, sizeof wait_ms);
    std::vector<char> buffer(1 << 16);
    for (int k = 0; k < 3; ++k) {  // open, set_settings, close
      const int size = zmq_recv(rep, buffer.data(), buffer.size(), 0);
      if (size < 0) return;
      const wire::RequestHeader request = wire::read_request_header(buffer.data(), size);
      wire::Writer out;
      out.bytes().assign(wire::kReplyHeaderBytes, '\0');
      quarry_status status = QUARRY_OK;
      if (request.op == static_cast<std::uint32_t>(wire::Op::open)) {
        protocol::write_values(out, protocol::OpenReply{7, 0, "0.1.0"});
      } else if (request.op == static_cast<std::uint32_t>(wire::Op::set_settings)) {
        try {  // as a 1.0 server reads it: its fields, then nothing
          wire::Reader in(buffer.data(), size, wire::kRequestHeaderBytes);
          quarry_settings s{};
          protocol::fields(in, s, 1u << 16);
          in.expect_end();
          settings_read += 1;
        } catch (const wire::WireError&) {
          status = QUARRY_ERROR_TRANSPORT;
        }
      }
      wire::ReplyHeader header;
      header.abi_version = 1u << 16;
      header.status = status;
      header.request_id = request.request_id;
      wire::write_reply_header(out.bytes(), header);
      zmq_send(rep, out.bytes().data(), out.bytes().size(), 0);
    }
  });
  quarry_sim sim;
  ASSERT_EQ(open(endpoint, sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  quarry_settings settings = quarry_default_settings();
  settings.periodic[2] = 1;
  EXPECT_EQ(quarry_set_settings(sim, &settings), QUARRY_ERROR_UNSUPPORTED);
  const std::string text = last_error(sim);
  EXPECT_NE(text.find("speaks ABI 1.0, which has no periodic axes"), std::string::npos) << text;
  settings.periodic[2] = 0;
  EXPECT_EQ(quarry_set_settings(sim, &settings), QUARRY_OK) << last_error(sim);
  EXPECT_EQ(quarry_close(sim), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  fake.join();
  EXPECT_EQ(settings_read.load(), 1);
  zmq_close(rep);
  zmq_ctx_term(context);
  fs::remove(endpoint.substr(6));
}

TEST(Serve, SigtermStopsTheServerDuringAnAdvanceAndRemovesItsSocket) {
  Server server;
  const std::string path = server.endpoint().substr(6);
  EXPECT_TRUE(fs::exists(path));
  quarry_sim sim;
  ASSERT_EQ(open(server.endpoint(), sim, 5000), QUARRY_OK) << last_error(QUARRY_NO_SIM);
  build_one_particle(sim);
  std::atomic<quarry_status> status{QUARRY_OK};
  std::thread advance([&] { status = quarry_advance(sim, 1e5, nullptr); });
  std::this_thread::sleep_for(300ms);
  server.process().kill(SIGTERM);
  advance.join();
  EXPECT_EQ(status.load(), QUARRY_ERROR_TRANSPORT);
  EXPECT_NE(last_error(sim).find("stopping"), std::string::npos) << last_error(sim);
  EXPECT_EQ(server.process().wait_exit(5000), 0) << server.log();
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(server.wait_for("stopped (signal 15)", 1000)) << server.log();
  EXPECT_EQ(quarry_close(sim), QUARRY_ERROR_TRANSPORT);
}

}  // namespace
