// Ed25519 check on the Cortex-M4F under QEMU: the verifier, built with the target's flags,
// accepts RFC 8032's five vectors and refuses each with one bit of its message flipped. Also the
// image tests/bench/signature.sh counts the instructions of one verification in. Exits through
// semihosting: 0 when every verdict is right, 1 with the failing vector printed.
#include "palpa/protocol/ed25519.h"
#include "rfc8032_vectors.h"
#include "semihosting.h"

namespace pp = palpa::protocol;
namespace mps2 = palpa::boards::mps2;

namespace {

uint8_t g_message[1024];

uint8_t Nibble(char c) { return static_cast<uint8_t>(c <= '9' ? c - '0' : c - 'a' + 10); }

size_t FromHex(const char* hex, uint8_t* out, size_t capacity) {
  size_t n = 0;
  for (; hex[2 * n] != 0 && n < capacity; ++n)
    out[n] = static_cast<uint8_t>(Nibble(hex[2 * n]) << 4 | Nibble(hex[2 * n + 1]));
  return n;
}

}  // namespace

int main() {
  int index = 0;
  for (const auto& v : palpa::test::kRfc8032Vectors) {
    uint8_t key[32], signature[64];
    FromHex(v.public_key, key, sizeof(key));
    FromHex(v.signature, signature, sizeof(signature));
    const size_t size = FromHex(v.message, g_message, sizeof(g_message));
    const pp::SignatureCheck good =
        pp::Ed25519Verify(signature, sizeof(signature), g_message, size, key, sizeof(key));
    g_message[0] ^= 1;  // the empty message of TEST 1 gets one byte instead
    const pp::SignatureCheck bad = pp::Ed25519Verify(signature, sizeof(signature), g_message,
                                                     size == 0 ? 1 : size, key, sizeof(key));
    if (good != pp::SignatureCheck::kValid || bad != pp::SignatureCheck::kMismatch) {
      mps2::SemihostPrint(v.name);
      mps2::SemihostPrint(": ");
      mps2::SemihostPrint(pp::SignatureCheckName(good));
      mps2::SemihostPrint(" / ");
      mps2::SemihostPrint(pp::SignatureCheckName(bad));
      mps2::SemihostPrint("\ned25519 check: wrong verdict\n");
      mps2::SemihostExit(1);
    }
    ++index;
  }
  mps2::SemihostPrintNumber("ed25519 check: verdicts right, vectors", static_cast<uint32_t>(index));
  mps2::SemihostPrint("\n");
  mps2::SemihostExit(0);
}
