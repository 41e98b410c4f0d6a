// The study's methods: a study chosen by name or given as a document (never a file named by a
// page), its session started under the operator's study directory, the participant's answers,
// moving on, and the stop — which releases the board at once on the urgent lane.
#include "palpa/serve/study_methods.h"

#include <filesystem>
#include <memory>

#include "palpa/host/study_runner.h"
#include "palpa/serve/params.h"
#include "study_desk.h"

namespace palpa::serve {
namespace {

using Json = rpc::Json;
namespace fs = std::filesystem;

BoardAnswer Ok(Json result) { return BoardAnswer{std::move(result), std::nullopt}; }

/// A name that may be a directory of its own: the participant id's rule.
std::optional<rpc::Error> CheckDirName(const std::string& what, const std::string& name) {
  const host::Outcome ok = host::CheckParticipant(name);
  if (ok.ok()) return std::nullopt;
  return BadParam(what + " \"" + name +
                  "\" cannot name a directory: 1 to 64 letters, digits, '_', '.' or '-', not "
                  "starting with '.' or '-'");
}

/// A file's name as the library reads names (a '/' or a .json name is a file).
bool NamesFile(const std::string& s) {
  return s.find('/') != std::string::npos ||
         (s.size() > 5 && s.compare(s.size() - 5, 5, ".json") == 0);
}

/// The study a page asked for: a server study or a built-in by name, or a document.
std::optional<rpc::Error> ReadStudy(const Json& value, const StudyServeOptions& o,
                                    host::Study& out) {
  if (value.is_string()) {
    const std::string& name = value.get_ref<const std::string&>();
    for (const ServerStudy& s : o.server_studies) {
      if (s.name == name) {
        out = s.study;
        return std::nullopt;
      }
    }
    if (NamesFile(name)) {
      return BadParam(
          "'study': a page names no file on the server — give a study's name "
          "(study.list), a study document, or start palpa serve with --study FILE");
    }
    const auto s = host::LoadStudy(name);
    if (!s.ok()) return BadParam("'study': " + s.message + " (study.list lists them)");
    out = s.value;
    return std::nullopt;
  }
  if (!value.is_object()) return BadParam("'study' must be a study's name or a study document");
  const auto conditions = value.find("conditions");
  if (conditions != value.end() && conditions->is_string() &&
      NamesFile(conditions->get_ref<const std::string&>())) {
    return BadParam(
        "'study': conditions: a page names no file on the server (a shipped "
        "stimulus set by name, or the conditions themselves)");
  }
  const auto s = host::ParseStudy(value.dump(2));
  if (!s.ok()) return BadParam("'study': " + s.message);
  out = s.value;
  out.source = "a page's document";
  return std::nullopt;
}

Json ListJson(const StudyServeOptions& o) {
  Json list = Json::array();
  const auto add = [&](const host::Study& s, const char* source) {
    Json blocks = Json::array();
    for (const host::StudyBlock& b : s.blocks) blocks.push_back(b.name);
    list.push_back({{"name", s.name},
                    {"description", s.description},
                    {"source", source},
                    {"fingers", s.fingers},
                    {"unit", s.unit},
                    {"conditions", s.conditions.size()},
                    {"blocks", blocks}});
  };
  for (const std::string& n : host::BuiltInStudies()) {
    const auto s = host::LoadStudy(n);
    if (s.ok()) add(s.value, "built in");
  }
  for (const ServerStudy& s : o.server_studies) add(s.study, "server");
  return {{"studies", list},
          {"sessions_possible", !o.study_dir.empty()},
          {"trigger_gpio", o.trigger_gpio.empty() ? Json(nullptr) : Json(o.trigger_gpio)}};
}

/// The finger flags of an answer: one boolean per finger.
std::optional<rpc::Error> ReadAnswer(const Json& p, int64_t& trial, host::StudyAnswer& a) {
  if (auto e = OnlyKnown(p, {"trial", "tumour", "fingers"})) return e;
  if (!p.contains("trial")) return BadParam("'trial' is missing (the trial asked)");
  if (auto e = ReadInteger(p["trial"], "trial", 0, 1000000, trial)) return e;
  if (!p.contains("tumour") || !p["tumour"].is_boolean())
    return BadParam("'tumour' must be true or false");
  a.tumour = p["tumour"].get<bool>();
  if (!p.contains("fingers") || !p["fingers"].is_array() || p["fingers"].size() > 64)
    return BadParam("'fingers' must be an array of booleans, one per finger");
  for (const Json& f : p["fingers"]) {
    if (!f.is_boolean()) return BadParam("'fingers' must be an array of booleans, one per finger");
    a.fingers.push_back(f.get<bool>());
  }
  return std::nullopt;
}

PreparedCall Refusal(const host::Outcome& o) { return {BadParam(o.message), nullptr}; }

PreparedCall Prepare(const std::shared_ptr<StudyDesk>& desk, const std::string& method,
                     const Json& p) {
  const auto answer_now = [](Json result) {  // read-only or already handed over: never queued
    PreparedCall c{std::nullopt, [result](host::Device&) { return Ok(result); }, false};
    c.urgent = true;
    return c;
  };
  if (method == "study.list") {
    if (auto e = OnlyKnown(p, {})) return {e, nullptr};
    return answer_now(ListJson(desk->options()));
  }
  if (method == "study.watch") {
    if (auto e = OnlyKnown(p, {"view"})) return {e, nullptr};
    const std::string view = p.contains("view") && p["view"].is_string() ? p["view"] : "";
    if (view != "participant" && view != "experimenter")
      return {BadParam("'view' must be \"participant\" or \"experimenter\""), nullptr};
    PreparedCall c = answer_now(nullptr);
    c.job = [desk, view](host::Device&) {
      return Ok({{"view", view},
                 {"state",
                  view == "participant" ? desk->ParticipantState() : desk->ExperimenterState()}});
    };
    c.join = "study." + view;
    c.join_alone = view == "participant";
    return c;
  }
  if (method == "study.start") {
    if (auto e = OnlyKnown(p, {"study", "participant", "resume"})) return {e, nullptr};
    const StudyServeOptions& o = desk->options();
    if (o.study_dir.empty())
      return {BadParam("no study directory: start palpa serve with --study-dir DIR"), nullptr};
    if (!p.contains("study")) return {BadParam("'study' is missing"), nullptr};
    host::Study study;
    if (auto e = ReadStudy(p["study"], o, study)) return {e, nullptr};
    if (!p.contains("participant") || !p["participant"].is_string())
      return {BadParam("'participant' must be a participant id (a string)"), nullptr};
    const std::string participant = p["participant"];
    if (auto e = CheckDirName("'participant'", participant)) return {e, nullptr};
    if (auto e = CheckDirName("the study's name", study.name)) return {e, nullptr};
    bool resume = false;
    if (auto e = ReadFlag(p, "resume", resume)) return {e, nullptr};
    const std::string shown = study.name + "/" + participant;
    const fs::path out = fs::path(o.study_dir) / study.name / participant;
    return {std::nullopt, [desk, study, participant, out, shown, resume](host::Device& d) {
              std::error_code ec;
              fs::create_directories(out.parent_path(), ec);
              const fs::path root = fs::weakly_canonical(desk->options().study_dir, ec);
              const fs::path real = fs::weakly_canonical(out, ec);
              if (ec || real.parent_path().parent_path() != root) {
                return BoardAnswer{nullptr, BadParam(shown + " leads out of the study directory")};
              }
              const host::Outcome started =
                  desk->Start(d, study, participant, out.string(), shown, resume);
              if (!started.ok()) return BoardAnswer{nullptr, Refused(started)};
              return Ok(desk->ExperimenterState());
            }};
  }
  if (method == "study.answer") {
    int64_t trial = 0;
    host::StudyAnswer a;
    if (auto e = ReadAnswer(p, trial, a)) return {e, nullptr};
    // Handed over here, on the server's thread: the answer's time is not held up behind the lane.
    if (const host::Outcome given = desk->Answer(static_cast<int>(trial), a); !given.ok())
      return Refusal(given);
    return answer_now({{"trial", trial}, {"accepted", true}});
  }
  if (method == "study.next") {
    if (auto e = OnlyKnown(p, {"trial"})) return {e, nullptr};
    int64_t trial = -1;
    if (p.contains("trial")) {
      if (auto e = ReadInteger(p["trial"], "trial", 0, 1000000, trial)) return {e, nullptr};
    }
    if (const host::Outcome moved = desk->Next(static_cast<int>(trial)); !moved.ok())
      return Refusal(moved);
    return answer_now({{"moved_on", true}});
  }
  if (method == "study.stop") {
    if (auto e = OnlyKnown(p, {})) return {e, nullptr};
    if (const host::Outcome stopped = desk->Stop("study.stop"); !stopped.ok())
      return Refusal(stopped);
    // Anyone may stop, as anyone may E-stop: the board released at once, not behind a set.
    PreparedCall c{std::nullopt,
                   [](host::Device& d) {
                     const host::Outcome r = d.Release();
                     if (!r.ok()) return BoardAnswer{nullptr, Refused(r)};
                     return Ok({{"stopped", true}, {"board_released", true}});
                   },
                   false};
    c.urgent = true;
    return c;
  }
  return {rpc::Error{rpc::kMethodNotFound, "method not found: '" + method + "'", nullptr}, nullptr};
}

}  // namespace

MethodGroup StudyMethods(StudyServeOptions options) {
  auto desk = std::make_shared<StudyDesk>(std::move(options));
  MethodGroup g;
  g.prefix = "study.";
  g.names = {"study.list",   "study.start", "study.watch",
             "study.answer", "study.next",  "study.stop"};
  // The participant's own acts: from a client in the participant's view, which has heard nothing
  // of the conditions, never from the experimenter's page or a bystander. Anyone may stop.
  g.channel_only = {{"study.answer", "study.participant"}, {"study.next", "study.participant"}};
  g.prepare = [desk](const std::string& method, const Json& params) {
    return Prepare(desk, method, params);
  };
  // The experimenter's control went (closed page, taken by another): the session stops with it;
  // the server releases the board.
  g.on_control_change = [desk] {
    if (desk->running()) desk->Stop("control changed hands");
  };
  g.channel_notifications = [desk] { return desk->Take(); };
  return g;
}

}  // namespace palpa::serve
