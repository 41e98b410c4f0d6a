// Firmware images and update packages on the host: building an image from a slot's binary (the
// build step after linking), and the package that carries both slot builds of one release.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"
#include "palpa/protocol/image.h"

namespace palpa::host {

/// No board's slot is near this (the simulated and MPS2 boards' are 192 KiB): an update package
/// holds two slot images, `palpa package` reads one binary per slot.
inline constexpr FileLimits kPackageFileLimits{"update package", 16 * 1024 * 1024};
inline constexpr FileLimits kSlotBinaryLimits{"slot binary", 8 * 1024 * 1024};

/// An image to build: its fields (header_size padded for an MCU's vector table, load_address
/// where the slot appears in the board's address map) and the body.
struct ImageSpec : protocol::ImageFields {
  std::vector<uint8_t> body;  ///< the binary linked to run from the slot
  /// Signs the image (its key and signature TLVs); nullptr: unsigned, which boards refuse.
  protocol::ImageSigner* signer = nullptr;
};

/// Header, body, protected TLVs (kind, slot, counter), TLVs (SHA-256; key and signature).
std::vector<uint8_t> BuildImage(const ImageSpec& spec);

/// The image of `slot` in a release (spec's board kind, version, rollback counter and the body
/// linked for that slot), laid out for the board kind's flash: the header padded to 256 bytes
/// where an MCU's vector table follows it, loaded where the slot appears in its address map.
/// Out of range ("N bytes do not fit a slot of M") when the body is too large for a slot.
Result<std::vector<uint8_t>> BuildSlotImage(ImageSpec spec, uint8_t slot);

/// Verifies an image held in memory (as the board would, for any slot size), its signature
/// against the key it names: which keys a board trusts is the board's to say.
protocol::Status VerifyImageBytes(const std::vector<uint8_t>& image, protocol::ImageInfo* info,
                                  protocol::ImageError* error);

/// One release for both slots: the host writes the build for the slot the board reports inactive.
struct UpdatePackage {
  std::array<std::vector<uint8_t>, 2> slot_image;
};

/// "PALPAPKG", version 1, then per slot: slot (u8), size (u32 LE), the image.
std::vector<uint8_t> WritePackage(const UpdatePackage& package);
/// Parses and verifies both images (each for its own slot, one board kind, one version);
/// image_invalid with a reason that says what is wrong and where.
Result<UpdatePackage> ReadPackage(const std::vector<uint8_t>& bytes);

}  // namespace palpa::host
