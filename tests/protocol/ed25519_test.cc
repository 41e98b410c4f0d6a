// The board's Ed25519 verifier, SHA-512 and SHA-256 against libsodium: RFC 8032's vectors, 2 000
// random keys and messages, corruptions, and every malformed class (S ≥ L, small-order R and A,
// non-canonical encodings, wrong lengths). Both must reach the same verdict on every input.
#include <sodium.h>

#include <random>
#include <string>
#include <vector>

#include "CppUTest/TestHarness.h"
#include "palpa/protocol/ed25519.h"
#include "palpa/protocol/sha256.h"
#include "palpa/protocol/sha512.h"
#include "rfc8032_vectors.h"

namespace pp = palpa::protocol;

namespace {

using Bytes = std::vector<uint8_t>;

Bytes Hex(const char* hex) {
  Bytes out;
  for (size_t i = 0; hex[i] != 0 && hex[i + 1] != 0; i += 2)
    out.push_back(static_cast<uint8_t>(std::stoi(std::string(hex + i, 2), nullptr, 16)));
  return out;
}

bool SodiumAccepts(const Bytes& sig, const Bytes& msg, const Bytes& pk) {
  return crypto_sign_verify_detached(sig.data(), msg.data(), msg.size(), pk.data()) == 0;
}

pp::SignatureCheck Ours(const Bytes& sig, const Bytes& msg, const Bytes& pk) {
  return pp::Ed25519Verify(sig.data(), sig.size(), msg.data(), msg.size(), pk.data(), pk.size());
}

/// Both verifiers on one input: the same verdict, and ours gives `expected` as its reason.
void ExpectVerdict(const Bytes& sig, const Bytes& msg, const Bytes& pk, pp::SignatureCheck expected,
                   const char* what) {
  const pp::SignatureCheck ours = Ours(sig, msg, pk);
  const bool sodium = SodiumAccepts(sig, msg, pk);
  CHECK_EQUAL_TEXT(sodium, ours == pp::SignatureCheck::kValid, what);
  STRCMP_EQUAL_TEXT(pp::SignatureCheckName(expected), pp::SignatureCheckName(ours), what);
}

struct KeyPair {
  Bytes pk = Bytes(32), sk = Bytes(64);
};

KeyPair FromSeed(const Bytes& seed) {
  KeyPair k;
  crypto_sign_seed_keypair(k.pk.data(), k.sk.data(), seed.data());
  return k;
}

Bytes Sign(const KeyPair& k, const Bytes& msg) {
  Bytes sig(64);
  crypto_sign_detached(sig.data(), nullptr, msg.data(), msg.size(), k.sk.data());
  return sig;
}

Bytes RandomBytes(std::mt19937_64& rng, size_t n) {
  Bytes out(n);
  for (auto& b : out) b = static_cast<uint8_t>(rng());
  return out;
}

/// The eight points of small order (1, 2, 4, 8), canonically encoded.
const char* const kSmallOrder[] = {
    "0100000000000000000000000000000000000000000000000000000000000000",
    "ecffffffffffffffffffffffffffffffffffffffffffffffffffffffffffff7f",
    "0000000000000000000000000000000000000000000000000000000000000000",
    "0000000000000000000000000000000000000000000000000000000000000080",
    "c7176a703d4dd84fba3c0b760d10670f2a2053fa2c39ccc64ec7fd7792ac037a",
    "c7176a703d4dd84fba3c0b760d10670f2a2053fa2c39ccc64ec7fd7792ac03fa",
    "26e8958fc2b227b045c3f489f2ef98f0d5dfac05d3c63339b13802886d53fc05",
    "26e8958fc2b227b045c3f489f2ef98f0d5dfac05d3c63339b13802886d53fc85"};

/// y + p for the curve's y values below 19 (each also has a canonical encoding y).
Bytes NonCanonical(uint8_t y, bool sign) {
  Bytes out(32, 0xff);
  out[0] = static_cast<uint8_t>(0xed + y);
  out[31] = sign ? 0xff : 0x7f;
  return out;
}

/// S + L (little-endian), a second encoding of the same scalar.
Bytes AddOrder(const Bytes& s) {
  const Bytes order = Hex("edd3f55c1a631258d69cf7a2def9de1400000000000000000000000000000010");
  Bytes out(32);
  unsigned carry = 0;
  for (int i = 0; i < 32; ++i) {
    carry += s[i] + order[i];
    out[i] = static_cast<uint8_t>(carry);
    carry >>= 8;
  }
  return out;
}

}  // namespace

TEST_GROUP(Sha512){void setup() override{CHECK(sodium_init() >= 0);
}
}
;

/// Every message length from 0 to 399 (three SHA-512 blocks, six SHA-256 ones, and every padding
/// case), fed in random pieces: the same digest as libsodium's `reference`.
template <class Hasher>
void MatchesAtEveryLengthInPieces(int (*reference)(unsigned char*, const unsigned char*,
                                                   unsigned long long),
                                  uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (size_t n = 0; n < 400; ++n) {
    const Bytes data = RandomBytes(rng, n);
    decltype(Hasher().Finish()) want;
    reference(want.data(), data.data(), data.size());
    Hasher h;
    for (size_t at = 0; at < n;) {
      const size_t take = std::min<size_t>(n - at, 1 + rng() % 150);
      h.Update(data.data() + at, take);
      at += take;
    }
    const auto got = h.Finish();
    MEMCMP_EQUAL_TEXT(want.data(), got.data(), want.size(), std::to_string(n).c_str());
  }
}

TEST(Sha512, MatchesLibsodiumAtEveryLengthAroundTheBlockAndInPieces) {
  MatchesAtEveryLengthInPieces<pp::Sha512Hasher>(crypto_hash_sha512, 512);
}

TEST_GROUP(Sha256){void setup() override{CHECK(sodium_init() >= 0);
}
}
;

TEST(Sha256, MatchesLibsodiumAtEveryLengthAroundTheBlockAndInPieces) {
  MatchesAtEveryLengthInPieces<pp::Sha256Hasher>(crypto_hash_sha256, 256);
}

TEST_GROUP(Ed25519){void setup() override{CHECK(sodium_init() >= 0);
}
}
;

TEST(Ed25519, Rfc8032VectorsAreReproducedByLibsodiumAndAccepted) {
  for (const auto& v : palpa::test::kRfc8032Vectors) {
    const KeyPair k = FromSeed(Hex(v.seed));
    const Bytes msg = Hex(v.message), sig = Hex(v.signature), pk = Hex(v.public_key);
    CHECK_TEXT(k.pk == pk, v.name);
    CHECK_TEXT(Sign(k, msg) == sig, v.name);
    ExpectVerdict(sig, msg, pk, pp::SignatureCheck::kValid, v.name);
    Bytes other = msg;
    other.push_back(0);
    ExpectVerdict(sig, other, pk, pp::SignatureCheck::kMismatch, v.name);
  }
}

TEST(Ed25519, TwoThousandRandomKeysAndMessagesSignedByLibsodium) {
  std::mt19937_64 rng(25519);
  int accepted = 0, refused = 0;
  for (int i = 0; i < 2000; ++i) {
    const KeyPair k = FromSeed(RandomBytes(rng, 32));
    const Bytes msg = RandomBytes(rng, rng() % 200);
    const Bytes sig = Sign(k, msg);
    CHECK_EQUAL((int)pp::SignatureCheck::kValid, (int)Ours(sig, msg, k.pk));
    CHECK(SodiumAccepts(sig, msg, k.pk));
    ++accepted;
    // One flipped bit in the signature, the message or the key: both refuse.
    Bytes bad_sig = sig, bad_msg = msg, bad_pk = k.pk;
    switch (i % 3) {
      case 0:
        bad_sig[rng() % 64] ^= static_cast<uint8_t>(1u << (rng() % 8));
        break;
      case 1:
        if (bad_msg.empty())
          bad_msg.push_back(0);
        else
          bad_msg[rng() % bad_msg.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
        break;
      default:
        bad_pk[rng() % 32] ^= static_cast<uint8_t>(1u << (rng() % 8));
    }
    const pp::SignatureCheck ours = Ours(bad_sig, bad_msg, bad_pk);
    CHECK(ours != pp::SignatureCheck::kValid);
    CHECK(!SodiumAccepts(bad_sig, bad_msg, bad_pk));
    ++refused;
  }
  LONGS_EQUAL(2000, accepted);
  LONGS_EQUAL(2000, refused);
}

TEST(Ed25519, RandomBytesAsSignaturesAndKeysGetTheSameVerdictFromBoth) {
  std::mt19937_64 rng(8032);
  for (int i = 0; i < 2000; ++i) {
    const Bytes sig = RandomBytes(rng, 64), msg = RandomBytes(rng, 40), pk = RandomBytes(rng, 32);
    CHECK_EQUAL(SodiumAccepts(sig, msg, pk), Ours(sig, msg, pk) == pp::SignatureCheck::kValid);
  }
}

TEST(Ed25519, NonCanonicalSIsRefused) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 200; ++i) {
    const KeyPair k = FromSeed(RandomBytes(rng, 32));
    const Bytes msg = RandomBytes(rng, 32);
    Bytes sig = Sign(k, msg);
    const Bytes s_plus_l = AddOrder(Bytes(sig.begin() + 32, sig.end()));
    std::copy(s_plus_l.begin(), s_plus_l.end(), sig.begin() + 32);  // the same S mod L
    ExpectVerdict(sig, msg, k.pk, pp::SignatureCheck::kNonCanonicalS, "S + L");
  }
  const KeyPair k = FromSeed(Bytes(32, 7));
  Bytes sig = Sign(k, {});
  const Bytes order = AddOrder(Bytes(32, 0));
  std::copy(order.begin(), order.end(), sig.begin() + 32);
  ExpectVerdict(sig, {}, k.pk, pp::SignatureCheck::kNonCanonicalS, "S = L");
  std::fill(sig.begin() + 32, sig.end(), 0xff);
  ExpectVerdict(sig, {}, k.pk, pp::SignatureCheck::kNonCanonicalS, "S = 2^256 - 1");
}

TEST(Ed25519, SmallOrderKeysAreRefusedEvenWithSignaturesThatSatisfyTheEquation) {
  // With A of small order, [k]A vanishes for k ≡ 0 mod its order and R = [S]B "verifies" any
  // message: a forgery the small-order check exists for.
  std::mt19937_64 rng(2);
  for (const char* a : kSmallOrder) {
    const Bytes pk = Hex(a);
    for (int i = 0; i < 20; ++i) {
      Bytes s(32);
      crypto_core_ed25519_scalar_random(s.data());
      Bytes r(32);
      CHECK(crypto_scalarmult_ed25519_base_noclamp(r.data(), s.data()) == 0);
      Bytes sig = r;
      sig.insert(sig.end(), s.begin(), s.end());
      const Bytes msg = RandomBytes(rng, 16);
      ExpectVerdict(sig, msg, pk, pp::SignatureCheck::kSmallOrderKey, a);
    }
  }
}

TEST(Ed25519, SmallOrderRIsRefused) {
  std::mt19937_64 rng(3);
  for (const char* r : kSmallOrder) {
    const KeyPair k = FromSeed(RandomBytes(rng, 32));
    Bytes sig = Hex(r);
    const Bytes s = RandomBytes(rng, 31);
    sig.insert(sig.end(), s.begin(), s.end());
    sig.push_back(0);  // S < L
    ExpectVerdict(sig, {1, 2, 3}, k.pk, pp::SignatureCheck::kSmallOrderR, r);
  }
  // The identity as both R and A with S = 0 satisfies the equation outright.
  Bytes sig = Hex(kSmallOrder[0]);
  sig.resize(64, 0);
  ExpectVerdict(sig, {}, Hex(kSmallOrder[0]), pp::SignatureCheck::kSmallOrderKey, "R = A = O");
}

TEST(Ed25519, NonCanonicalPointEncodingsAreRefused) {
  const KeyPair k = FromSeed(Bytes(32, 9));
  const Bytes msg = {4, 5, 6};
  const Bytes good = Sign(k, msg);
  for (uint8_t y : {0, 1, 3, 4, 5, 6, 9, 10, 14, 15, 16, 18}) {
    for (bool sign : {false, true}) {
      ExpectVerdict(good, msg, NonCanonical(y, sign), pp::SignatureCheck::kBadKey, "A = y + p");
      Bytes sig = NonCanonical(y, sign);
      sig.insert(sig.end(), good.begin() + 32, good.end());
      ExpectVerdict(sig, msg, k.pk, pp::SignatureCheck::kBadR, "R = y + p");
    }
  }
  // x = 0 with the sign bit set: y = 1 and y = -1 have x = 0 ("negative zero").
  Bytes negative_zero = Hex(kSmallOrder[0]);
  negative_zero[31] |= 0x80;
  ExpectVerdict(good, msg, negative_zero, pp::SignatureCheck::kBadKey, "A = -0");
  // A y whose x^2 is not a square: no point at all.
  Bytes off_curve = Hex(kSmallOrder[0]);
  off_curve[0] = 2;
  ExpectVerdict(good, msg, off_curve, pp::SignatureCheck::kBadKey, "A off the curve");
}

TEST(Ed25519, WrongLengthsAreRefused) {
  const KeyPair k = FromSeed(Bytes(32, 1));
  const Bytes msg = {1};
  const Bytes sig = Sign(k, msg);
  for (size_t n : {0, 32, 63, 65, 128}) {
    Bytes s = sig;
    s.resize(n, 0);
    LONGS_EQUAL((int)pp::SignatureCheck::kBadLength, (int)Ours(s, msg, k.pk));
  }
  for (size_t n : {0, 31, 33, 64}) {
    Bytes pk = k.pk;
    pk.resize(n, 0);
    LONGS_EQUAL((int)pp::SignatureCheck::kBadLength, (int)Ours(sig, msg, pk));
  }
  // libsodium's combined form refuses a signed message shorter than a signature the same way.
  unsigned long long opened = 0;
  uint8_t out[64];
  CHECK(crypto_sign_open(out, &opened, sig.data(), 63, k.pk.data()) != 0);
}
