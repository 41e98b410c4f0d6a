// The Ed25519 public keys this firmware accepts images from: compiled in from the build's
// PALPA_TRUSTED_KEYS (cmake/PalpaKeys.cmake), the current key and one to rotate to. Never taken
// from the link: an image names its signer, and the board checks that name against this list.
#pragma once

#include "palpa/protocol/image.h"

namespace palpa::core {

const protocol::TrustedKeys& TrustedImageKeys();

}  // namespace palpa::core
