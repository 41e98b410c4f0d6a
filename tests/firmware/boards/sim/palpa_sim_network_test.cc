// palpa-sim among neighbours: its ports are loopback unless a flag says otherwise (and then it
// warns), its Net F/T answers only the address that asked and only for a bounded count, its
// Modbus server and its board link take a bounded number of clients, and its pty link replaces
// only its own link.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "mini_client.h"
#include "sim_process.h"

#include "CppUTest/TestHarness.h"

using palpa::testing::SimProcess;

namespace {

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

int PortOf(const std::string& address) {
  return std::atoi(address.c_str() + address.rfind(':') + 1);
}

sockaddr_in Loopback(int port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return a;
}

/// A UDP socket on loopback that sends RDT requests to the simulated Net F/T.
struct RdtClient {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in server{};
  explicit RdtClient(int port) : server(Loopback(port)) {}
  ~RdtClient() { close(fd); }
  void Request(uint16_t command, uint32_t count) {
    const uint8_t r[8] = {0x12,
                          0x34,
                          static_cast<uint8_t>(command >> 8),
                          static_cast<uint8_t>(command),
                          static_cast<uint8_t>(count >> 24),
                          static_cast<uint8_t>(count >> 16),
                          static_cast<uint8_t>(count >> 8),
                          static_cast<uint8_t>(count)};
    sendto(fd, r, sizeof(r), 0, reinterpret_cast<const sockaddr*>(&server), sizeof(server));
  }
  /// Records that arrive until none has come for `quiet_ms`; -1 when they still come after 3 s.
  int Count(int quiet_ms) {
    int n = 0;
    uint8_t record[64];
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (std::chrono::steady_clock::now() < give_up) {
      pollfd p{fd, POLLIN, 0};
      if (poll(&p, 1, quiet_ms) <= 0) return n;
      if (recv(fd, record, sizeof(record), 0) == 36) ++n;
    }
    return -1;
  }
};

/// A Modbus TCP "read input registers 0..1" request; true when an answer comes.
bool ModbusAnswers(int fd) {
  const uint8_t request[12] = {0, 1, 0, 0, 0, 6, 1, 4, 0, 0, 0, 2};
  if (send(fd, request, sizeof(request), MSG_NOSIGNAL) != sizeof(request)) return false;
  pollfd p{fd, POLLIN, 0};
  uint8_t reply[64];
  return poll(&p, 1, 2000) > 0 && recv(fd, reply, sizeof(reply), 0) > 0;
}

}  // namespace

TEST_GROUP(PalpaSimNetwork){};

TEST(PalpaSimNetwork, OnlyLoopbackUnlessAFlagSaysOtherwiseAndThenItWarns) {
  const std::vector<std::vector<std::string>> wide = {
      {"--listen", "tcp:0.0.0.0:0"},
      {"--listen", "tcp:127.0.0.1:0", "--truth", "tcp:0.0.0.0:0"},
      {"--listen", "tcp:127.0.0.1:0", "--rig-modbus", "tcp:0.0.0.0:0"},
      {"--listen", "tcp:127.0.0.1:0", "--rig-netft", "udp:0.0.0.0:0"},
  };
  for (const auto& options : wide) {
    const std::string& option = options[options.size() - 2];
    std::vector<std::string> args = {"--config", "thesis-pneumatic-3"};
    args.insert(args.end(), options.begin(), options.end());
    SimProcess refused;
    CHECK_FALSE_TEXT(refused.Start(args), option.c_str());
    LONGS_EQUAL_TEXT(2, refused.Stop(), refused.output().c_str());
    CHECK_TEXT(Contains(refused.output(),
                        option + " " + options.back() + ": 0.0.0.0 is not a loopback address"),
               refused.output().c_str());
    CHECK_TEXT(Contains(refused.output(), "--allow-remote"), refused.output().c_str());
    args.push_back("--allow-remote");
    SimProcess allowed;
    CHECK_TEXT(allowed.Start(args), allowed.output().c_str());
    CHECK_TEXT(Contains(allowed.output(), "palpa-sim: warning: " + option + " " + options.back() +
                                              " is reachable from other hosts"),
               allowed.output().c_str());
    LONGS_EQUAL(0, allowed.Stop());
  }
  // A port alone means loopback.
  SimProcess plain;
  CHECK_TEXT(plain.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:0"}),
             plain.output().c_str());
  CHECK_TEXT(Contains(plain.address(), "tcp:127.0.0.1:"), plain.address().c_str());
  CHECK_FALSE(Contains(plain.output(), "warning"));
  LONGS_EQUAL(0, plain.Stop());
}

TEST(PalpaSimNetwork, NetFtStreamsOnlyToWhoAskedAndNeverForever) {
  SimProcess sim;
  CHECK_TEXT(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0",
                        "--rig-netft", "udp:127.0.0.1:0", "--speed", "10"}),
             sim.output().c_str());
  const int port = PortOf(sim.netft_address());
  RdtClient asker(port), bystander(port);
  // "Until told to stop" is bounded: at most a second of board time (1000 records; a busy
  // machine may drop some datagrams, never add any), then the stream ends.
  asker.Request(2, 0);
  // A bias request from someone else does not turn the stream towards them.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  bystander.Request(0x42, 0);
  int streamed = asker.Count(300);
  CHECK_TEXT(streamed >= 1 && streamed <= 1000, std::to_string(streamed).c_str());
  LONGS_EQUAL(0, bystander.Count(100));
  // A count larger than the bound is cut to it as well; a single record is one record.
  asker.Request(2, 5000000);
  streamed = asker.Count(300);
  CHECK_TEXT(streamed >= 1 && streamed <= 1000, std::to_string(streamed).c_str());
  asker.Request(2, 1);
  LONGS_EQUAL(1, asker.Count(200));
  LONGS_EQUAL(0, sim.Stop());
}

TEST(PalpaSimNetwork, ModbusTakesABoundedNumberOfClients) {
  SimProcess sim;
  CHECK_TEXT(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0",
                        "--rig-modbus", "tcp:127.0.0.1:0"}),
             sim.output().c_str());
  const sockaddr_in server = Loopback(PortOf(sim.rig_address()));
  std::vector<int> clients;
  for (int i = 0; i < 6; ++i) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    CHECK(connect(fd, reinterpret_cast<const sockaddr*>(&server), sizeof(server)) == 0);
    clients.push_back(fd);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // accepted in this order
  }
  for (int i = 0; i < 4; ++i) CHECK_TEXT(ModbusAnswers(clients[i]), std::to_string(i).c_str());
  for (int i = 4; i < 6; ++i)
    CHECK_FALSE_TEXT(ModbusAnswers(clients[i]), std::to_string(i).c_str());
  // A place freed is a place taken.
  close(clients[0]);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const int late = socket(AF_INET, SOCK_STREAM, 0);
  CHECK(connect(late, reinterpret_cast<const sockaddr*>(&server), sizeof(server)) == 0);
  CHECK(ModbusAnswers(late));
  close(late);
  for (int i = 1; i < 6; ++i) close(clients[i]);
  LONGS_EQUAL(0, sim.Stop());
}

TEST(PalpaSimNetwork, TheBoardLinkTakesABoundedNumberOfHosts) {
  namespace pp = palpa::protocol;
  SimProcess sim;
  CHECK_TEXT(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0"}),
             sim.output().c_str());
  const int port = PortOf(sim.address());
  std::vector<palpa::testing::MiniClient> hosts(10);
  for (auto& host : hosts) {
    CHECK(host.ConnectTcp("127.0.0.1", port));
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // accepted in this order
  }
  // The first host opens a session; a second is told busy. Everything the board says reaches
  // the eight hosts on the line, and nothing the two turned away.
  CHECK(hosts[0].Hello(1).ok());
  hosts[1].Send(pp::Hello{2, 0});
  for (size_t i = 0; i < hosts.size(); ++i) {
    bool busy = false;
    for (const auto& f : hosts[i].Read(300)) {
      busy |= f.Is<pp::Nack>() && f.As<pp::Nack>().status == pp::Status::kBusy;
    }
    CHECK_TEXT(busy == (i < 8), std::to_string(i).c_str());
  }
  for (auto& host : hosts) host.Close();
  LONGS_EQUAL(0, sim.Stop());
}

TEST(PalpaSimNetwork, APtyLinkReplacesOnlyItsOwnStaleLink) {
  const std::string path = "/tmp/palpa-sim-pty-" + std::to_string(getpid());
  // A user's file where the link would go: refused and kept.
  std::ofstream(path) << "a user's file";
  SimProcess refused;
  CHECK_FALSE(refused.Start({"--config", "thesis-pneumatic-3", "--listen", "pty:" + path}));
  LONGS_EQUAL(1, refused.Stop());
  CHECK_TEXT(Contains(refused.output(), path + " exists and is not a pty link"),
             refused.output().c_str());
  std::ifstream kept(path);
  std::string contents;
  std::getline(kept, contents);
  STRCMP_EQUAL("a user's file", contents.c_str());
  std::remove(path.c_str());
  // A link to a pty that is gone (a simulator that was killed): replaced.
  CHECK(symlink("/dev/pts/999999", path.c_str()) == 0);
  SimProcess first;
  CHECK_TEXT(first.Start({"--config", "thesis-pneumatic-3", "--listen", "pty:" + path}),
             first.output().c_str());
  // A link to a pty in use (another simulator's): refused, and the other keeps its link.
  SimProcess second;
  CHECK_FALSE(second.Start({"--config", "thesis-pneumatic-3", "--listen", "pty:" + path}));
  CHECK_TEXT(Contains(second.output(), "in use"), second.output().c_str());
  second.Stop();
  struct stat st;
  CHECK(lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode));
  // On exit a simulator removes its link, but not what someone put there meanwhile.
  std::remove(path.c_str());
  std::ofstream(path) << "new";
  LONGS_EQUAL(0, first.Stop());
  CHECK(lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode));
  std::remove(path.c_str());
}
