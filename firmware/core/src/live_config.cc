// The board's configuration: loading, a candidate validated whole, saving, the factory reset.
#include "palpa/core/internal/live_config.h"

#include <cstring>

namespace palpa::core {

void LiveConfig::Load() {
  std::memset(&live_, 0, sizeof(live_));  // padding too: the integrity CRC covers raw memory
  is_default_ = store_.Load(factory_, live_) == ConfigStore::Source::kFactory;
  if (!is_default_ && !FitsTheHardware(live_, nullptr)) {  // saved for other hardware
    std::memcpy(&live_, &factory_, sizeof(live_));
    is_default_ = true;
  }
  saved_ = !is_default_;
  unsaved_ = false;
  crc_ = ConfigCrc(live_);
}

bool LiveConfig::FitsTheHardware(const BoardConfig& config, ConfigError* error) const {
  for (uint8_t i = 0; i < config.line_count; ++i) {
    const hal::AnalogOutputSpec spec = dac_.spec(i);
    if (config.lines[i].dac_bits != spec.bits || config.lines[i].dac_signal != spec.range) {
      if (error != nullptr)
        *error = {protocol::ConfigSection::kLine, i,
                  "DAC resolution or signal range differs from the board's DAC"};
      return false;
    }
    const char* refused = line_check_ != nullptr ? line_check_(config.lines[i]) : nullptr;
    if (refused != nullptr) {
      if (error != nullptr) *error = {protocol::ConfigSection::kLine, i, refused};
      return false;
    }
  }
  return true;
}

BoardConfig& LiveConfig::StartCandidate() {
  std::memcpy(&candidate_, &live_, sizeof(candidate_));
  return candidate_;
}

Status LiveConfig::CommitCandidate(uint32_t& detail) {
  ConfigError error;
  Status status = ValidateConfig(candidate_, &error);
  if (status == Status::kOk && !FitsTheHardware(candidate_, &error)) status = Status::kBadValue;
  if (status != Status::kOk) {
    detail = error.detail();
    return status;
  }
  detail = 0;
  // Between two ticks (dispatch never runs inside one): the whole configuration changes at once.
  std::memcpy(&live_, &candidate_, sizeof(live_));
  is_default_ = false;
  unsaved_ = true;
  crc_ = ConfigCrc(live_);
  return Status::kOk;
}

Status LiveConfig::Save() {
  const Status status = store_.Save(live_);
  if (status == Status::kOk) {
    saved_ = true;
    unsaved_ = false;
  }
  return status;
}

Status LiveConfig::FactoryReset() {
  const Status erased = store_.Erase();
  if (erased != Status::kOk && erased != Status::kUnavailable) return erased;
  std::memcpy(&live_, &factory_, sizeof(live_));
  is_default_ = true;
  saved_ = false;  // erased, or nothing persists on this board
  unsaved_ = false;
  crc_ = ConfigCrc(live_);
  return Status::kOk;
}

}  // namespace palpa::core
