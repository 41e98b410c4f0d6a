// The palpa command line: shared context, exit codes and the commands' entry points.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

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
  bool json = false;
  host::DeviceOptions options;  ///< how Device() opens it
  /// Opens the device on first use; prints the error and returns nullptr when it cannot.
  host::Device* Device();
  std::unique_ptr<host::Device> device;
};

/// A usage error: names the argument and what was expected. Returns kExitUsage.
int Usage(const std::string& command, const std::string& message);
/// Prints an operation's failure (or its notes when --json is off). Returns the exit code.
int Report(const Context& context, const host::Outcome& outcome, const std::string& what);

int CmdList(Context& c, const std::vector<std::string>& args);
int CmdInfo(Context& c, const std::vector<std::string>& args);
int CmdDiag(Context& c, const std::vector<std::string>& args);
int CmdConfig(Context& c, const std::vector<std::string>& args);
int CmdSet(Context& c, const std::vector<std::string>& args);
int CmdLine(Context& c, const std::vector<std::string>& args);
int CmdMonitor(Context& c, const std::vector<std::string>& args);
int CmdRecord(Context& c, const std::vector<std::string>& args);
int CmdEStop(Context& c, const std::vector<std::string>& args);
int CmdClear(Context& c, const std::vector<std::string>& args);
int CmdDemo(Context& c, const std::vector<std::string>& args);
int CmdCalibrate(Context& c, const std::vector<std::string>& args);
int CmdFlash(Context& c, const std::vector<std::string>& args);
int CmdPackage(Context& c, const std::vector<std::string>& args);

/// One finger request from "N=VALUE": L2 (level), 0.5 (0..1), 1.2mm, 0.9N/mm, -10kPa. Fingers are
/// numbered from 1 on the command line. Returns false with a message naming the argument.
bool ParseFingerArgument(const std::string& arg, uint8_t finger_count, host::FingerRequest& out,
                         std::string* error);
/// "L=VALUE" with VALUE in kPa (a "kPa" suffix is allowed); lines numbered from 1.
bool ParseLineArgument(const std::string& arg, uint8_t line_count, std::pair<uint8_t, double>& out,
                       std::string* error);
/// A number with a unit suffix, e.g. "--duration 5" (seconds). False when not a finite number.
bool ParseNumber(const std::string& text, double& out);
/// "auto", "pi", "api", "pi:8": the compensator a calibration fits (auto: empty, the better of
/// pi and api); operators 0 when not given.
bool ParseCompensator(const std::string& text, std::optional<protocol::CompensatorKind>& kind,
                      int& operators);

}  // namespace palpa::cli
