// Device: the board's whole configuration read back section by section, checked and encoded as
// the firmware would, and applied in one staged, all-or-nothing upload.
#include <string>
#include <vector>

#include "palpa/host/device.h"

namespace palpa::host {

Result<core::BoardConfig> Device::ReadConfig() {
  core::BoardConfig config{};
  const pp::HelloReply& b = info();
  auto board = ReadBoard();
  if (!board.ok()) return board.outcome();
  config.board = board.value;
  config.line_count = b.line_count;
  for (uint8_t i = 0; i < b.line_count; ++i) {
    auto line = ReadLine(i);
    if (!line.ok()) return line.outcome();
    config.lines[i] = line.value;
  }
  config.finger_count = b.finger_count;
  for (uint8_t f = 0; f < b.finger_count; ++f) {
    auto finger = ReadFinger(f);
    if (!finger.ok()) return finger.outcome();
    config.fingers[f] = finger.value;
  }
  return config;
}

Outcome Device::EncodeConfig(const core::BoardConfig& config, std::vector<uint8_t>* records) const {
  core::ConfigError error;
  if (core::ValidateConfig(config, &error) != Status::kOk) {
    return Outcome{Status::kOutOfRange,
                   std::string("the configuration is not valid: ") +
                       pp::kConfigSectionNames[static_cast<int>(error.section)] + " " +
                       std::to_string(error.index + options_.number_from) + ": " + error.reason +
                       " (nothing was sent)",
                   {}};
  }
  records->assign(core::kMaxConfigBlob, 0);
  const auto size = core::EncodeConfigBlob(config, records->data(), records->size());
  if (!size.ok() || size.value > pp::kMaxStagedBytes) {
    return Outcome{Status::kOverflow,
                   "the configuration is too large for one staged upload (" +
                       std::to_string(size.value) + " bytes; nothing was sent)",
                   {}};
  }
  records->resize(size.value);
  return {};
}

Outcome Device::ApplyConfig(const core::BoardConfig& config) {
  std::vector<uint8_t> records;
  if (Outcome o = EncodeConfig(config, &records); !o.ok()) return o;
  return ConfigureStaged(records.data(), records.size());
}

}  // namespace palpa::host
