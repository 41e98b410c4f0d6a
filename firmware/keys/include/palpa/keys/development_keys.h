// The DEVELOPMENT ONLY key pairs (firmware/keys/*.key): published with the source, so what they
// sign proves nothing outside the lab. palpa-sim's factory image and the tests sign with them;
// never linked into the host library.
#pragma once

#include "palpa/hal/linux/ed25519_signer.h"

namespace palpa::keys {

/// firmware/keys/development.key: the key development builds trust first.
const hal::linux_signing::Ed25519Seed& DevelopmentSeed();
/// firmware/keys/development-next.key: the second trusted key (the one to rotate to).
const hal::linux_signing::Ed25519Seed& DevelopmentNextSeed();

}  // namespace palpa::keys
