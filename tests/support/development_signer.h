// The tests' image signers: the DEVELOPMENT ONLY keys the development builds trust, and a key
// no board trusts.
#pragma once

#include "palpa/hal/linux/ed25519_signer.h"
#include "palpa/keys/development_keys.h"

namespace palpa::testing {

/// firmware/keys/development.key, which palpa-sim and the development images trust.
inline hal::linux_signing::Ed25519Signer& DevelopmentSigner() {
  static hal::linux_signing::Ed25519Signer signer(keys::DevelopmentSeed());
  return signer;
}

/// firmware/keys/development-next.key: the second trusted key (the one to rotate to).
inline hal::linux_signing::Ed25519Signer& DevelopmentNextSigner() {
  static hal::linux_signing::Ed25519Signer signer(keys::DevelopmentNextSeed());
  return signer;
}

/// A key of the tests' own, trusted by no board.
inline hal::linux_signing::Ed25519Signer& UntrustedSigner() {
  static hal::linux_signing::Ed25519Signer signer(hal::linux_signing::Ed25519Seed{42, 42, 42});
  return signer;
}

}  // namespace palpa::testing
