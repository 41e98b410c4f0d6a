// RequestGuard: which Host, Origin and token a request may carry, rule by rule.
#include <string>

#include "palpa/serve/request_guard.h"

// CppUTest last: its new/delete macros break the standard headers included after it.
#include <CppUTest/TestHarness.h>

using palpa::serve::GuardVerdict;
using palpa::serve::ParseListen;
using palpa::serve::RequestFacts;
using palpa::serve::RequestGuard;
using palpa::serve::ServeOptions;

namespace {

ServeOptions Listening(const std::string& listen, const std::string& token = "") {
  ServeOptions o;
  o.listen = ParseListen(listen).value;
  o.token = token;
  return o;
}

GuardVerdict Check(const RequestGuard& g, const std::string& host, const char* origin = nullptr,
                   const std::string& target = "/") {
  RequestFacts r;
  r.host = host;
  r.has_origin = origin != nullptr;
  r.origin = origin ? origin : "";
  r.target = target;
  return g.Check(r);
}

const std::string kToken = "0123456789abcdef0123456789abcdef";

}  // namespace

TEST_GROUP(ServeListen){};

TEST(ServeListen, TakesAddressesAndRefusesNames) {
  CHECK_TRUE(ParseListen("127.0.0.1:7180").value.loopback);
  CHECK_TRUE(ParseListen("127.3.4.5:0").value.loopback);
  CHECK_TRUE(ParseListen("[::1]:7180").value.loopback);
  CHECK_FALSE(ParseListen("0.0.0.0:7180").value.loopback);
  CHECK_FALSE(ParseListen("192.168.1.5:80").value.loopback);
  CHECK_EQUAL(7180, ParseListen("127.0.0.1:7180").value.port);
  for (const char* bad : {"localhost:7180", "127.0.0.1", "127.0.0.1:65536", "127.0.0.1:-1",
                          "127.0.0.1:0x10", ":7180", "[::1]7180", "::1:7180", "127.0.0.1: 80"}) {
    CHECK_FALSE_TEXT(ParseListen(bad).ok(), bad);
  }
  STRCMP_CONTAINS("is not an IP address", ParseListen("lab.local:7180").message.c_str());
}

TEST_GROUP(ServeGuard){};

TEST(ServeGuard, LoopbackAnswersOnlyToLoopbackNamesOnItsPort) {
  const RequestGuard g(Listening("127.0.0.1:0"), 7180);
  CHECK_TRUE(Check(g, "127.0.0.1:7180").allowed);
  CHECK_TRUE(Check(g, "localhost:7180").allowed);
  CHECK_TRUE(Check(g, "LOCALHOST:7180").allowed);
  CHECK_TRUE(Check(g, "[::1]:7180").allowed);
  CHECK_FALSE(Check(g, "127.0.0.1:7181").allowed);
  CHECK_FALSE(Check(g, "127.0.0.1").allowed);              // port 80, not this one
  CHECK_FALSE(Check(g, "attacker.example:7180").allowed);  // DNS rebinding
  CHECK_FALSE(Check(g, "localhost.attacker.example:7180").allowed);
  CHECK_FALSE(Check(g, "192.168.1.5:7180").allowed);
  CHECK_FALSE(Check(g, "[::1:7180").allowed);
  CHECK_FALSE(Check(g, "127.0.0.1:7180:1").allowed);
  const GuardVerdict none = Check(g, "");
  CHECK_FALSE(none.allowed);
  CHECK_EQUAL(400, none.http_status);
  STRCMP_CONTAINS("is not this server", Check(g, "evil:7180").reason.c_str());
}

TEST(ServeGuard, OriginMustBeThisServersPage) {
  const RequestGuard g(Listening("127.0.0.1:0"), 7180);
  CHECK_TRUE(Check(g, "127.0.0.1:7180", "http://127.0.0.1:7180").allowed);
  CHECK_TRUE(Check(g, "127.0.0.1:7180", "http://localhost:7180").allowed);
  CHECK_TRUE(Check(g, "127.0.0.1:7180").allowed);  // a script: browsers always send Origin
  for (const char* bad :
       {"http://attacker.example", "null", "", "https://127.0.0.1:7180", "http://127.0.0.1:7181",
        "http://127.0.0.1:7180.attacker.example", "file://", "http://attacker.example:7180"}) {
    const GuardVerdict v = Check(g, "127.0.0.1:7180", bad);
    CHECK_FALSE_TEXT(v.allowed, bad);
    CHECK_EQUAL(403, v.http_status);
  }
}

TEST(ServeGuard, BeyondLoopbackEveryRequestNeedsTheToken) {
  const RequestGuard g(Listening("0.0.0.0:0", kToken), 7180);
  GuardVerdict v = Check(g, "10.0.0.2:7180");
  CHECK_FALSE(v.allowed);
  CHECK_EQUAL(401, v.http_status);
  CHECK_FALSE(Check(g, "10.0.0.2:7180", nullptr, "/?token=" + kToken.substr(1)).allowed);
  CHECK_FALSE(Check(g, "10.0.0.2:7180", nullptr, "/?token=" + kToken + "0").allowed);
  CHECK_FALSE(Check(g, "10.0.0.2:7180", nullptr, "/?xtoken=" + kToken).allowed);
  v = Check(g, "10.0.0.2:7180", nullptr, "/websocket?a=1&token=" + kToken);
  CHECK_TRUE(v.allowed);
  CHECK_TRUE(v.set_token_cookie);
  RequestFacts r;
  r.host = "10.0.0.2:7180";
  r.target = "/app.js";
  r.cookie = "other=1; palpa_token=" + kToken;
  CHECK_TRUE(g.Check(r).allowed);
  CHECK_FALSE(g.Check(r).set_token_cookie);
  r.cookie = "palpa_token=" + kToken.substr(0, 31) + "0";
  CHECK_FALSE(g.Check(r).allowed);
  r.cookie.clear();
  r.authorization = "Bearer " + kToken;
  CHECK_TRUE(g.Check(r).allowed);
  // Any IP address may name a non-loopback server; a DNS name only when allowed.
  CHECK_FALSE(Check(g, "lab.example:7180", nullptr, "/?token=" + kToken).allowed);
  ServeOptions named = Listening("0.0.0.0:0", kToken);
  named.allowed_hosts = {"Lab.Example"};
  const RequestGuard with_name(named, 7180);
  CHECK_TRUE(
      Check(with_name, "lab.example:7180", "http://lab.example:7180", "/?token=" + kToken).allowed);
}
