// The request channel (api/channel.h) between two of its ends in one process: a request and its
// reply pass whole, in turn, also when the server end sleeps on the futex between them; a ring
// for a request on the socket is told apart; a reply that does not come ends the wait at its
// budget; a segment that is not a channel is refused.
#include "api/channel.h"

#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

namespace quarry::api {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

TEST(Channel, RequestsAndRepliesPassWholeAndInTurn) {
  std::unique_ptr<Channel> client = Channel::create();
  std::unique_ptr<Channel> server = Channel::attach(client->name());
  std::thread serving([&] {
    for (int k = 0; k < 200; ++k) {
      while (!server->wait_request(Channel::kSpin, 20ms)) {
      }
      bool oversized = true;
      const std::string request = server->take_request(oversized);
      EXPECT_FALSE(oversized);
      if (k % 50 == 49) std::this_thread::sleep_for(30ms);  // the client gives up spinning
      server->post_reply("reply to " + request);
    }
  });
  for (int k = 0; k < 200; ++k) {
    // Sizes from 1 byte to a reply that fills the whole area.
    const std::string request =
        k == 199 ? std::string(Channel::kCapacity - 9, 'x')
                 : std::string(static_cast<std::size_t>(1 + 37 * k), static_cast<char>('a' + k % 26));
    client->post_request(request);
    while (!client->wait_reply(20ms)) {
    }
    const auto reply = client->reply();
    ASSERT_EQ(std::string(reinterpret_cast<const char*>(reply.data()), reply.size()),
              "reply to " + request)
        << k;
    if (k % 50 == 24) std::this_thread::sleep_for(30ms);  // the server gives up spinning
  }
  serving.join();
}

TEST(Channel, ARingForTheSocketCarriesNoRequest) {
  std::unique_ptr<Channel> client = Channel::create();
  std::unique_ptr<Channel> server = Channel::attach(client->name());
  EXPECT_FALSE(server->wait_request(0us, 1ms));
  client->post_socket_request();
  ASSERT_TRUE(server->wait_request(0us, 100ms));
  bool oversized = true;
  EXPECT_TRUE(server->take_request(oversized).empty());
  EXPECT_FALSE(oversized);
  EXPECT_EQ(server->socket_posted(), 1u);
}

TEST(Channel, AReplyThatDoesNotComeEndsTheWaitAtItsBudget) {
  std::unique_ptr<Channel> client = Channel::create();
  client->post_request("anyone?");
  const auto start = Clock::now();
  EXPECT_FALSE(client->wait_reply(50ms));
  const double waited = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(waited, 0.045);
  EXPECT_LT(waited, 2.0);
}

TEST(Channel, MoreThanItsCapacityIsRefusedNotWritten) {
  std::unique_ptr<Channel> client = Channel::create();
  EXPECT_THROW(client->post_request(std::string(Channel::kCapacity + 1, 'x')), std::length_error);
  EXPECT_THROW(client->post_reply(std::string(Channel::kCapacity + 1, 'x')), std::length_error);
}

TEST(Channel, ASegmentThatIsNotAChannelIsRefused) {
  std::unique_ptr<SharedSegment> plain = SharedSegment::create(1 << 20);
  try {
    Channel::attach(plain->name());
    FAIL() << "attached";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a request channel"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace quarry::api
