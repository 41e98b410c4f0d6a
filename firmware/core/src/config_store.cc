// Two-copy configuration storage with CRCs and a header written last.
#include "palpa/core/config_store.h"

#include "palpa/protocol/little_endian.h"

#include "palpa/protocol/crc32.h"

namespace palpa::core {
namespace {

constexpr uint32_t kMagic = 0x50434647;  // "GFCP"
constexpr uint32_t kHeaderSize = 20;

// One blob buffer shared by load and save: both run between ticks, never together.
uint8_t g_blob[kMaxConfigBlob];

}  // namespace

bool ConfigStore::ReadHeader(uint8_t copy, Header& header) {
  uint8_t raw[kHeaderSize];
  if (flash_->Read(base_ + copy * flash_->sector_size(), raw, sizeof(raw)) != Status::kOk)
    return false;
  header = Header{protocol::LoadLe32(raw), protocol::LoadLe32(raw + 4), protocol::LoadLe32(raw + 8),
                  protocol::LoadLe32(raw + 12), protocol::LoadLe32(raw + 16)};
  return header.magic == kMagic && protocol::Crc32(raw, 16) == header.header_crc &&
         header.length <= flash_->sector_size() - kHeaderSize && header.length <= sizeof(g_blob);
}

bool ConfigStore::ReadCopy(uint8_t copy, const Header& header, const BoardConfig& factory,
                           BoardConfig& config) {
  const uint32_t at = base_ + copy * flash_->sector_size() + kHeaderSize;
  if (flash_->Read(at, g_blob, header.length) != Status::kOk) return false;
  if (protocol::Crc32(g_blob, header.length) != header.crc) return false;
  config = BoardConfig{};  // a saved blob is complete: start empty, not from the defaults
  config.board = factory.board;
  return ApplyConfigBlob(g_blob, header.length, config, nullptr) == Status::kOk &&
         ValidateConfig(config, nullptr) == Status::kOk;
}

ConfigStore::Source ConfigStore::Load(const BoardConfig& factory, BoardConfig& config) {
  if (flash_ == nullptr) {
    config = factory;
    return Source::kFactory;
  }
  Header headers[2];
  bool valid[2] = {ReadHeader(0, headers[0]), ReadHeader(1, headers[1])};
  // Newest first (sequence compared on the u32 circle); fall back to the other copy.
  uint8_t order[2] = {0, 1};
  if (valid[0] && valid[1] && static_cast<int32_t>(headers[1].sequence - headers[0].sequence) > 0) {
    order[0] = 1;
    order[1] = 0;
  } else if (!valid[0]) {
    order[0] = 1;
    order[1] = 0;
  }
  for (uint8_t copy : order) {
    if (valid[copy] && ReadCopy(copy, headers[copy], factory, config)) {
      sequence_ = headers[copy].sequence;
      newest_ = copy;
      return Source::kFlash;
    }
  }
  config = factory;
  return Source::kFactory;
}

Status ConfigStore::Save(const BoardConfig& config) {
  if (flash_ == nullptr) return Status::kUnavailable;
  const auto size = EncodeConfigBlob(config, g_blob, sizeof(g_blob));
  if (!size.ok() || size.value > flash_->sector_size() - kHeaderSize) return Status::kOverflow;
  const uint8_t copy = newest_ == 0 ? 1 : 0;
  const uint32_t at = base_ + copy * flash_->sector_size();
  if (flash_->Erase(at) != Status::kOk) return Status::kIoError;
  if (flash_->Program(at + kHeaderSize, g_blob, size.value) != Status::kOk) return Status::kIoError;
  uint8_t header[kHeaderSize];
  protocol::StoreLe32(header, kMagic);
  protocol::StoreLe32(header + 4, sequence_ + 1);
  protocol::StoreLe32(header + 8, static_cast<uint32_t>(size.value));
  protocol::StoreLe32(header + 12, protocol::Crc32(g_blob, size.value));
  protocol::StoreLe32(header + 16, protocol::Crc32(header, 16));
  if (flash_->Program(at, header, sizeof(header)) != Status::kOk) return Status::kIoError;
  ++sequence_;
  newest_ = copy;
  return Status::kOk;
}

Status ConfigStore::Erase() {
  if (flash_ == nullptr) return Status::kUnavailable;
  for (uint8_t copy = 0; copy < 2; ++copy) {
    if (flash_->Erase(base_ + copy * flash_->sector_size()) != Status::kOk) return Status::kIoError;
  }
  sequence_ = 0;
  newest_ = 1;
  return Status::kOk;
}

}  // namespace palpa::core
