// Firmware image format, MCUboot-style: a 32-byte header, the body (the slot's XIP binary), the
// protected TLVs (board kind, load slot, anti-rollback counter) and the TLVs (SHA-256 over
// header + body + protected TLVs; a signature TLV reserved). Parsed here, freestanding, by the
// bootloader, the board's update engine and the host's flasher alike.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/enums.h"
#include "palpa/protocol/sha256.h"
#include "palpa/protocol/status.h"

namespace palpa::protocol {

inline constexpr uint32_t kImageMagic = 0x96f3b83d;  ///< MCUboot's IMAGE_MAGIC
inline constexpr uint16_t kImageHeaderSize = 32;     ///< the header's fields; zeros may pad it
/// The largest header (fields and padding): a Cortex-M vector table after it must sit on a
/// boundary of its own size rounded up to a power of two, so an image for an MCU pads its header.
inline constexpr uint16_t kMaxImageHeaderSize = 1024;
inline constexpr uint16_t kTlvInfoMagic = 0x6907;           ///< unprotected TLV area
inline constexpr uint16_t kProtectedTlvInfoMagic = 0x6908;  ///< protected TLV area

/// TLV types: MCUboot's where it has one, palpa's own in 0xA0..0xAF.
enum class TlvType : uint16_t {
  kSha256 = 0x10,           ///< 32 bytes, unprotected (it covers the protected area)
  kEd25519 = 0x24,          ///< reserved: a signature, checked once keys are provisioned
  kSecurityCounter = 0x50,  ///< u32 anti-rollback counter, protected
  kBoardKind = 0xA0,        ///< u8 BoardKind, protected
  kLoadSlot = 0xA1,         ///< u8 slot the body is linked for, protected
};

/// What an image says of itself when it is made: header and protected TLVs.
struct ImageFields {
  uint16_t header_size = kImageHeaderSize;  ///< the body starts here (≥ 32, a multiple of 4)
  uint32_t load_address = 0;
  uint8_t version_major = 0, version_minor = 0;
  uint16_t version_revision = 0;
  uint32_t build = 0;
  BoardKind board_kind = BoardKind::kSim;
  uint8_t slot = 0;
  uint32_t rollback_counter = 0;
};

/// What a well-formed image says of itself: its fields, and what follows from its body.
struct ImageInfo : ImageFields {
  uint32_t body_size = 0;
  uint32_t total_size = 0;  ///< header + body + both TLV areas: what occupies the slot
  Sha256Digest sha256{};    ///< over header + body + protected TLVs, as recorded and as computed
};

/// Why an image was refused.
enum class ImageError : uint8_t {
  kNone,
  kUnreadable,    ///< the reader failed
  kBadMagic,      ///< no image here (erased, or not an image)
  kBadHeader,     ///< header size or flags not this format's
  kTooLarge,      ///< does not fit the slot
  kBadTlvArea,    ///< a TLV area's magic or length is wrong
  kMissingTlv,    ///< board kind, slot, counter or SHA-256 absent
  kHashMismatch,  ///< the body is not what the header and TLVs describe
};
const char* ImageErrorName(ImageError e);

/// Where the image's bytes come from (the slot in flash, a file, memory).
class ImageSource {
 public:
  virtual bool Read(uint32_t offset, uint8_t* out, size_t size) = 0;

 protected:
  ~ImageSource() = default;
};

/// Bytes an image of a body this size occupies.
constexpr uint32_t ImageSize(uint32_t body_size, uint16_t header_size = kImageHeaderSize) {
  return header_size + body_size + (4 + 5 + 5 + 8) + (4 + 4 + 32);
}

/// Writes header, body, protected TLVs and the SHA-256 TLV into `out`; returns the image size,
/// or 0 when `capacity` is too small. The build step and the simulated factory use it.
uint32_t WriteImage(const ImageFields& fields, const uint8_t* body, uint32_t body_size,
                    uint8_t* out, uint32_t capacity);

/// Parses the header and TLVs and checks the hash, reading at most `slot_size` bytes in small
/// pieces (no buffer the size of an image). kOk with *info filled, or kImageInvalid with *error.
Status VerifyImage(ImageSource& source, uint32_t slot_size, ImageInfo* info, ImageError* error);

}  // namespace palpa::protocol
