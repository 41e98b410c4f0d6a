// palpa render's --input URIs parsed, each kind with its own check.
#include "render_inputs.h"

#include <optional>

namespace palpa::cli {

host::Result<InputSource> ParseInputSource(const std::string& text) {
  using Source = host::Result<InputSource>;
  const auto fail = [&](const std::string& why) {
    return Source(protocol::Status::kInvalidArgument,
                  "--input " + text + ": " + why + " (" + kInputSyntax + ")");
  };
  InputSource s;
  const auto rest = [&](const char* scheme) {
    const std::string head = std::string(scheme) + ":";
    return text.rfind(head, 0) == 0 ? std::optional<std::string>(text.substr(head.size()))
                                    : std::nullopt;
  };
  if (auto p = rest("evdev")) {
    if (p->empty()) return fail("evdev: needs the event node's path");
    s.kind = InputSource::kEvdev, s.path = *p;
  } else if (auto u = rest("tactile-udp")) {
    const size_t colon = u->rfind(':');
    const std::string port = colon == std::string::npos ? *u : u->substr(colon + 1);
    // Loopback unless an address is named: frames are not authenticated (docs/threat_model.md).
    s.host = colon != std::string::npos ? u->substr(0, colon) : "127.0.0.1";
    if (s.host.empty()) return fail("an empty address before the port");
    if (port.empty() || port.size() > 5 ||
        port.find_first_not_of("0123456789") != std::string::npos || std::stoul(port) < 1 ||
        std::stoul(port) > 65535)
      return fail("the port must be 1 … 65535");
    s.kind = InputSource::kTactileUdp, s.port = static_cast<uint16_t>(std::stoul(port));
  } else if (auto f = rest("tactile-file")) {
    if (f->empty()) return fail("tactile-file: needs the stream's path");
    s.kind = InputSource::kTactileFile, s.path = *f;
  } else if (auto t = rest("file")) {
    if (t->empty()) return fail("file: needs the trajectory's path");
    s.path = *t;
  } else {
    const size_t colon = text.find(':');
    const size_t slash = text.find('/');
    if (colon != std::string::npos && (slash == std::string::npos || colon < slash) && colon > 1)
      return fail("unknown input kind \"" + text.substr(0, colon) + "\"");
    if (text.empty()) return fail("empty");
    s.path = text;
  }
  return s;
}

}  // namespace palpa::cli
