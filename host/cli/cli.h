// The palpa command line: shared context, exit codes and the commands' entry points.
#pragma once

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_signals.h"
#include "palpa/host/device.h"

namespace palpa::cli {

/// Exit codes (docs/cli.md).
enum Exit : int {
  kExitOk = 0,
  kExitFailed = 1,   ///< the board refused, or did not answer
  kExitUsage = 2,    ///< a malformed command line: nothing was sent
  kExitConnect = 3,  ///< the device could not be opened
};

struct Context {
  std::string device_uri;
  /// The device is a simulator started for this one command (no --device, no $PALPA_DEVICE and
  /// no `palpa sim start`): what the command changes is gone when it exits, and it says so.
  bool throwaway = false;
  /// No --device, no $PALPA_DEVICE, no kept simulator: device_uri is the default
  /// (sim:thesis-5finger), and a command may choose a simulated board that fits it instead.
  bool device_defaulted = false;
  bool json = false;
  host::DeviceOptions options;  ///< how Device() opens it
  /// How the device's messages number fingers and lines: from 1, as the command line does, or
  /// from 0 for a command whose clients number as the library's APIs do (serve).
  uint8_t number_from = 1;
  /// A simulated device (sim:) is started with its truth side channel, and Device() says where
  /// in truth_address (serve plots the true output beside the estimate).
  bool truth_wanted = false;
  std::string truth_address;
  /// Opens the device on first use; prints the error and returns nullptr when it cannot.
  host::Device* Device();
  std::unique_ptr<host::Device> device;
  std::unique_ptr<ClosedOnSignal> closed_on_signal;  ///< released before the device closes
};

/// --json: every command prints JSON, errors included. Set once, before a command runs.
void SetJsonOutput(bool json);
bool JsonOutput();
/// Where a command's text report goes: stdout, or with --json stderr (as progress), so that stdout
/// carries only JSON.
FILE* TextOut();
/// One JSON document on a line of its own on stdout.
void PrintJson(const nlohmann::ordered_json& j);
/// A failure: "palpa WHAT: MESSAGE" on stderr, or with --json
/// {"error": {"status", "message", "command", "exit_code"}} on stdout. Returns exit_code.
int Fail(const std::string& what, protocol::Status status, const std::string& message,
         int exit_code = kExitFailed);
/// A usage error: names the argument and what was expected. Returns kExitUsage.
int Usage(const std::string& command, const std::string& message);
/// Prints an operation's failure (or its notes when --json is off). Returns the exit code.
int Report(const Context& context, const host::Outcome& outcome, const std::string& what);
/// On stderr (--json too), one line each: calibration files that disagree with the static inverse
/// their finger's board holds by more than their fit residual (the board's curve is followed).
void WarnCurves(host::Device& device);
/// The closest of `candidates` to a mistyped `word` (a letter or two off, or a prefix), or "".
std::string Suggest(const std::string& word, const std::vector<std::string>& candidates);

/// A command: its name, synopsis and help text beside its handler. Each cmd_*.cc defines its own;
/// main.cc only lists them (`palpa --help`, `palpa COMMAND --help`).
struct Command {
  const char* name;
  const char* synopsis;
  const char* help;
  int (*run)(Context&, const std::vector<std::string>&);
};

extern const Command kListCommand, kInfoCommand, kDiagCommand, kConfigCommand, kSetCommand,
    kLineCommand, kMonitorCommand, kRecordCommand, kEStopCommand, kClearCommand, kDemoCommand,
    kCalibrateCommand, kFlashCommand, kPackageCommand, kKeygenCommand, kSimCommand, kSceneCommand,
    kRenderCommand, kServeCommand, kStudyCommand;
/// palpa study's subcommands (cmd_study_*.cc), listed by cmd_study.cc.
int CmdStudyReport(Context& c, const std::vector<std::string>& args);

/// One finger request from "N=VALUE": L2 (level), 0.5 (0..1), 1.2mm, 0.9N/mm, -10kPa. Fingers are
/// numbered from 1 on the command line, up to `finger_count`. Returns false with a message naming
/// the argument (and the unit meant, for "10kpa"). Every mistake here is an invalid argument.
host::Result<host::FingerRequest> ParseFingerArgument(const std::string& arg, uint8_t finger_count);
/// "L=VALUE" with VALUE in kPa (a "kPa" suffix is allowed); lines numbered from 1.
host::Result<std::pair<uint8_t, double>> ParseLineArgument(const std::string& arg,
                                                           uint8_t line_count);
/// The same finger or line twice on one command line ("1=L2 1=L1") is refused: which one was
/// meant? `indices` are 0-based; `what` is "finger" or "line".
host::Outcome CheckDistinct(const std::vector<uint8_t>& indices,
                            const std::vector<std::string>& args, const char* what);
/// Every finger or line named exists on this board; otherwise a message naming the board's range
/// ("finger 9: this thesis-5finger board has fingers 1 to 5").
host::Outcome CheckOnBoard(const std::vector<uint8_t>& indices, uint8_t count, const char* what,
                           const std::string& board_name);
/// Splits off "--hold S": the seconds (0 without it), or why the value is refused.
host::Result<double> TakeHold(std::vector<std::string>& args);
/// Keeps the session (and so the actuation) for `hold_s`, or says that it is not kept; palpa's
/// exit then closes the session (or gives control of a served board up), every output safe.
void Hold(const Context& c, double hold_s);
/// --device serve:HOST:PORT: the commands that go through a running palpa serve, and running one.
bool RunsThroughServe(const std::string& command);
int RunThroughServe(Context& c, const std::string& command, const std::vector<std::string>& args);
/// A decimal number ("5", "-10.5", "1e3"), finite: no hex, no "inf", no spaces.
bool ParseNumber(const std::string& text, double& out);
/// "--rate 5": the value after option `i`, or a usage message that it is missing.
host::Result<std::string> OptionValue(const std::vector<std::string>& args, size_t i);
/// "auto", "pi", "api", "pi:8": the compensator a calibration fits (auto: empty, the better of
/// pi and api); operators 0 when not given.
bool ParseCompensator(const std::string& text, std::optional<protocol::CompensatorKind>& kind,
                      int& operators);

}  // namespace palpa::cli
