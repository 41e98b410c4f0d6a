// palpa-gadget: a board's USB side in device mode (vendor bulk, HID, CDC-ACM), bridged to a
// simulated board (palpa-sim) over TCP, so host programs meet a real USB stack.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "frame_gate.h"
#include "gadget_link.h"

namespace {

const char kUsage[] =
    "usage: palpa-gadget --sim tcp:HOST:PORT [options]\n"
    "\n"
    "Presents a palpa board over USB device mode and carries its byte stream to and from a\n"
    "simulated board (palpa-sim --listen tcp:...). Needs configfs, libcomposite, usb_f_fs,\n"
    "usb_f_acm and a USB device controller (dummy_hcd for tests).\n"
    "\n"
    "  --sim tcp:HOST:PORT   the simulated board to bridge to\n"
    "  --udc NAME            USB device controller (default: the first in /sys/class/udc)\n"
    "  --name NAME           configfs gadget name (default palpa)\n"
    "  --serial TEXT         USB serial number string (default 0001)\n"
    "  --functions LIST      any of bulk,hid,acm (default all three)\n"
    "  --speed full|high     the fastest speed offered (default full, as an MCU's USB)\n"
    "  --help                this text\n";

volatile sig_atomic_t g_stop = 0;
volatile sig_atomic_t g_report = 0;
void OnSignal(int) { g_stop = 1; }
void OnReport(int) { g_report = 1; }

/// What the link has carried, for a person or a benchmark (on SIGUSR1 and on exit).
void Report(const palpa::gadget::GadgetLink& link, const palpa::gadget::FrameGate& gate) {
  const auto& c = link.counters();
  using palpa::gadget::Channel;
  auto at = [](const uint64_t* v, Channel ch) {
    return static_cast<unsigned long long>(v[static_cast<int>(ch)]);
  };
  std::printf(
      "palpa-gadget: active %s; from the host: bulk %llu, hid %llu, acm %llu bytes; to the host: "
      "bulk %llu, hid %llu (in %llu reports), acm %llu bytes; dropped %llu bytes, %llu telemetry "
      "frames\n",
      palpa::gadget::ChannelName(link.active()), at(c.bytes_from_host, Channel::kBulk),
      at(c.bytes_from_host, Channel::kHid), at(c.bytes_from_host, Channel::kAcm),
      at(c.bytes_to_host, Channel::kBulk), at(c.bytes_to_host, Channel::kHid),
      static_cast<unsigned long long>(c.hid_reports), at(c.bytes_to_host, Channel::kAcm),
      static_cast<unsigned long long>(c.dropped),
      static_cast<unsigned long long>(gate.telemetry_dropped()));
  std::fflush(stdout);
}

struct Options {
  std::string sim;
  palpa::gadget::GadgetLinkOptions link;
};

bool Parse(int argc, char** argv, Options& o, std::string* error) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    if (i + 1 >= argc) {
      *error = arg + ": " + (arg.rfind("--", 0) == 0 ? "expected a value" : "unexpected argument");
      return false;
    }
    const std::string value = argv[++i];
    if (arg == "--sim") {
      o.sim = value;
    } else if (arg == "--udc") {
      o.link.udc = value;
    } else if (arg == "--name") {
      o.link.name = value;
    } else if (arg == "--serial") {
      o.link.identity.serial = value;
    } else if (arg == "--speed") {
      if (value != "full" && value != "high") {
        *error = "--speed " + value + ": expected full or high";
        return false;
      }
      o.link.identity.max_speed = value + "-speed";
    } else if (arg == "--functions") {
      o.link.bulk = o.link.hid = o.link.acm = false;
      size_t at = 0;
      while (at <= value.size()) {
        const size_t comma = value.find(',', at);
        const std::string f = value.substr(at, comma == std::string::npos ? comma : comma - at);
        if (f == "bulk") {
          o.link.bulk = true;
        } else if (f == "hid") {
          o.link.hid = true;
        } else if (f == "acm") {
          o.link.acm = true;
        } else {
          *error = "--functions " + value + ": unknown function '" + f + "' (bulk, hid, acm)";
          return false;
        }
        if (comma == std::string::npos) break;
        at = comma + 1;
      }
    } else {
      *error = arg + ": unknown option";
      return false;
    }
  }
  if (o.sim.rfind("tcp:", 0) != 0 || o.sim.rfind(':') <= 4) {
    *error = "--sim " + (o.sim.empty() ? std::string("is required") : o.sim) +
             ": expected tcp:HOST:PORT";
    return false;
  }
  return true;
}

int ConnectTcp(const std::string& spec) {
  const size_t colon = spec.rfind(':');
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(std::atoi(spec.c_str() + colon + 1)));
  if (inet_pton(AF_INET, spec.substr(4, colon - 4).c_str(), &address.sin_addr) != 1) return -1;
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return -1;
  }
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return fd;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!Parse(argc, argv, o, &error)) {
    std::fprintf(stderr, "palpa-gadget: %s\n(see palpa-gadget --help)\n", error.c_str());
    return 2;
  }
  int sim = ConnectTcp(o.sim);
  if (sim < 0) {
    std::fprintf(stderr, "palpa-gadget: --sim %s: cannot connect: %s\n", o.sim.c_str(),
                 std::strerror(errno));
    return 1;
  }
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  struct sigaction report {};
  report.sa_handler = OnReport;
  sigaction(SIGUSR1, &report, nullptr);
  signal(SIGPIPE, SIG_IGN);

  palpa::gadget::GadgetLink link;
  if (!link.Open(o.link, &error)) {
    std::fprintf(stderr, "palpa-gadget: %s\n", error.c_str());
    return 1;
  }
  const auto& id = o.link.identity;
  if (link.stale_removed())
    std::printf("palpa-gadget: removed the gadget a program that died left behind\n");
  std::printf("palpa-gadget: usb %04x:%04x \"%s\" serial %s on %s (%s)\n", id.vendor, id.product,
              id.product_name.c_str(), id.serial.c_str(), link.udc().c_str(), id.max_speed.c_str());
  std::printf("palpa-gadget: configfs %s\n", link.configfs_path().c_str());
  if (!link.acm_device().empty()) std::printf("palpa-gadget: acm %s\n", link.acm_device().c_str());
  std::printf("palpa-gadget: bridged to %s\n", o.sim.c_str());
  std::fflush(stdout);

  // The simulator is read as fast as it writes; the gate keeps to what a board's transmit
  // buffer holds (whole telemetry frames dropped when the host does not take them).
  palpa::gadget::FrameGate gate;
  std::vector<uint8_t> to_sim;
  uint8_t buffer[4096];
  while (!g_stop) {
    if (g_report) {
      g_report = 0;
      Report(link, gate);
    }
    std::vector<pollfd> fds = link.PollFds();
    fds.push_back(pollfd{sim, static_cast<short>(POLLIN | (to_sim.empty() ? 0 : POLLOUT)), 0});
    poll(fds.data(), fds.size(), link.PollTimeoutMs() < 0 ? 100 : link.PollTimeoutMs());
    link.Pump();
    size_t n;
    while ((n = link.Read(buffer, sizeof(buffer))) > 0)
      to_sim.insert(to_sim.end(), buffer, buffer + n);
    if (!to_sim.empty()) {
      const ssize_t w = send(sim, to_sim.data(), to_sim.size(), MSG_DONTWAIT);
      if (w > 0) to_sim.erase(to_sim.begin(), to_sim.begin() + w);
    }
    gate.Flush(link);
    ssize_t r;
    while ((r = recv(sim, buffer, sizeof(buffer), MSG_DONTWAIT)) > 0)
      gate.FromBoard(buffer, static_cast<size_t>(r), link);
    if (r == 0 || (r < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
      std::fprintf(stderr, "palpa-gadget: the simulated board closed the connection\n");
      break;
    }
    link.Pump();
  }
  Report(link, gate);
  link.Close();
  close(sim);
  std::printf("palpa-gadget: stopped\n");
  return 0;
}
