// Firmware images and update packages on the host: building an image from a slot's binary (the
// build step after linking), and the package that carries both slot builds of one release.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "palpa/protocol/image.h"

namespace palpa::host {

struct ImageSpec {
  std::vector<uint8_t> body;  ///< the binary linked to run from the slot
  uint16_t header_size = protocol::kImageHeaderSize;  ///< padded for an MCU's vector table
  uint32_t load_address = 0;  ///< where the slot appears in the board's address map
  uint8_t version_major = 0, version_minor = 0;
  uint16_t version_revision = 0;
  uint32_t build = 0;
  protocol::BoardKind board_kind = protocol::BoardKind::kSim;
  uint8_t slot = 0;
  uint32_t rollback_counter = 0;
};

/// Header, body, protected TLVs (kind, slot, counter), TLVs (SHA-256).
std::vector<uint8_t> BuildImage(const ImageSpec& spec);

/// Verifies an image held in memory (as the board would, for any slot size).
protocol::Status VerifyImageBytes(const std::vector<uint8_t>& image, protocol::ImageInfo* info,
                                  protocol::ImageError* error);

/// One release for both slots: the host writes the build for the slot the board reports inactive.
struct UpdatePackage {
  std::array<std::vector<uint8_t>, 2> slot_image;
};

/// "PALPAPKG", version 1, then per slot: slot (u8), size (u32 LE), the image.
std::vector<uint8_t> WritePackage(const UpdatePackage& package);
/// Parses and verifies both images (each for its own slot, one board kind, one version);
/// nullopt with a reason that says what is wrong and where.
std::optional<UpdatePackage> ReadPackage(const std::vector<uint8_t>& bytes, std::string* error);

}  // namespace palpa::host
