// Protocol benchmark: codec throughput (MB/s) and a fixed workload for instruction counting.
//   palpa_protocol_bench throughput        prints encode and decode throughput
//   palpa_protocol_bench frames N          encodes N 8-line telemetry frames (for callgrind)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "palpa/protocol/codec.h"

namespace pp = palpa::protocol;

namespace {

pp::Telemetry EightLineTelemetry(uint32_t i) {
  pp::Telemetry t{};
  t.boot_nonce = 0x1234567u;
  t.first_sample_us = 1000ull * i;
  t.sample_interval_us = 1000;
  t.tick_count = 2;
  t.line_count = 8;
  t.setpoint_generation = i;
  t.sample_count = 16;
  for (uint8_t s = 0; s < 16; ++s) {
    t.samples[s] = pp::LineSample{static_cast<int32_t>(10000 * (s % 8) + i % 97),
                                  static_cast<int32_t>(10000 * (s % 8) - 37),
                                  static_cast<uint16_t>(400 * s), 0};
  }
  return t;
}

// Kept out of line so the instruction count covers exactly one frame's encoding.
[[gnu::noinline]] size_t EncodeOne(const pp::Telemetry& t, uint8_t* out) {
  return pp::EncodeMessageFrame(t, 0, pp::flags::kFromBoard, out, pp::kMaxFrameSize).value;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

int Throughput() {
  constexpr int kFrames = 200000;
  std::vector<pp::Telemetry> messages;
  for (int i = 0; i < 64; ++i) messages.push_back(EightLineTelemetry(static_cast<uint32_t>(i)));
  std::vector<uint8_t> stream;
  stream.reserve(static_cast<size_t>(kFrames) * pp::kMaxFrameSize);
  uint8_t frame[pp::kMaxFrameSize];

  auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kFrames; ++i) {
    const size_t n = EncodeOne(messages[i % 64], frame);
    stream.insert(stream.end(), frame, frame + n);
  }
  const double encode_s = Seconds(start);

  start = std::chrono::steady_clock::now();
  pp::OwningFrameDecoder decoder;
  size_t decoded = 0;
  uint64_t checksum = 0;
  for (uint8_t b : stream) {
    if (decoder.Process(b) != pp::FrameDecoder::Event::kFrame) continue;
    pp::DispatchFrame(decoder.frame(), [&](const auto& m, const pp::Header&) {
      if constexpr (std::is_same_v<std::decay_t<decltype(m)>, pp::Telemetry>) {
        checksum += static_cast<uint64_t>(m.samples[3].setpoint_pa);
        ++decoded;
      }
    });
  }
  const double decode_s = Seconds(start);
  if (decoded != kFrames) {
    std::fprintf(stderr, "decoded %zu of %d frames\n", decoded, kFrames);
    return 1;
  }
  const double mb = static_cast<double>(stream.size()) / 1e6;
  std::printf("codec: %d telemetry frames (8 lines x 2 ticks, %zu bytes each on the wire)\n",
              kFrames, stream.size() / kFrames);
  std::printf("  encode + frame : %8.1f MB/s  (%.0f frames/s)\n", mb / encode_s,
              kFrames / encode_s);
  std::printf("  deframe+decode : %8.1f MB/s  (%.0f frames/s)  [checksum %llu]\n", mb / decode_s,
              kFrames / decode_s, static_cast<unsigned long long>(checksum % 1000));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "throughput") == 0) return Throughput();
  if (argc == 3 && std::strcmp(argv[1], "frames") == 0) {
    const long n = std::strtol(argv[2], nullptr, 10);
    uint8_t frame[pp::kMaxFrameSize];
    const pp::Telemetry t = EightLineTelemetry(7);
    size_t total = 0;
    for (long i = 0; i < n; ++i) total += EncodeOne(t, frame);
    return total > 0 ? 0 : 1;
  }
  std::fprintf(stderr, "usage: palpa_protocol_bench throughput | frames N\n");
  return 2;
}
