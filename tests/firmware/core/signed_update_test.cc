// Signed images on the board: the update engine and the bootloader take only images signed by a
// compiled-in key, the rollback floor moves only when the host confirms one, and the review's
// attack (random bytes as 9.9.9 with counter 4 294 967 295) no longer installs or pins anything.
#include <cstring>
#include <random>

#include "CppUTest/TestHarness.h"
#include "development_signer.h"
#include "palpa/core/trusted_keys.h"
#include "palpa/protocol/little_endian.h"
#include "update_scenario.h"

namespace core = palpa::core;
namespace pp = palpa::protocol;
namespace pt = palpa::testing;
namespace ph = palpa::host;

namespace {

/// The review's package: `size` random bytes as version 9.9.9, counter 4 294 967 295.
ph::UpdatePackage HostilePackage(pp::ImageSigner* signer) {
  std::mt19937 rng(1094);
  ph::UpdatePackage p;
  for (uint8_t slot = 0; slot < 2; ++slot) {
    ph::ImageSpec spec;
    spec.body.resize(1094);
    for (uint8_t& b : spec.body) b = static_cast<uint8_t>(rng());
    spec.load_address = core::kDefaultLayout.xip_base + core::kDefaultLayout.slot_offset[slot];
    spec.version_major = spec.version_minor = 9;
    spec.version_revision = 9;
    spec.slot = slot;
    spec.rollback_counter = 4294967295u;
    spec.signer = signer;
    p.slot_image[slot] = ph::BuildImage(spec);
  }
  return p;
}

/// The board's verdict on an image: its compiled-in keys.
pp::ImageError BoardVerdict(const std::vector<uint8_t>& image, pp::ImageInfo* info = nullptr) {
  pp::MemoryImageSource source(image.data(), image.size());
  pp::ImageInfo ignored;
  pp::ImageError error = pp::ImageError::kNone;
  pp::VerifyImage(source, static_cast<uint32_t>(image.size()), &core::TrustedImageKeys(),
                  info != nullptr ? info : &ignored, &error);
  return error;
}

/// Where the unprotected TLV area of an image starts.
size_t TlvAreaAt(const std::vector<uint8_t>& image) {
  const uint16_t header = pp::LoadLe16(image.data() + 8), protected_size = pp::LoadLe16(&image[10]);
  return header + pp::LoadLe32(image.data() + 12) + protected_size;
}

uint32_t Floor(pt::UpdateWorld& w) {
  return core::BootStore(&w.flash, w.layout).Load().rollback_floor;
}

}  // namespace

TEST_GROUP(SignedUpdate){};

TEST(SignedUpdate, TheReviewsHostilePackageIsRefusedAndALegitimateOneStillInstalls) {
  for (pp::ImageSigner* signer : {static_cast<pp::ImageSigner*>(nullptr),
                                  static_cast<pp::ImageSigner*>(&pt::UntrustedSigner())}) {
    pt::UpdateWorld w(21);
    const uint32_t floor = Floor(w);
    const pt::UpdateOutcome hostile = pt::RunUpdate(w, HostilePackage(signer));
    CHECK_FALSE(hostile.completed);
    STRCMP_EQUAL("activate", hostile.failed_step.c_str());
    LONGS_EQUAL(floor, Floor(w));  // nothing pinned
    CHECK(w.Reboot().reason == core::BootReason::kConfirmed);
    LONGS_EQUAL(0, w.running);
    CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 2, 4096, 22)).completed);  // counter 2 installs
    LONGS_EQUAL(2, Floor(w));
  }
}

TEST(SignedUpdate, UnsignedUntrustedAndBadlySignedImagesAreRefusedWithTheirReason) {
  const std::vector<uint8_t> good = pt::MakeRelease(1, 1, 2, 1000, 3).slot_image[0];
  pp::ImageInfo info;
  LONGS_EQUAL((int)pp::ImageError::kNone, (int)BoardVerdict(good, &info));
  LONGS_EQUAL(0, info.trusted_index);
  LONGS_EQUAL((int)pp::ImageError::kUnsigned,
              (int)BoardVerdict(
                  pt::MakeRelease(1, 1, 2, 1000, 3, pp::BoardKind::kSim, nullptr).slot_image[0]));
  LONGS_EQUAL((int)pp::ImageError::kUntrustedKey,
              (int)BoardVerdict(
                  pt::MakeRelease(1, 1, 2, 1000, 3, pp::BoardKind::kSim, &pt::UntrustedSigner())
                      .slot_image[0]));
  // The second trusted key (the one to rotate to) is accepted as itself.
  const auto next =
      pt::MakeRelease(1, 1, 2, 1000, 3, pp::BoardKind::kSim, &pt::DevelopmentNextSigner());
  LONGS_EQUAL((int)pp::ImageError::kNone, (int)BoardVerdict(next.slot_image[0], &info));
  LONGS_EQUAL(1, info.trusted_index);
  // TLVs: SHA-256 (36 bytes), public key (36), signature (68).
  const size_t tlvs = TlvAreaAt(good), key_at = tlvs + 4 + 36, signature_at = key_at + 36;
  for (size_t i = 0; i < 64; ++i) {  // any one bit of the signature
    std::vector<uint8_t> bad = good;
    bad[signature_at + 4 + i] ^= static_cast<uint8_t>(1u << (i % 8));
    LONGS_EQUAL((int)pp::ImageError::kBadSignature, (int)BoardVerdict(bad, &info));
  }
  // A trusted key's name over another key's signature: refused by the signature, not the name.
  std::vector<uint8_t> renamed = next.slot_image[0];
  std::memcpy(&renamed[key_at + 4], core::TrustedImageKeys().key[0], 32);
  LONGS_EQUAL((int)pp::ImageError::kBadSignature, (int)BoardVerdict(renamed, &info));
  LONGS_EQUAL((int)pp::SignatureCheck::kMismatch, (int)info.signature);
  // A signature TLV of the wrong length (the area's length follows): refused as such.
  std::vector<uint8_t> short_signature = good;
  short_signature[signature_at + 2] = 63;
  short_signature.erase(short_signature.end() - 1);
  pp::StoreLe16(&short_signature[tlvs + 2], pp::LoadLe16(&short_signature[tlvs + 2]) - 1);
  LONGS_EQUAL((int)pp::ImageError::kBadSignature, (int)BoardVerdict(short_signature, &info));
  LONGS_EQUAL((int)pp::SignatureCheck::kBadLength, (int)info.signature);
  // A second signature TLV: ambiguous, refused.
  std::vector<uint8_t> twice = good;
  twice.insert(twice.end(), good.end() - 68, good.end());
  pp::StoreLe16(&twice[tlvs + 2], pp::LoadLe16(&twice[tlvs + 2]) + 68);
  LONGS_EQUAL((int)pp::ImageError::kBadTlvArea, (int)BoardVerdict(twice, &info));
}

TEST(SignedUpdate, TheBootloaderBootsNoSlotThatIsNotValidlySigned) {
  for (pp::ImageSigner* signer : {static_cast<pp::ImageSigner*>(nullptr),
                                  static_cast<pp::ImageSigner*>(&pt::UntrustedSigner())}) {
    pt::UpdateWorld w(5);
    // Slot 1 written behind the update engine's back and marked for a trial boot.
    const auto image = pt::MakeRelease(1, 4, 3, 2000, 6, pp::BoardKind::kSim, signer).slot_image[1];
    w.flash.Program(w.layout.slot_offset[1], image.data(), image.size());
    core::BootStore store(&w.flash, w.layout);
    core::BootState state = store.Load();
    state.trial = 1;
    state.trial_state = core::TrialState::kPending;
    CHECK(store.Save(state) == pp::Status::kOk);
    CHECK(w.Reboot().reason == core::BootReason::kConfirmed);
    LONGS_EQUAL(0, w.running);
    // With the good image gone too, nothing boots: recovery mode.
    w.flash.Erase(w.layout.slot_offset[0]);
    CHECK(w.Reboot().reason == core::BootReason::kRecovery);
  }
}

TEST(SignedUpdate, TheFloorMovesOnlyWhenTheHostConfirmsAndOnlyToTheImagesCounter) {
  pt::UpdateWorld w(7);
  LONGS_EQUAL(0, Floor(w));  // the factory image's first boot leaves it
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 6, 3000, 8), false).completed);
  LONGS_EQUAL(0, Floor(w));  // activated and booted in trial: not yet
  CHECK(w.Reboot().reason == core::BootReason::kReverted);
  LONGS_EQUAL(0, Floor(w));  // never confirmed: never
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 6, 3000, 8)).completed);
  LONGS_EQUAL(6, Floor(w));  // confirmed: exactly its counter
  // A signed image with a higher counter found by the bootloader alone (the confirmed slot
  // lost) boots as a fallback but does not move the floor.
  const auto higher = pt::MakeRelease(1, 2, 40, 3000, 9).slot_image[0];
  w.flash.Erase(w.layout.slot_offset[0]);
  w.flash.Program(w.layout.slot_offset[0], higher.data(), higher.size());
  w.flash.Erase(w.layout.slot_offset[1]);
  CHECK(w.Reboot().reason == core::BootReason::kFallback);
  LONGS_EQUAL(6, Floor(w));
}
