// libFuzzer: whatever a client sends the server's API, before any device sees it — a message read
// as JSON-RPC, each call prepared by the board's methods (the parameters checked), a request's
// Host, Origin and token judged, a target's text read. Nothing may throw or crash; a call that is
// prepared without an error names only fingers and lines the board has; a request let in beyond
// loopback carries the token.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "palpa/host/request_text.h"
#include "palpa/serve/board_methods.h"
#include "palpa/serve/params.h"
#include "palpa/serve/request_guard.h"
#include "palpa/serve/scene_methods.h"

namespace {

using namespace palpa::serve;

const std::string kToken = "0123456789abcdef0123456789abcdef";

palpa::protocol::HelloReply Board() {
  palpa::protocol::HelloReply b{};
  b.finger_count = 5;
  b.line_count = 7;
  return b;
}

void Message(const std::string& text) {
  static const MethodGroup board = BoardMethods(Board());
  static const MethodGroup scene = SceneMethods(Board(), {});  // scene documents read too
  const rpc::Parsed parsed = rpc::ParseMessage(text, 64);
  for (const rpc::Call& call : parsed.calls) {
    if (!call.params.is_object()) __builtin_trap();
    const MethodGroup& group = call.method.rfind("scene.", 0) == 0 ? scene : board;
    const PreparedCall prepared = group.prepare(call.method, call.params);
    if (!prepared.error && !prepared.job) __builtin_trap();  // nothing prepared, nothing refused
    std::vector<palpa::host::FingerRequest> targets;
    if (!ReadTargets(call.params, Board(), targets)) {
      for (const auto& t : targets) {
        if (t.finger >= 5 || !std::isfinite(t.request.value)) __builtin_trap();
      }
    }
    std::vector<std::pair<uint8_t, double>> setpoints;
    if (!ReadSetpoints(call.params, Board(), setpoints)) {
      for (const auto& [line, kpa] : setpoints) {
        if (line >= 7 || !std::isfinite(kpa)) __builtin_trap();
      }
    }
  }
  for (const rpc::Json& answer : parsed.answers) (void)rpc::Text(answer);
}

void Request(const std::string& text) {
  static const RequestGuard loopback = [] {
    ServeOptions o;
    return RequestGuard(o, 7180);
  }();
  static const RequestGuard remote = [] {
    ServeOptions o;
    o.listen = ParseListen("0.0.0.0:7180").value;
    o.token = kToken;
    o.allowed_hosts = {"lab.example"};
    return RequestGuard(o, 7180);
  }();
  RequestFacts r;
  std::string* fields[] = {&r.host, &r.origin, &r.target, &r.cookie, &r.authorization};
  size_t at = 0, field = 0;
  while (field < 5) {
    const size_t end = text.find('\n', at);
    *fields[field++] = text.substr(at, end == std::string::npos ? std::string::npos : end - at);
    if (end == std::string::npos) break;
    at = end + 1;
  }
  r.has_origin = !r.origin.empty();
  (void)loopback.Check(r);
  const GuardVerdict v = remote.Check(r);
  if (v.allowed && r.target.find(kToken) == std::string::npos &&
      r.cookie.find(kToken) == std::string::npos &&
      r.authorization.find(kToken) == std::string::npos)
    __builtin_trap();  // in without the token
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 3) {
    case 0:
      Message(text);
      break;
    case 1:
      Request(text);
      break;
    default: {
      const auto r = palpa::host::ParseRequestText(text);
      if (r.ok() && !std::isfinite(r.value.value)) __builtin_trap();
      (void)ParseListen(text);
    }
  }
  return 0;
}
