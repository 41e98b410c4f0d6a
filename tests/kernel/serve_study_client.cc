// Runs inside the guest (tests/kernel/gpio): a study session through `palpa serve`'s API, as the
// experimenter's and the participant's pages drive it — control taken, the participant's view
// joined, the study started, every trial answered "no tumour" — so that the server's trigger line
// pulses at each event on a gpio-mockup line.
//   palpa_guest_study_client serve:HOST:PORT STUDY PARTICIPANT
// Exit 0 when the session completed; 1 with the reason otherwise.
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "palpa/host/serve_client.h"

using palpa::host::ServeClient;

namespace {

int Fail(const std::string& why) {
  std::printf("study client: %s\n", why.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) return Fail("usage: palpa_guest_study_client serve:HOST:PORT STUDY PARTICIPANT");
  // The server was started just before: it listens once its board has answered.
  auto client = ServeClient::Connect(argv[1]);
  for (int i = 0; i < 100 && !client.ok(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    client = ServeClient::Connect(argv[1]);
  }
  if (!client.ok()) return Fail("cannot reach " + std::string(argv[1]) + ": " + client.message);
  ServeClient& c = *client.value;
  const auto list = c.Call("study.list");
  if (!list.ok() || !list.value["trigger_gpio"].is_string())
    return Fail("study.list names no trigger line: " +
                (list.ok() ? list.value.dump() : list.message));
  std::printf("study client: the server's trigger line is %s\n",
              list.value["trigger_gpio"].get<std::string>().c_str());
  for (const auto& [method, params] :
       {std::pair<const char*, nlohmann::json>{"control.take", nlohmann::json::object()},
        {"study.watch", {{"view", "participant"}}},
        {"study.start", {{"study", argv[2]}, {"participant", argv[3]}}}}) {
    const auto r = c.Call(method, params);
    if (!r.ok()) return Fail(std::string(method) + ": " + r.message);
  }
  int answered = 0;
  nlohmann::json n;
  while (c.NextNotification(n, 30)) {
    if (n["method"] != "notify_study_participant") continue;
    const nlohmann::json& p = n["params"];
    const std::string state = p["state"];
    if (state == "finished") {
      std::printf("study client: %d trials answered, the session complete\n", answered);
      return 0;
    }
    if (state == "stopped") return Fail("the session stopped");
    if (state == "break" && !c.Call("study.next").ok()) return Fail("study.next refused");
    if (state != "answer") continue;
    const nlohmann::json none = std::vector<bool>(p["fingers"].get<size_t>(), false);
    const auto r =
        c.Call("study.answer", {{"trial", p["trial"]}, {"tumour", false}, {"fingers", none}});
    if (!r.ok()) return Fail("study.answer: " + r.message);
    ++answered;
  }
  return Fail(c.closed() ? "the server closed the connection" : "no notification for 30 s");
}
