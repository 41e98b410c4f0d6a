// Parsing of palpa-sim's arguments, with an error that names the argument at fault.
#include "sim_options.h"

#include <arpa/inet.h>

#include <cstdio>
#include <cstdlib>
#include <utility>

namespace palpa::sim {

const char* const kSimUsage =
    "usage: palpa-sim --config NAME --listen tcp:HOST:PORT|pty:PATH [options]\n"
    "\n"
    "The simulated palpa board: the firmware core on a plant model, speaking the wire protocol.\n"
    "\n"
    "  --config NAME        board configuration: thesis-pneumatic-3, thesis-jamming-2,\n"
    "                       thesis-5finger, full-8\n"
    "  --listen SPEC        tcp:127.0.0.1:PORT (0 = any free port) or pty:PATH (a symlink to\n"
    "                       the pty; an existing PATH is replaced only if it is a link to a pty\n"
    "                       that is gone)\n"
    "  --unit N             simulated actuator unit (0 = nominal; others differ as real units do)\n"
    "  --seed N             regulator and sensor units, noise (default 1)\n"
    "  --speed X            virtual seconds per real second, 0.01 to 100 (default 1)\n"
    "  --plant LEVEL        0 ideal, 1 regulator, 2 actuator hysteresis, 3 sensors and rig "
    "(default 3)\n"
    "  --effects LIST       creep, rate, history=FRACTION (jamming vacuum-history effect)\n"
    "  --no-static-errors   regulators without static errors\n"
    "  --truth SPEC         stream true pressures, deformations and stiffnesses as JSON lines to\n"
    "                       file:PATH or tcp:127.0.0.1:PORT (a side channel: not in the protocol)\n"
    "  --truth-every-ms N   truth sample period in virtual ms (default 10)\n"
    "  --stamp file:PATH    write CLOCK_MONOTONIC stamps when a generation of line setpoints or\n"
    "                       finger targets is applied and when it first reaches the DAC, lines\n"
    "                       \"setpoints|targets GENERATION applied|dac NS\" (latency benchmarks)\n"
    "                       (file outputs are written whole: they appear when palpa-sim stops)\n"
    "  --rig-modbus SPEC    serve the calibration rig (linear stage and force sensor over the "
    "same\n"
    "                       plant and clock) by Modbus on tcp:127.0.0.1:PORT (0 = any free port)\n"
    "                       or rtu:PATH (115200 8N1; e.g. one end of a socat pty pair)\n"
    "  --rig-netft SPEC     serve the rig's force sensor as an ATI Net F/T (RDT over UDP) on\n"
    "                       udp:127.0.0.1:PORT (0 = any free port)\n"
    "  --rig-finger N       the finger under the rig's indenter (default 0)\n"
    "  --flash FILE         keep the board's flash in FILE (created when missing): its saved\n"
    "                       configuration, boot state and firmware slots survive a restart, as\n"
    "                       a board's do a power cycle (palpa sim start uses one per "
    "configuration)\n"
    "  --allow-remote       let --listen, --truth, --rig-modbus and --rig-netft bind addresses\n"
    "                       other than loopback (127.0.0.0/8); nothing palpa-sim serves is\n"
    "                       authenticated, so anyone who reaches such a port can use it\n"
    "  --help               this text\n"
    "\n"
    "A network address is HOST:PORT with an IPv4 HOST, or PORT alone for 127.0.0.1.\n";

namespace {

using hal::Done;
using hal::Opened;

/// Every refusal of an argument.
Done Refused(std::string why) { return {hal::Status::kBadValue, std::move(why)}; }

/// `text` as a number from `lo` to `hi`, into `out` (its type's value of it).
template <typename T>
Done Number(const std::string& name, const std::string& text, double lo, double hi, T& out) {
  char* end = nullptr;
  const double n = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(n >= lo && n <= hi)) {
    char range[64];
    std::snprintf(range, sizeof(range), "%g to %g", lo, hi);
    return Refused(name + " " + text + ": expected a number from " + range);
  }
  out = static_cast<T>(n);
  return {};
}

/// `text` as a whole number from 0 to `hi`, into `out`; anything else is refused with `expected`.
template <typename T>
Done Whole(const std::string& name, const std::string& text, int hi, const char* expected, T& out) {
  double n = 0;
  if (!Number(name, text, 0, hi, n).ok() || n != static_cast<int>(n))
    return Refused(name + " " + text + ": " + expected);
  out = static_cast<T>(n);
  return {};
}

Done ParseEffects(const std::string& list, Effects& effects) {
  size_t at = 0;
  while (at <= list.size()) {
    const size_t comma = list.find(',', at);
    const std::string item =
        list.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
    if (item == "creep") {
      effects.creep = true;
    } else if (item == "rate") {
      effects.rate = true;
    } else if (item.rfind("history=", 0) == 0) {
      const Done history = Number("--effects history", item.substr(8), 0.0, 0.5, effects.history);
      if (!history.ok()) return history;
    } else {
      return Refused("--effects " + list + ": unknown effect '" + item +
                     "' (expected creep, rate, history=FRACTION)");
    }
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return {};
}

/// "tcp:HOST:PORT" / "udp:HOST:PORT" (or just the PORT: loopback) checked and written out in
/// full; a host outside 127.0.0.0/8 only with --allow-remote, and then with a warning.
Done CheckNetworkAddress(const std::string& option, std::string& spec, bool allow_remote,
                         std::vector<std::string>& warnings) {
  const size_t scheme = spec.find(':') + 1;
  const std::string rest = spec.substr(scheme);
  const size_t colon = rest.rfind(':');
  const std::string host = colon == std::string::npos ? "127.0.0.1" : rest.substr(0, colon);
  const std::string port = colon == std::string::npos ? rest : rest.substr(colon + 1);
  const std::string where = option + " " + spec + ": ";
  char* end = nullptr;
  const long n = std::strtol(port.c_str(), &end, 10);
  if (port.empty() || *end != '\0' || n < 0 || n > 65535)
    return Refused(where + "the port must be a number from 0 to 65535");
  in_addr address{};
  if (inet_pton(AF_INET, host.c_str(), &address) != 1)
    return Refused(where + "'" + host + "' is not an IPv4 address");
  if ((ntohl(address.s_addr) >> 24) != 127) {
    if (!allow_remote) {
      return Refused(where + host +
                     " is not a loopback address: other hosts could reach it, and nothing "
                     "palpa-sim serves is authenticated (--allow-remote serves it anyway)");
    }
    warnings.push_back(option + " " + spec +
                       " is reachable from other hosts: anyone who reaches it can use it, nothing "
                       "there is authenticated");
  }
  spec = spec.substr(0, scheme) + host + ":" + port;
  return {};
}

/// `value` as the option `arg` (one that takes a value), into `out`.
Done TakeOption(const std::string& arg, const std::string& value, SimCommandLine& out) {
  if (arg == "--config") {
    out.board.config = value;
  } else if (arg == "--listen") {
    out.listen = value;
  } else if (arg == "--unit") {
    return Number(arg, value, 0, 1000, out.board.plant.unit);
  } else if (arg == "--seed") {
    return Number(arg, value, 0, 4294967295.0, out.board.plant.seed);
  } else if (arg == "--speed") {
    return Number(arg, value, 0.01, 100, out.speed);
  } else if (arg == "--plant") {
    return Whole(arg, value, 3, "expected a level 0, 1, 2 or 3", out.board.plant.level);
  } else if (arg == "--effects") {
    return ParseEffects(value, out.board.plant.effects);
  } else if (arg == "--truth") {
    if (value.rfind("file:", 0) != 0 && value.rfind("tcp:", 0) != 0)
      return Refused("--truth " + value + ": expected file:PATH or tcp:HOST:PORT");
    out.truth = value;
  } else if (arg == "--stamp") {
    if (value.rfind("file:", 0) != 0 || value.size() == 5)
      return Refused("--stamp " + value + ": expected file:PATH");
    out.stamp_file = value.substr(5);
  } else if (arg == "--rig-modbus") {
    if (value.rfind("tcp:", 0) != 0 && value.rfind("rtu:", 0) != 0)
      return Refused("--rig-modbus " + value + ": expected tcp:HOST:PORT or rtu:PATH");
    out.rig_modbus = value;
  } else if (arg == "--rig-netft") {
    if (value.rfind("udp:", 0) != 0)
      return Refused("--rig-netft " + value + ": expected udp:HOST:PORT");
    out.rig_netft = value;
  } else if (arg == "--rig-finger") {
    return Whole(arg, value, 7, "expected a finger 0 to 7", out.rig_finger);
  } else if (arg == "--flash") {
    if (value.empty()) return Refused("--flash: expected a file");
    out.board.flash_file = value;
  } else if (arg == "--truth-every-ms") {
    return Number(arg, value, 1, 10000, out.truth_every_ms);
  } else {
    return Refused("unknown option '" + arg + "'");
  }
  return {};
}

}  // namespace

Opened<SimCommandLine> ParseSimCommandLine(const std::vector<std::string>& args) {
  SimCommandLine out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      out.help = true;
      return out;
    }
    if (arg == "--no-static-errors") {
      out.board.plant.static_errors = false;
      continue;
    }
    if (arg == "--allow-remote") {
      out.allow_remote = true;
      continue;
    }
    Done taken;
    if (arg.rfind("--", 0) != 0) {
      taken = Refused("unexpected argument '" + arg + "'");
    } else if (i + 1 >= args.size()) {
      taken = Refused(arg + ": a value is missing");
    } else {
      taken = TakeOption(arg, args[++i], out);
    }
    if (!taken.ok()) return {taken.status, taken.message};
  }
  if (out.listen.empty())
    return {hal::Status::kBadValue, "--listen is required (tcp:127.0.0.1:PORT or pty:PATH)"};
  const std::pair<const char*, std::string*> addresses[] = {{"--listen", &out.listen},
                                                            {"--truth", &out.truth},
                                                            {"--rig-modbus", &out.rig_modbus},
                                                            {"--rig-netft", &out.rig_netft}};
  for (const auto& [option, spec] : addresses) {
    if (spec->rfind("tcp:", 0) != 0 && spec->rfind("udp:", 0) != 0) continue;
    const Done checked = CheckNetworkAddress(option, *spec, out.allow_remote, out.warnings);
    if (!checked.ok()) return {checked.status, checked.message};
  }
  out.board.time_scale = out.speed;
  return out;
}

}  // namespace palpa::sim
