// Building and reading firmware images and update packages.
#include "palpa/host/firmware_image.h"

#include <cstring>

#include "palpa/core/flash_layout.h"

namespace palpa::host {
namespace {

void Put32(std::vector<uint8_t>& v, uint32_t x) {
  for (int i = 0; i < 4; ++i) v.push_back(static_cast<uint8_t>(x >> (8 * i)));
}

constexpr char kPackageMagic[8] = {'P', 'A', 'L', 'P', 'A', 'P', 'K', 'G'};

}  // namespace

std::vector<uint8_t> BuildImage(const ImageSpec& s) {
  const auto body_size = static_cast<uint32_t>(s.body.size());
  std::vector<uint8_t> image(protocol::ImageSize(body_size, s.header_size, s.signer != nullptr));
  if (protocol::WriteImage(s, s.body.data(), body_size, image.data(),
                           static_cast<uint32_t>(image.size()), s.signer) == 0)
    return {};
  return image;
}

protocol::Status VerifyImageBytes(const std::vector<uint8_t>& image, protocol::ImageInfo* info,
                                  protocol::ImageError* error) {
  protocol::MemoryImageSource source(image.data(), image.size());
  const protocol::Status s =
      protocol::VerifyImage(source, static_cast<uint32_t>(image.size()), nullptr, info, error);
  if (s == protocol::Status::kOk && info->total_size != image.size()) {
    *error = protocol::ImageError::kBadTlvArea;  // trailing bytes: not one image
    return protocol::Status::kImageInvalid;
  }
  return s;
}

std::vector<uint8_t> WritePackage(const UpdatePackage& p) {
  std::vector<uint8_t> out(kPackageMagic, kPackageMagic + 8);
  out.push_back(1);  // package version
  out.push_back(2);  // entries
  for (uint8_t slot = 0; slot < 2; ++slot) {
    out.push_back(slot);
    Put32(out, static_cast<uint32_t>(p.slot_image[slot].size()));
    out.insert(out.end(), p.slot_image[slot].begin(), p.slot_image[slot].end());
  }
  return out;
}

Result<UpdatePackage> ReadPackage(const std::vector<uint8_t>& bytes) {
  auto fail = [](std::string why) -> Result<UpdatePackage> {
    return {Status::kImageInvalid, std::move(why)};
  };
  if (bytes.size() < 10 || std::memcmp(bytes.data(), kPackageMagic, 8) != 0)
    return fail("not a palpa update package (no PALPAPKG header)");
  if (bytes[8] != 1) return fail("package version " + std::to_string(bytes[8]) + " is not 1");
  if (bytes[9] != 2) return fail("package has " + std::to_string(bytes[9]) + " images, not 2");
  UpdatePackage p;
  size_t at = 10;
  protocol::ImageInfo first{};
  for (uint8_t k = 0; k < 2; ++k) {
    if (at + 5 > bytes.size()) return fail("package truncated in entry " + std::to_string(k));
    const uint8_t slot = bytes[at];
    const uint32_t size = static_cast<uint32_t>(bytes[at + 1]) | bytes[at + 2] << 8 |
                          bytes[at + 3] << 16 | static_cast<uint32_t>(bytes[at + 4]) << 24;
    at += 5;
    if (slot != k)
      return fail("entry " + std::to_string(k) + " is for slot " + std::to_string(slot));
    if (size > bytes.size() - at)
      return fail("package truncated: slot " + std::to_string(k) + " image needs " +
                  std::to_string(size) + " bytes, " + std::to_string(bytes.size() - at) + " left");
    p.slot_image[k].assign(bytes.begin() + static_cast<long>(at),
                           bytes.begin() + static_cast<long>(at + size));
    at += size;
    protocol::ImageInfo info;
    protocol::ImageError why;
    if (VerifyImageBytes(p.slot_image[k], &info, &why) != protocol::Status::kOk)
      return fail("slot " + std::to_string(k) + " image: " + protocol::ImageErrorName(why));
    if (info.slot != k)
      return fail("slot " + std::to_string(k) + " image is linked for slot " +
                  std::to_string(info.slot));
    if (k == 0) {
      first = info;
    } else if (info.board_kind != first.board_kind || info.version_major != first.version_major ||
               info.version_minor != first.version_minor ||
               info.version_revision != first.version_revision ||
               info.rollback_counter != first.rollback_counter) {
      return fail("the two slot images are not one release (kind, version or counter differ)");
    }
  }
  if (at != bytes.size())
    return fail("package has " + std::to_string(bytes.size() - at) + " bytes after its images");
  return p;
}

Result<std::vector<uint8_t>> BuildSlotImage(ImageSpec spec, uint8_t slot) {
  // An MCU's vector table follows the header and must be aligned to its size: pad to 256 bytes.
  spec.header_size =
      spec.board_kind == protocol::BoardKind::kSim || spec.board_kind == protocol::BoardKind::kLinux
          ? protocol::kImageHeaderSize
          : 256;
  const core::FlashLayout& layout = core::kDefaultLayout;
  if (protocol::ImageSize(static_cast<uint32_t>(spec.body.size()), spec.header_size) >
      layout.slot_size) {
    return {Status::kOutOfRange, std::to_string(spec.body.size()) + " bytes do not fit a slot of " +
                                     std::to_string(layout.slot_size)};
  }
  spec.slot = slot;
  spec.load_address = layout.xip_base + layout.slot_offset[slot];
  return BuildImage(spec);
}

}  // namespace palpa::host
