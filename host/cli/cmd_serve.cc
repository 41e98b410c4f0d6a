// palpa serve: the board's session held by one process, its API and page served to browsers and
// scripts (docs/serve.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "cli.h"
#include "palpa/serve/scene_methods.h"
#include "palpa/serve/server.h"
#include "palpa/serve/study_methods.h"
#include "trigger_line.h"

namespace palpa::cli {

int CmdServe(Context& c, const std::vector<std::string>& args) {
  serve::ServeOptions options;
  std::vector<serve::ServerScene> scenes;
  serve::StudyServeOptions studies;
  const std::vector<std::string> known = {"--listen", "--device",    "--allow-host",
                                          "--web",    "--truth",     "--scene",
                                          "--study",  "--study-dir", "--trigger-gpio"};
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (std::find(known.begin(), known.end(), a) == known.end()) {
      const std::string near = Suggest(a, known);
      return Usage("serve", "unexpected argument '" + a + "'" +
                                (near.empty() ? "" : " (did you mean " + near + "?)"));
    }
    const host::Result<std::string> value = OptionValue(args, i);
    if (!value.ok()) return Usage("serve", value.message);
    ++i;
    if (a == "--listen") {
      const host::Result<serve::Endpoint> listen = serve::ParseListen(value.value);
      if (!listen.ok()) return Usage("serve", listen.message);
      options.listen = listen.value;
    } else if (a == "--device") {
      c.device_uri = value.value;
      c.throwaway = false;
    } else if (a == "--truth") {
      options.truth_address = value.value;
    } else if (a == "--scene") {  // the operator's file, read now; pages load it by name
      const auto spec = host::LoadScene(value.value);
      if (!spec.ok()) return Fail("serve", spec.status, spec.message, kExitUsage);
      const std::string name = spec.value.name.empty() ? value.value : spec.value.name;
      for (const serve::ServerScene& s : scenes) {
        if (s.name == name) return Usage("serve", "two --scene files named '" + name + "'");
      }
      scenes.push_back({name, spec.value});
    } else if (a == "--study") {  // likewise: read now, offered by its name
      const auto study = host::LoadStudy(value.value);
      if (!study.ok()) return Fail("serve", study.status, study.message, kExitUsage);
      for (const serve::ServerStudy& s : studies.server_studies) {
        if (s.name == study.value.name)
          return Usage("serve", "two --study files named '" + s.name + "'");
      }
      studies.server_studies.push_back({study.value.name, study.value});
    } else if (a == "--study-dir") {
      studies.study_dir = value.value;
    } else if (a == "--trigger-gpio") {
      studies.trigger_gpio = value.value;
    } else if (a == "--allow-host") {
      options.allowed_hosts.push_back(value.value);
    } else {
      options.web_root = value.value;
    }
  }
  if (options.web_root.empty()) options.web_root = serve::DefaultWebRoot();
  // The trigger line is taken before the board starts: a missing or busy line refuses to serve.
  if (!studies.trigger_gpio.empty()) {
    if (studies.study_dir.empty())
      return Usage("serve", "--trigger-gpio pulses at a study's events: it needs --study-dir DIR");
    auto opened = TriggerLine::Open(studies.trigger_gpio);
    if (!opened.ok()) return Fail("serve", opened.status, opened.message);
    std::shared_ptr<TriggerLine> line = opened.value;
    studies.on_trigger = [line](const host::TriggerEvent&) { line->Pulse("palpa serve"); };
  }
  if (!studies.study_dir.empty()) {  // made now: a mistyped path shows before any session
    std::error_code ec;
    std::filesystem::create_directories(studies.study_dir, ec);
    if (!std::filesystem::is_directory(studies.study_dir, ec))
      return Usage("serve", "--study-dir " + studies.study_dir + ": not a directory");
  }
  c.number_from = 0;  // the API numbers fingers and lines as the library's APIs do
  c.truth_wanted = options.truth_address.empty();  // a sim: board started here tells its truth
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  if (options.truth_address.empty()) options.truth_address = c.truth_address;
  studies.board = c.device_uri;
  studies.sim = host::SimProvenanceOf(d->link().Describe());  // nullopt on a real board
  studies.calibration_dir = c.options.calibration_dir;
  studies.use_calibrations = c.options.use_calibrations;
  auto server = serve::Server::Bind(
      *d, options,
      {serve::SceneMethods(d->info(), scenes), serve::StudyMethods(std::move(studies))});
  if (!server.ok()) return Fail("serve", server.status, server.message, kExitConnect);
  std::printf("palpa serve: %s on %s\n", d->link().Describe().c_str(), server.value->Url().c_str());
  if (!options.listen.loopback) {
    std::printf(
        "palpa serve: listening beyond loopback: every request needs the token in the URL above\n");
  }
  std::fflush(stdout);
  PollsInterruption polls;
  server.value->Run([] { return Interrupted(); });
  server.value.reset();  // every client gone; the session closes with the device (outputs safe)
  std::printf("palpa serve: stopped\n");
  return kExitOk;
}

const Command kServeCommand{
    "serve",
    "serve [--device URI] [--listen ADDRESS:PORT] [--allow-host NAME]... [--scene FILE]... "
    "[--study-dir DIR] [--study FILE]... [--trigger-gpio CHIP:LINE] [--web DIR] "
    "[--truth tcp:HOST:PORT]",
    "Holds the board's session and serves its JSON-RPC 2.0 API over a WebSocket (/websocket)\n"
    "and the page (/), for browsers and scripts (docs/serve.md). One client controls the board,\n"
    "the others watch; a controlling client that goes away (three unanswered pings, 100 ms\n"
    "apart) leaves the board released. Loopback only by default (127.0.0.1:7180); another\n"
    "--listen address needs the token printed at start. A simulated board (sim:) started here\n"
    "tells each finger's true output too; --truth reads it from a palpa-sim started with --truth.\n"
    "Pages load scenes whose tissue is a preset or a phantom; --scene FILE offers a scene file\n"
    "(its tissue from files beside it) by its name.\n"
    "Studies run in the browser (/study.html for the experimenter, /participant.html for the\n"
    "participant) with --study-dir DIR: each session goes to DIR/STUDY/PARTICIPANT, journalled as\n"
    "palpa study run journals it; --study FILE offers a study file by its name;\n"
    "--trigger-gpio CHIP:LINE pulses a GPIO line (libgpiod) for 10 ms at each trigger event.\n"
    "Ctrl-C stops it and closes the session.",
    CmdServe};

}  // namespace palpa::cli
