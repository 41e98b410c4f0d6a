// Reading a call's named parameters: each one's type and range checked, unknown names refused, so
// a method either has everything it needs or sends nothing.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/serve/json_rpc.h"

namespace palpa::serve {

/// An invalid-params error naming the parameter and what was expected.
rpc::Error BadParam(const std::string& why);

/// Every member of `params` is one of `known`; otherwise the error names the first stranger.
std::optional<rpc::Error> OnlyKnown(const rpc::Json& params,
                                    std::initializer_list<const char*> known);

/// An integer in [min, max] (a JSON integer: 1.0 and true are not), or the error saying so.
std::optional<rpc::Error> ReadInteger(const rpc::Json& value, const std::string& name, int64_t min,
                                      int64_t max, int64_t& out);
/// A finite number in [min, max].
std::optional<rpc::Error> ReadNumber(const rpc::Json& value, const std::string& name, double min,
                                     double max, double& out);
/// A boolean member, false when absent.
std::optional<rpc::Error> ReadFlag(const rpc::Json& params, const char* name, bool& out);

/// {"targets": [{"finger": 0, "level": 2}, {"finger": 3, "n_per_mm": 0.9},
/// {"finger": 1, "value": "1.2mm"}, ...]}: one unit per finger (level, normalized, n_per_mm, mm,
/// kpa — the Python module's names — or "value" as the command line writes it), each finger once.
std::optional<rpc::Error> ReadTargets(const rpc::Json& params, const protocol::HelloReply& board,
                                      std::vector<host::FingerRequest>& out);
/// {"setpoints": [{"line": 0, "kpa": 30}, ...]}: raw setpoints, each line once.
std::optional<rpc::Error> ReadSetpoints(const rpc::Json& params, const protocol::HelloReply& board,
                                        std::vector<std::pair<uint8_t, double>>& out);

}  // namespace palpa::serve
