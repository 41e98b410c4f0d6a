// Links protocol/ into a program with no C or C++ runtime at all: any use of the heap, exceptions,
// RTTI or static-init guards leaves an undefined symbol and fails the build.
#include "palpa/protocol/codec.h"
#include "palpa/protocol/ed25519.h"
#include "palpa/protocol/reliable_receiver.h"
#include "palpa/protocol/reliable_sender.h"
#include "palpa/protocol/session.h"

#include "bare_runtime.h"

namespace pp = palpa::protocol;

namespace {

int Exercise() {
  uint8_t frame[pp::kMaxFrameSize];
  pp::Telemetry t{};
  t.tick_count = 1;
  t.line_count = 1;
  t.sample_count = 1;
  const auto n = pp::EncodeMessageFrame(t, 0, pp::flags::kFromBoard, frame, sizeof(frame));
  if (!n.ok()) return 1;
  pp::OwningFrameDecoder decoder;
  int frames = 0;
  for (size_t i = 0; i < n.value; ++i) {
    if (decoder.Process(frame[i]) == pp::FrameDecoder::Event::kFrame) {
      pp::DispatchFrame(decoder.frame(), [&](const auto&, const pp::Header&) { ++frames; });
    }
  }
  pp::ReliableReceiver receiver;
  receiver.Reset(250);
  const pp::CachedOutcome* cached = nullptr;
  if (receiver.Classify(250, &cached) != pp::ReliableReceiver::Verdict::kApply) return 2;
  pp::ReliableSender sender;
  sender.Reset(0);
  if (!sender.Submit(pp::ClearFault{}, 1).ok()) return 3;
  sender.Transmit(0, [](const uint8_t*, size_t) {});
  pp::HostSession session;
  char text[96];
  session.DescribeVersions(text, sizeof(text));
  const uint8_t key[32] = {1}, signature[64] = {};  // the identity as a key: refused
  if (pp::Ed25519Verify(signature, 64, key, 32, key, 32) != pp::SignatureCheck::kSmallOrderKey)
    return 5;
  return frames == 1 ? 0 : 4;
}

}  // namespace

extern "C" int palpa_check_main() { return Exercise(); }
