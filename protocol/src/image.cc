// Image header and TLV parsing with the hash and signature checks, read in 64-byte pieces.
#include "palpa/protocol/image.h"

#include "palpa/protocol/little_endian.h"

namespace palpa::protocol {
namespace {

Status Fail(ImageError why, ImageError* error) {
  *error = why;
  return Status::kImageInvalid;
}

/// Walks one TLV area at `offset`; calls `visit(type, length, value_offset)` for each entry.
template <class Visit>
bool WalkTlvs(ImageSource& source, uint32_t offset, uint16_t magic, uint32_t limit,
              uint32_t* area_size, Visit visit) {
  uint8_t info[4];
  if (offset + 4 > limit || !source.Read(offset, info, 4)) return false;
  const uint16_t total = LoadLe16(info + 2);
  if (LoadLe16(info) != magic || total < 4 || offset + total > limit) return false;
  for (uint32_t at = offset + 4; at < offset + total;) {
    uint8_t entry[4];
    if (at + 4 > offset + total || !source.Read(at, entry, 4)) return false;
    const uint16_t length = LoadLe16(entry + 2);
    if (at + 4 + length > offset + total) return false;
    if (!visit(static_cast<TlvType>(LoadLe16(entry)), length, at + 4)) return false;
    at += 4 + length;
  }
  *area_size = total;
  return true;
}

/// One TLV entry at p; returns its size.
uint32_t PutTlv(uint8_t* p, TlvType type, const uint8_t* value, uint16_t length) {
  StoreLe16(p, static_cast<uint16_t>(type));
  StoreLe16(p + 2, length);
  for (uint16_t i = 0; i < length; ++i) p[4 + i] = value[i];
  return 4u + length;
}

}  // namespace

uint32_t WriteImage(const ImageFields& f, const uint8_t* body, uint32_t body_size, uint8_t* out,
                    uint32_t capacity, ImageSigner* signer) {
  const uint16_t header_size = f.header_size;
  if (header_size < kImageHeaderSize || header_size > kMaxImageHeaderSize || header_size % 4 != 0)
    return 0;
  const uint32_t size = ImageSize(body_size, header_size, signer != nullptr);
  if (size > capacity || body_size > capacity) return 0;
  constexpr uint16_t kProtectedSize = 4 + 5 + 5 + 8;
  uint8_t* h = out;
  for (uint32_t i = 0; i < header_size; ++i) h[i] = 0;
  StoreLe32(h, kImageMagic);
  StoreLe32(h + 4, f.load_address);
  StoreLe16(h + 8, header_size);
  StoreLe16(h + 10, kProtectedSize);
  StoreLe32(h + 12, body_size);
  h[20] = f.version_major;
  h[21] = f.version_minor;
  StoreLe16(h + 22, f.version_revision);
  StoreLe32(h + 24, f.build);
  for (uint32_t i = 0; i < body_size; ++i) out[header_size + i] = body[i];
  uint8_t* p = out + header_size + body_size;
  StoreLe16(p, kProtectedTlvInfoMagic);
  StoreLe16(p + 2, kProtectedSize);
  uint32_t at = 4;
  const uint8_t kind = static_cast<uint8_t>(f.board_kind);
  at += PutTlv(p + at, TlvType::kBoardKind, &kind, 1);
  at += PutTlv(p + at, TlvType::kLoadSlot, &f.slot, 1);
  uint8_t counter[4];
  StoreLe32(counter, f.rollback_counter);
  at += PutTlv(p + at, TlvType::kSecurityCounter, counter, 4);
  const Sha256Digest digest = Sha256Of(out, header_size + body_size + kProtectedSize);
  uint8_t* t = p + kProtectedSize;
  StoreLe16(t, kTlvInfoMagic);
  uint32_t tlvs = 4;
  tlvs += PutTlv(t + tlvs, TlvType::kSha256, digest.data(), 32);
  if (signer != nullptr) {
    uint8_t signature[kEd25519SignatureSize];
    if (!signer->Sign(digest, signature)) return 0;
    tlvs += PutTlv(t + tlvs, TlvType::kPublicKey, signer->PublicKey(), kEd25519PublicKeySize);
    tlvs += PutTlv(t + tlvs, TlvType::kEd25519, signature, kEd25519SignatureSize);
  }
  StoreLe16(t + 2, static_cast<uint16_t>(tlvs));
  return size;
}

const char* ImageErrorName(ImageError e) {
  switch (e) {
    case ImageError::kNone:
      return "valid";
    case ImageError::kUnreadable:
      return "unreadable";
    case ImageError::kBadMagic:
      return "no image (bad magic)";
    case ImageError::kBadHeader:
      return "header not of this format";
    case ImageError::kTooLarge:
      return "larger than the slot";
    case ImageError::kBadTlvArea:
      return "TLV area malformed";
    case ImageError::kMissingTlv:
      return "board kind, slot, rollback counter or SHA-256 missing";
    case ImageError::kHashMismatch:
      return "SHA-256 does not match";
    case ImageError::kUnsigned:
      return "not signed";
    case ImageError::kUntrustedKey:
      return "signed by a key this board does not trust";
    case ImageError::kBadSignature:
      return "signature does not verify";
  }
  return "?";
}

Status VerifyImage(ImageSource& source, uint32_t slot_size, const TrustedKeys* trusted,
                   ImageInfo* info, ImageError* error, VerifyProgress* progress) {
  *error = ImageError::kNone;
  *info = ImageInfo{};
  uint8_t h[kImageHeaderSize];
  if (slot_size < kImageHeaderSize || !source.Read(0, h, sizeof(h)))
    return Fail(ImageError::kUnreadable, error);
  if (LoadLe32(h) != kImageMagic) return Fail(ImageError::kBadMagic, error);
  const uint16_t header_size = LoadLe16(h + 8), protected_size = LoadLe16(h + 10);
  info->load_address = LoadLe32(h + 4);
  info->body_size = LoadLe32(h + 12);
  const uint32_t flags = LoadLe32(h + 16);
  info->version_major = h[20];
  info->version_minor = h[21];
  info->version_revision = LoadLe16(h + 22);
  info->build = LoadLe32(h + 24);
  if (header_size < kImageHeaderSize || header_size > kMaxImageHeaderSize || header_size % 4 != 0 ||
      flags != 0 || header_size > slot_size) {
    return Fail(ImageError::kBadHeader, error);
  }
  info->header_size = header_size;
  if (info->body_size > slot_size - header_size) return Fail(ImageError::kTooLarge, error);
  const uint32_t protected_at = header_size + info->body_size;

  // Protected TLVs: what the hash covers besides header and body.
  bool kind = false, slot = false, counter = false;
  uint32_t protected_total = 0;
  auto read_value = [&](uint32_t at, uint16_t length, uint8_t* out, uint16_t want) {
    return length == want && source.Read(at, out, want);
  };
  const bool protected_ok = WalkTlvs(
      source, protected_at, kProtectedTlvInfoMagic, slot_size, &protected_total,
      [&](TlvType type, uint16_t length, uint32_t at) {
        uint8_t v[4];
        switch (type) {
          case TlvType::kBoardKind:
            if (!read_value(at, length, v, 1) || v[0] >= static_cast<uint8_t>(BoardKind::kCount))
              return false;
            info->board_kind = static_cast<BoardKind>(v[0]);
            return kind = true;
          case TlvType::kLoadSlot:
            if (!read_value(at, length, v, 1) || v[0] > 1) return false;
            info->slot = v[0];
            return slot = true;
          case TlvType::kSecurityCounter:
            if (!read_value(at, length, v, 4)) return false;
            info->rollback_counter = LoadLe32(v);
            return counter = true;
          default:
            return true;  // unknown protected entries are covered by the hash: harmless
        }
      });
  if (!protected_ok || protected_total != protected_size)
    return Fail(ImageError::kBadTlvArea, error);

  // Unprotected TLVs: the hash, the signer's key and the signature (each at most once).
  bool hashed = false, keyed = false, signed_ = false;
  uint16_t key_length = 0, signature_length = 0;
  Sha256Digest recorded{};
  uint8_t signature[kEd25519SignatureSize] = {};
  uint32_t tlv_total = 0;
  const bool tlv_ok = WalkTlvs(
      source, protected_at + protected_total, kTlvInfoMagic, slot_size, &tlv_total,
      [&](TlvType type, uint16_t length, uint32_t at) {
        switch (type) {
          case TlvType::kSha256:
            if (hashed) return false;
            hashed = length == 32 && source.Read(at, recorded.data(), 32);
            return hashed;
          case TlvType::kPublicKey:  // a wrong length is read as far as it fits, and refused
            if (keyed) return false;
            keyed = true;
            key_length = length;
            return source.Read(at, info->signer, length < 32 ? length : 32);
          case TlvType::kEd25519:
            if (signed_) return false;
            signed_ = true;
            signature_length = length;
            return source.Read(at, signature, length < 64 ? length : 64);
          default:
            return true;
        }
      });
  if (!tlv_ok) return Fail(ImageError::kBadTlvArea, error);
  if (!kind || !slot || !counter || !hashed) return Fail(ImageError::kMissingTlv, error);
  info->total_size = protected_at + protected_total + tlv_total;

  Sha256Hasher hasher;
  uint8_t piece[64];
  const uint32_t covered = protected_at + protected_total;
  for (uint32_t at = 0; at < covered;) {
    const uint32_t n = covered - at < sizeof(piece) ? covered - at : sizeof(piece);
    if (!source.Read(at, piece, n)) return Fail(ImageError::kUnreadable, error);
    hasher.Update(piece, n);
    at += n;
  }
  info->sha256 = hasher.Finish();
  if (info->sha256 != recorded) return Fail(ImageError::kHashMismatch, error);

  // The signature of the digest, by a key the board trusts (or, for the host, the named key).
  info->has_signature = keyed && signed_;
  if (!info->has_signature) return Fail(ImageError::kUnsigned, error);
  if (trusted != nullptr) {
    for (uint8_t k = 0; k < trusted->count && k < kMaxTrustedKeys; ++k) {
      bool same = key_length == kEd25519PublicKeySize;
      for (size_t i = 0; same && i < kEd25519PublicKeySize; ++i)
        same = trusted->key[k][i] == info->signer[i];
      if (same) info->trusted_index = k;
    }
    if (info->trusted_index == 0xFF) return Fail(ImageError::kUntrustedKey, error);
  }
  const uint8_t* key = trusted != nullptr ? trusted->key[info->trusted_index] : info->signer;
  info->signature = Ed25519Verify(signature, signature_length, info->sha256.data(),
                                  info->sha256.size(), key, key_length, progress);
  if (info->signature != SignatureCheck::kValid) return Fail(ImageError::kBadSignature, error);
  return Status::kOk;
}

}  // namespace palpa::protocol
