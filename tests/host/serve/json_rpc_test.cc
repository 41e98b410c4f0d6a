// JSON-RPC envelopes, control and pings: what each message becomes before any method sees it.
#include <string>

#include "palpa/host/request_text.h"
#include "palpa/serve/control.h"
#include "palpa/serve/json_rpc.h"
#include "palpa/serve/params.h"

// CppUTest last: its new/delete macros break the standard headers included after it.
#include <CppUTest/TestHarness.h>

namespace rpc = palpa::serve::rpc;
using palpa::serve::Control;
using palpa::serve::PingWatch;

namespace {

int FirstCode(const rpc::Parsed& p) {
  return p.answers.empty() ? 0 : p.answers.front()["error"]["code"].get<int>();
}

}  // namespace

TEST_GROUP(ServeJsonRpc){};

TEST(ServeJsonRpc, ReadsCallsAndNotifications) {
  rpc::Parsed p = rpc::ParseMessage(R"({"jsonrpc":"2.0","id":"a","method":"board.info"})", 64);
  CHECK_EQUAL(1u, p.calls.size());
  CHECK_FALSE(p.calls[0].notification);
  CHECK_TRUE(p.calls[0].params.is_object());
  p = rpc::ParseMessage(R"({"jsonrpc":"2.0","method":"board.estop"})", 64);
  CHECK_TRUE(p.calls[0].notification);
  p = rpc::ParseMessage(
      R"([{"jsonrpc":"2.0","id":1,"method":"a"},{"jsonrpc":"2.0","id":2,"method":"b"},3])", 64);
  CHECK_TRUE(p.batch);
  CHECK_EQUAL(2u, p.calls.size());
  CHECK_EQUAL(1u, p.answers.size());
}

TEST(ServeJsonRpc, RefusesEverythingElseWithTheRightCode) {
  CHECK_EQUAL(rpc::kParseError, FirstCode(rpc::ParseMessage("{", 64)));
  CHECK_EQUAL(rpc::kParseError, FirstCode(rpc::ParseMessage("\xff\xfe", 64)));
  CHECK_EQUAL(rpc::kParseError, FirstCode(rpc::ParseMessage("", 64)));
  for (const char* bad :
       {"1", "[]", "null", R"({"id":1,"method":"a"})", R"({"jsonrpc":"1.0","id":1,"method":"a"})",
        R"({"jsonrpc":"2.0","id":1})", R"({"jsonrpc":"2.0","id":1,"method":7})",
        R"({"jsonrpc":"2.0","id":1.5,"method":"a"})", R"({"jsonrpc":"2.0","id":{},"method":"a"})",
        R"({"jsonrpc":"2.0","id":1,"method":"a","extra":1})"}) {
    const rpc::Parsed p = rpc::ParseMessage(bad, 64);
    CHECK_TRUE_TEXT(p.calls.empty(), bad);
    CHECK_EQUAL_TEXT(rpc::kInvalidRequest, FirstCode(p), bad);
  }
  CHECK_EQUAL(
      rpc::kInvalidParams,
      FirstCode(rpc::ParseMessage(R"({"jsonrpc":"2.0","id":1,"method":"a","params":[1]})", 64)));
  std::string batch = "[";
  for (int i = 0; i < 65; ++i)
    batch += std::string(i ? "," : "") + R"({"jsonrpc":"2.0","id":1,"method":"a"})";
  CHECK_EQUAL(rpc::kInvalidRequest, FirstCode(rpc::ParseMessage(batch + "]", 64)));
  const std::string deep = std::string(30000, '[') + std::string(30000, ']');
  CHECK_EQUAL(rpc::kInvalidRequest, FirstCode(rpc::ParseMessage(deep, 64)));
}

TEST_GROUP(ServeParams){};

TEST(ServeParams, TargetsInEveryUnitAndNothingHalfRead) {
  palpa::protocol::HelloReply board{};
  board.finger_count = 5;
  std::vector<palpa::host::FingerRequest> out;
  const auto targets = rpc::Json::parse(
      R"({"targets":[{"finger":0,"level":2},{"finger":1,"normalized":0.5},{"finger":2,"mm":1.2},
                     {"finger":3,"n_per_mm":0.9},{"finger":4,"value":"-10kPa"}]})");
  CHECK_FALSE(palpa::serve::ReadTargets(targets, board, out).has_value());
  CHECK_EQUAL(5u, out.size());
  CHECK(out[4].request.kind == palpa::host::TargetKind::kPressureKpa);
  DOUBLES_EQUAL(-10, out[4].request.value, 0);
  for (const char* bad :
       {R"({"targets":[{"finger":5,"level":1}]})", R"({"targets":[{"finger":true,"level":1}]})",
        R"({"targets":[{"finger":0.0,"level":1}]})", R"({"targets":[{"finger":0,"level":1.5}]})",
        R"({"targets":[{"finger":0,"level":1,"mm":1}]})", R"({"targets":[{"finger":0}]})",
        R"({"targets":[{"finger":0,"value":"10kpa"}]})",
        R"({"targets":[{"finger":0,"level":1},{"finger":0,"level":2}]})", R"({"targets":[]})",
        R"({"targets":[{"finger":0,"mm":1e400}]})",
        R"({"targets":[{"finger":18446744073709551615,"level":1}]})",
        R"({"targets":[{"finger":0,"level":1}],"x":1})"}) {
    out.clear();
    const auto e = palpa::serve::ReadTargets(rpc::Json::parse(bad, nullptr, false), board, out);
    CHECK_TRUE_TEXT(e.has_value(), bad);
    CHECK_EQUAL_TEXT(rpc::kInvalidParams, e->code, bad);
  }
}

TEST(ServeParams, TheCommandLinesReadingOfAValue) {
  STRCMP_EQUAL("unknown unit 'kpa' (did you mean 10kPa?)",
               palpa::host::ParseRequestText("10kpa").message.c_str());
  CHECK(palpa::host::ParseRequestText("L2").value.kind == palpa::host::TargetKind::kLevel);
  CHECK_FALSE(palpa::host::ParseRequestText("").ok());
  CHECK_FALSE(palpa::host::ParseRequestText("inf").ok());
  CHECK_FALSE(palpa::host::ParseRequestText("1.5").ok());
}

TEST_GROUP(ServeControl){};

TEST(ServeControl, OneControllerPassedOnlyByForceAndReleasedWhenItLeaves) {
  Control c;
  CHECK_TRUE(c.Take(1, false, "").ok());
  const auto refused = c.Take(2, false, "client 1");
  CHECK_FALSE(refused.ok());
  CHECK_TRUE(c.Controls(1));
  CHECK_FALSE(c.Leave(2).release_board);  // a watcher leaving changes nothing
  const auto forced = c.Take(2, true, "client 1");
  CHECK_TRUE(forced.value.release_board);  // the new controller starts from a safe board
  CHECK_EQUAL(1u, *forced.value.previous);
  CHECK_TRUE(c.Leave(2).release_board);
  CHECK_FALSE(c.controller().has_value());  // nobody: a reconnecting client gets nothing back
}

TEST(ServeControl, GoneAfterThreeMissedPingsAndNotBefore) {
  PingWatch w(3);
  uint64_t seq = 0;
  CHECK_FALSE(w.Due(seq));  // ping 1
  w.Pong(seq);
  CHECK_FALSE(w.Due(seq));  // 2
  CHECK_FALSE(w.Due(seq));  // 3: 2 unanswered
  w.Pong(2);                // late, still alive
  CHECK_FALSE(w.Due(seq));  // 4
  CHECK_FALSE(w.Due(seq));  // 5
  CHECK_EQUAL(3, w.missed());
  CHECK_TRUE(w.Due(seq));  // 3, 4, 5 unanswered: gone
  w.Pong(99);              // a pong for a ping never sent counts for nothing
  CHECK_EQUAL(3, w.missed());
}
