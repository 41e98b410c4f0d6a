// A board behind a running `palpa serve` (docs/serve.md), as the C ABI and the command line reach
// it through serve:HOST:PORT: the server's JSON-RPC methods behind Device-like calls, control taken
// by the first call that acts on the board (never by force) and given up on closing.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/device.h"
#include "palpa/host/outcome.h"
#include "palpa/host/serve_client.h"
#include "palpa/protocol/messages_bootstrap.h"

namespace palpa::host {

/// One telemetry sample as the server sends it (lines and fingers from 0).
struct ServedSample {
  uint64_t board_time_us = 0;
  double host_time_s = 0;  ///< SteadySeconds() when its notification arrived, less its age
  std::vector<int32_t> setpoint_pa, measured_pa;
  std::vector<uint8_t> status;
  uint32_t fault_bitmap = 0;  ///< latched, as of the notification that carried it
  std::vector<double> finger_output;
};

class ServedDevice {
 public:
  /// Connects (a malformed address, nothing listening or a refused upgrade: an error naming the
  /// address and what was wrong), tells the server `client_name` and reads board.info.
  static Result<std::unique_ptr<ServedDevice>> Open(const std::string& uri,
                                                    const std::string& client_name);
  /// Gives control up when held (the server then releases the board) and disconnects.
  ~ServedDevice();
  ServedDevice(const ServedDevice&) = delete;
  ServedDevice& operator=(const ServedDevice&) = delete;

  ServeClient& client() { return *client_; }
  const std::string& uri() const { return uri_; }
  /// board.info's answer, read on opening: {"device", "board", "lines", "fingers"}, from 0.
  const nlohmann::json& board() const { return board_; }
  /// The board's identity as its Hello would give it (the fields board.info carries: kind, id,
  /// firmware, catalog, simulation, configuration, lines, finger kinds) and the latched faults
  /// read now; `catalog_matches` as the server's link found it.
  Result<protocol::HelloReply> Info(bool* catalog_matches = nullptr);
  /// Every finger exists on the served board ("finger 7 does not exist (this board has fingers
  /// 0 to 4)"), checked before anything is sent.
  Outcome CheckFingers(const std::vector<uint8_t>& fingers) const;

  /// Control, once: refused (busy, naming the holder) while another client of the server has it.
  Outcome TakeControl();
  /// board.set: returns once the board applied every request (the server always waits).
  Outcome Set(const std::vector<FingerRequest>& requests);
  Outcome EStop();  ///< everyone's: no control needed
  /// board.clear: the faults that were latched, by name.
  Result<std::vector<std::string>> ClearFault();
  Outcome Release();
  Result<nlohmann::json> ReadConfig();
  Outcome ApplyConfig(const nlohmann::json& patch, bool save);

  /// Telemetry thinned by the server to `sample_rate_hz` (1 … 1000), each sample handed to
  /// `on_sample` on the client's reader thread as its notification arrives.
  Outcome SubscribeSamples(double sample_rate_hz,
                           std::function<void(const ServedSample&)> on_sample);

 private:
  ServedDevice() = default;
  Outcome Act(const std::string& method, const nlohmann::json& params = nlohmann::json::object());

  std::string uri_;
  std::unique_ptr<ServeClient> client_;
  nlohmann::json board_;
  bool controls_ = false;
};

}  // namespace palpa::host
