// Firmware image format, MCUboot-style: a 32-byte header, the body (the slot's XIP binary), the
// protected TLVs (board kind, load slot, anti-rollback counter) and the TLVs (SHA-256 over
// header + body + protected TLVs; the signer's Ed25519 public key; the Ed25519 signature of that
// SHA-256). Parsed here, freestanding, by the bootloader, the board's update engine and the
// host's flasher alike.
#pragma once

#include <cstddef>
#include <cstdint>

#include "palpa/protocol/ed25519.h"
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
  kPublicKey = 0x02,        ///< 32 bytes: the signer's Ed25519 key (a board trusts its own list)
  kSha256 = 0x10,           ///< 32 bytes, unprotected (it covers the protected area)
  kEd25519 = 0x24,          ///< 64 bytes: Ed25519 signature of the SHA-256 digest
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
  uint32_t total_size = 0;     ///< header + body + both TLV areas: what occupies the slot
  Sha256Digest sha256{};       ///< over header + body + protected TLVs, as recorded and as computed
  bool has_signature = false;  ///< public-key and signature TLVs present
  uint8_t signer[kEd25519PublicKeySize] = {};            ///< the public key the image names
  SignatureCheck signature = SignatureCheck::kMismatch;  ///< its signature's verdict
  uint8_t trusted_index = 0xFF;  ///< which of the board's keys signed it (0xFF: not checked)
};

/// The public keys a board accepts images from, compiled into its firmware (never taken from
/// the link): the current key and one to rotate to.
inline constexpr size_t kMaxTrustedKeys = 2;
struct TrustedKeys {
  uint8_t count = 0;
  uint8_t key[kMaxTrustedKeys][kEd25519PublicKeySize] = {};
};

/// Signs an image's SHA-256 digest as it is written (the host, with libsodium; never the board).
class ImageSigner {
 public:
  virtual const uint8_t* PublicKey() const = 0;  ///< 32 bytes
  /// The Ed25519 signature of `digest` into `signature` (64 bytes); false when it failed.
  virtual bool Sign(const Sha256Digest& digest, uint8_t* signature) = 0;

 protected:
  ~ImageSigner() = default;
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
  kUnsigned,      ///< no public-key and signature TLVs
  kUntrustedKey,  ///< signed by a key the board does not trust
  kBadSignature,  ///< the signature does not verify (ImageInfo::signature says why)
};
const char* ImageErrorName(ImageError e);

/// Where the image's bytes come from (the slot in flash, a file, memory).
class ImageSource {
 public:
  virtual bool Read(uint32_t offset, uint8_t* out, size_t size) = 0;

 protected:
  ~ImageSource() = default;
};

/// An image already in memory (a package on the host, an image a test built); the bytes must
/// outlive it.
class MemoryImageSource final : public ImageSource {
 public:
  MemoryImageSource(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool Read(uint32_t offset, uint8_t* out, size_t size) override {
    if (offset > size_ || size > size_ - offset) return false;
    __builtin_memcpy(out, data_ + offset, size);
    return true;
  }

 private:
  const uint8_t* data_;
  size_t size_;
};

/// Bytes an image of a body this size occupies (signed: with the key and signature TLVs).
constexpr uint32_t ImageSize(uint32_t body_size, uint16_t header_size = kImageHeaderSize,
                             bool is_signed = true) {
  return header_size + body_size + (4 + 5 + 5 + 8) + (4 + 4 + 32) +
         (is_signed ? uint32_t{(4 + kEd25519PublicKeySize) + (4 + kEd25519SignatureSize)} : 0u);
}

/// Writes header, body, protected TLVs and the TLVs (SHA-256; with `signer`, its public key and
/// the signature of the SHA-256) into `out`; returns the image size, or 0 when `capacity` is too
/// small or signing failed. A null signer writes an unsigned image, which every board refuses
/// (tests make them). The build step and the simulated factory use it.
uint32_t WriteImage(const ImageFields& fields, const uint8_t* body, uint32_t body_size,
                    uint8_t* out, uint32_t capacity, ImageSigner* signer);

/// Parses the header and TLVs, checks the hash, then the signature, reading at most `slot_size`
/// bytes in small pieces (no buffer the size of an image). kOk with *info filled, or
/// kImageInvalid with *error. The board passes its compiled-in `trusted` keys: the image must
/// name one of them and carry its valid signature. The host, which does not know what a board
/// trusts, passes nullptr: the signature is checked against the key the image names (the board
/// decides whether it trusts that key). `progress` is stepped during the signature check.
Status VerifyImage(ImageSource& source, uint32_t slot_size, const TrustedKeys* trusted,
                   ImageInfo* info, ImageError* error, VerifyProgress* progress = nullptr);

}  // namespace palpa::protocol
