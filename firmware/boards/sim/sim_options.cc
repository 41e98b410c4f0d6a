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

bool Number(const std::string& name, const std::string& text, double lo, double hi, double& out,
            std::string* error) {
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(out >= lo && out <= hi)) {
    char range[64];
    std::snprintf(range, sizeof(range), "%g to %g", lo, hi);
    *error = name + " " + text + ": expected a number from " + range;
    return false;
  }
  return true;
}

bool ParseEffects(const std::string& list, Effects& effects, std::string* error) {
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
      double h = 0;
      if (!Number("--effects history", item.substr(8), 0.0, 0.5, h, error)) return false;
      effects.history = static_cast<float>(h);
    } else {
      *error = "--effects " + list + ": unknown effect '" + item +
               "' (expected creep, rate, history=FRACTION)";
      return false;
    }
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return true;
}

/// "tcp:HOST:PORT" / "udp:HOST:PORT" (or just the PORT: loopback) checked and written out in
/// full; a host outside 127.0.0.0/8 only with --allow-remote, and then with a warning.
bool CheckNetworkAddress(const std::string& option, std::string& spec, bool allow_remote,
                         std::vector<std::string>& warnings, std::string* error) {
  const size_t scheme = spec.find(':') + 1;
  const std::string rest = spec.substr(scheme);
  const size_t colon = rest.rfind(':');
  const std::string host = colon == std::string::npos ? "127.0.0.1" : rest.substr(0, colon);
  const std::string port = colon == std::string::npos ? rest : rest.substr(colon + 1);
  const std::string where = option + " " + spec + ": ";
  char* end = nullptr;
  const long n = std::strtol(port.c_str(), &end, 10);
  if (port.empty() || *end != '\0' || n < 0 || n > 65535) {
    *error = where + "the port must be a number from 0 to 65535";
    return false;
  }
  in_addr address{};
  if (inet_pton(AF_INET, host.c_str(), &address) != 1) {
    *error = where + "'" + host + "' is not an IPv4 address";
    return false;
  }
  if ((ntohl(address.s_addr) >> 24) != 127) {
    if (!allow_remote) {
      *error = where + host +
               " is not a loopback address: other hosts could reach it, and nothing palpa-sim "
               "serves is authenticated (--allow-remote serves it anyway)";
      return false;
    }
    warnings.push_back(option + " " + spec +
                       " is reachable from other hosts: anyone who reaches it can use it, nothing "
                       "there is authenticated");
  }
  spec = spec.substr(0, scheme) + host + ":" + port;
  return true;
}

}  // namespace

bool ParseSimCommandLine(const std::vector<std::string>& args, SimCommandLine& out,
                         std::string* error) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      out.help = true;
      return true;
    }
    if (arg == "--no-static-errors") {
      out.board.plant.static_errors = false;
      continue;
    }
    if (arg == "--allow-remote") {
      out.allow_remote = true;
      continue;
    }
    if (arg.rfind("--", 0) != 0) {
      *error = "unexpected argument '" + arg + "'";
      return false;
    }
    if (i + 1 >= args.size()) {
      *error = arg + ": a value is missing";
      return false;
    }
    const std::string& value = args[++i];
    double n = 0;
    if (arg == "--config") {
      out.board.config = value;
    } else if (arg == "--listen") {
      out.listen = value;
    } else if (arg == "--unit") {
      if (!Number(arg, value, 0, 1000, n, error)) return false;
      out.board.plant.unit = static_cast<uint32_t>(n);
    } else if (arg == "--seed") {
      if (!Number(arg, value, 0, 4294967295.0, n, error)) return false;
      out.board.plant.seed = static_cast<uint32_t>(n);
    } else if (arg == "--speed") {
      if (!Number(arg, value, 0.01, 100, n, error)) return false;
      out.speed = static_cast<float>(n);
    } else if (arg == "--plant") {
      if (!Number(arg, value, 0, 3, n, error) || n != static_cast<int>(n)) {
        *error = "--plant " + value + ": expected a level 0, 1, 2 or 3";
        return false;
      }
      out.board.plant.level = static_cast<int>(n);
    } else if (arg == "--effects") {
      if (!ParseEffects(value, out.board.plant.effects, error)) return false;
    } else if (arg == "--truth") {
      if (value.rfind("file:", 0) != 0 && value.rfind("tcp:", 0) != 0) {
        *error = "--truth " + value + ": expected file:PATH or tcp:HOST:PORT";
        return false;
      }
      out.truth = value;
    } else if (arg == "--stamp") {
      if (value.rfind("file:", 0) != 0 || value.size() == 5) {
        *error = "--stamp " + value + ": expected file:PATH";
        return false;
      }
      out.stamp_file = value.substr(5);
    } else if (arg == "--rig-modbus") {
      if (value.rfind("tcp:", 0) != 0 && value.rfind("rtu:", 0) != 0) {
        *error = "--rig-modbus " + value + ": expected tcp:HOST:PORT or rtu:PATH";
        return false;
      }
      out.rig_modbus = value;
    } else if (arg == "--rig-netft") {
      if (value.rfind("udp:", 0) != 0) {
        *error = "--rig-netft " + value + ": expected udp:HOST:PORT";
        return false;
      }
      out.rig_netft = value;
    } else if (arg == "--rig-finger") {
      if (!Number(arg, value, 0, 7, n, error) || n != static_cast<int>(n)) {
        *error = "--rig-finger " + value + ": expected a finger 0 to 7";
        return false;
      }
      out.rig_finger = static_cast<uint8_t>(n);
    } else if (arg == "--flash") {
      if (value.empty()) {
        *error = "--flash: expected a file";
        return false;
      }
      out.board.flash_file = value;
    } else if (arg == "--truth-every-ms") {
      if (!Number(arg, value, 1, 10000, n, error)) return false;
      out.truth_every_ms = static_cast<uint32_t>(n);
    } else {
      *error = "unknown option '" + arg + "'";
      return false;
    }
  }
  if (out.listen.empty()) {
    *error = "--listen is required (tcp:127.0.0.1:PORT or pty:PATH)";
    return false;
  }
  const std::pair<const char*, std::string*> addresses[] = {{"--listen", &out.listen},
                                                            {"--truth", &out.truth},
                                                            {"--rig-modbus", &out.rig_modbus},
                                                            {"--rig-netft", &out.rig_netft}};
  for (const auto& [option, spec] : addresses) {
    if ((spec->rfind("tcp:", 0) == 0 || spec->rfind("udp:", 0) == 0) &&
        !CheckNetworkAddress(option, *spec, out.allow_remote, out.warnings, error)) {
      return false;
    }
  }
  out.board.time_scale = out.speed;
  return true;
}

}  // namespace palpa::sim
