// Image signing with libsodium's Ed25519 (deterministic signatures, RFC 8032).
#include "palpa/hal/linux/ed25519_signer.h"

#include <sodium.h>

#include <cstdlib>

namespace palpa::hal::linux_signing {
namespace {

void InitSodium() {
  if (sodium_init() < 0) std::abort();  // no usable randomness source: nothing can be signed
}

}  // namespace

Ed25519Signer::Ed25519Signer(const Ed25519Seed& seed) : seed_(seed) {
  InitSodium();
  crypto_sign_seed_keypair(public_.data(), secret_.data(), seed_.data());
}

Ed25519Signer Ed25519Signer::Generate() {
  InitSodium();
  Ed25519Seed seed;
  randombytes_buf(seed.data(), seed.size());
  Ed25519Signer signer(seed);
  sodium_memzero(seed.data(), seed.size());
  return signer;
}

Ed25519Signer::~Ed25519Signer() {
  sodium_memzero(seed_.data(), seed_.size());
  sodium_memzero(secret_.data(), secret_.size());
}

bool Ed25519Signer::Sign(const protocol::Sha256Digest& digest, uint8_t* signature) {
  return crypto_sign_detached(signature, nullptr, digest.data(), digest.size(), secret_.data()) ==
         0;
}

}  // namespace palpa::hal::linux_signing
