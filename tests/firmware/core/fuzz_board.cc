// libFuzzer target: the whole board behind its link, driven by a script of operations.
//
// Whatever arrives — packets of any type and body, garbage bytes, configurations edited
// anywhere and sent directly or staged, sensor counts of any value, the E-stop pin, a failing
// DAC, long silences — the board must not crash or invoke undefined behaviour, and:
//  * every configured line's DAC code commands a pressure within the line's limits and its
//    kind's hard ceiling (checked after every tick against the configuration the tick ran with);
//  * a channel a configuration dropped holds the safe code of the line it last had;
//  * a refused configuration message changes nothing of the live configuration;
//  * every commanded pressure is finite;
//  * while an update is under way every line holds its safe code, no update message ever
//    changes the bootloader or the running image's slot, and an activated slot holds a valid
//    image the rollback floor allows (board_fuzz_update.cc);
//  * a Close of the session ends it and a Release keeps it, both with every line at its safe
//    code from the next tick and no fault latched for them; a Close during an update leaves what
//    was written resumable; a Close or Release of another session, a repeated Close and a second
//    host's Hello change nothing (no_session, busy).
// Each operation is an opcode byte followed by its arguments (missing bytes read as 0).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "board_fuzz_update.h"
#include "board_harness.h"
#include "dac_pressure.h"
#include "fuzz_input.h"
#include "palpa/core/board_configs.h"
#include "palpa/core/ceilings.h"
#include "palpa/protocol/crc32.h"

namespace pp = palpa::protocol;
namespace pc = palpa::core;
using palpa::testing::BoardHarness;

namespace {

using Script = palpa::testing::FuzzInput;

constexpr auto Fail = palpa::testing::BoardFuzzFail;

using palpa::testing::PressureOfCounts;
using palpa::testing::PressurePerCount;

bool IsConfigurationChange(uint8_t type) {
  using T = pp::MessageType;
  return type == static_cast<uint8_t>(T::kConfigureBoard) ||
         type == static_cast<uint8_t>(T::kConfigureLine) ||
         type == static_cast<uint8_t>(T::kConfigureFinger) ||
         type == static_cast<uint8_t>(T::kStagedCommit);
}

/// PALPA_BOARD_FUZZ_TRACE set: each answer and each run of ticks is printed (to read a finding).
const bool kTrace = std::getenv("PALPA_BOARD_FUZZ_TRACE") != nullptr;

struct Fuzzer {
  palpa::testing::UpdateFuzzer update;  // before the board, which keeps a pointer to its engine
  BoardHarness h;
  /// The last configuration each DAC channel had, for the dropped-channel check.
  std::array<pp::ConfigureLine, palpa::hal::fake::kChannels> last_line{};
  std::array<bool, palpa::hal::fake::kChannels> ever_configured{};

  explicit Fuzzer(const char* config_name)
      : h(config_name, pp::ResetCause::kPowerOn, nullptr, &update.engine()) {
    Remember();
  }

  void Remember() {
    const pc::BoardConfig& c = h.board->config();
    for (uint8_t i = 0; i < c.line_count; ++i) {
      last_line[i] = c.lines[i];
      ever_configured[i] = true;
    }
  }

  /// Outputs against `ran_with`, the configuration the last tick used.
  void CheckOutputs(const pc::BoardConfig& ran_with) {
    const pc::BoardConfig& live = h.board->config();
    for (uint8_t i = 0; i < live.line_count; ++i) {
      if (!std::isfinite(h.board->line_output(i).command_pa))
        Fail("commanded pressure not finite", i);
    }
    // A failing DAC keeps its last codes (the board latches output_write and the valves take the
    // pressure away); the codes are checked again once writes succeed.
    if (h.dac.fail) return;
    for (uint8_t i = 0; i < ran_with.line_count; ++i) {
      const pp::ConfigureLine& c = ran_with.lines[i];
      const float pa = PressureOfCounts(c, h.dac.counts[i]);
      const float lsb = PressurePerCount(c);
      const pc::Ceiling ceiling = pc::CeilingFor(c.kind);
      if (h.dac.counts[i] > (1u << c.dac_bits) - 1u) Fail("DAC code beyond its resolution", i);
      if (pa < static_cast<float>(c.limit_min_pa) - lsb ||
          pa > static_cast<float>(c.limit_max_pa) + lsb)
        Fail("DAC code outside the line's limits", i);
      if (pa < static_cast<float>(ceiling.min_pa) - lsb ||
          pa > static_cast<float>(ceiling.max_pa) + lsb)
        Fail("DAC code outside the hard ceiling", i);
    }
    if (update.engine().in_update_mode()) {  // the outputs are safe before anything is erased
      for (uint8_t i = 0; i < ran_with.line_count; ++i) {
        const pp::ConfigureLine& c = ran_with.lines[i];
        if (std::fabs(PressureOfCounts(c, h.dac.counts[i]) - static_cast<float>(c.safe_pa)) >
            PressurePerCount(c))
          Fail("a line is not at its safe code during an update", i);
      }
    }
    for (uint8_t i = live.line_count; i < palpa::hal::fake::kChannels; ++i) {
      if (!ever_configured[i]) continue;
      const pp::ConfigureLine& c = last_line[i];
      const float pa = PressureOfCounts(c, h.dac.counts[i]);
      if (std::fabs(pa - static_cast<float>(c.safe_pa)) > PressurePerCount(c))
        Fail("a dropped channel is not at its safe code", i);
    }
  }

  /// One loop pass with the output checks; the plant follows as `plant` says.
  void Step(uint8_t plant) {
    const pc::BoardConfig ran_with = h.board->config();
    if (h.board->Step()) CheckOutputs(ran_with);
    Remember();
    if (plant % 3 == 1) h.FollowModel();
    if (plant % 3 == 2) h.FollowCommands();
  }

  void RunTicks(uint32_t ms, uint8_t plant, bool heartbeat) {
    for (uint32_t i = 0; i < ms; ++i) {
      h.clock.Advance(pc::Board::kTickUs);
      if (heartbeat && i % 20 == 0) {
        uint8_t frame[pp::kMaxFrameSize];
        const auto n = pp::EncodeMessageFrame(pp::Heartbeat{h.hello_nonce, ++h.generation}, 0, 0,
                                              frame, sizeof(frame));
        h.link.Inject(frame, n.value);
      }
      Step(plant);
      h.link.tx.clear();
    }
    if (!kTrace) return;
    std::fprintf(stderr, "%u ms: safe %d, latched 0x%x, DAC", ms, h.board->safe(),
                 h.board->latched_faults());
    for (uint8_t i = 0; i < h.board->config().line_count; ++i)
      std::fprintf(stderr, " %u", h.dac.counts[i]);
    std::fprintf(stderr, "\n");
  }

  /// Sends one packet and checks that a refused configuration change applied nothing.
  void SendPacket(uint8_t type, uint8_t seq, uint8_t flags, const uint8_t* body, size_t size) {
    if (size > pp::kMaxBodySize) size = pp::kMaxBodySize;
    uint8_t packet[pp::kMaxPacketSize];
    pp::WriteHeader(pp::Header{pp::kProtocolVersion, type, seq, flags}, packet);
    if (size > 0) std::memcpy(packet + pp::kHeaderSize, body, size);
    uint8_t frame[pp::kMaxFrameSize];
    const auto n = pp::EncodeFrame(packet, pp::kHeaderSize + size, frame, sizeof(frame));
    if (!n.ok()) Fail("a packet of at most the maximum size did not frame", type);
    const uint32_t before = pc::ConfigCrc(h.board->config());
    h.link.Inject(frame, n.value);
    Step(0);
    const pp::Status answer =
        BoardHarness::AnswerFor(h.Drain(), static_cast<pp::MessageType>(type));
    const bool refused = answer != pp::Status::kOk && answer != pp::Status::kUnavailable;
    if (kTrace) std::fprintf(stderr, "type %u: %s\n", type, pp::StatusName(answer));
    if (IsConfigurationChange(type) && refused && pc::ConfigCrc(h.board->config()) != before)
      Fail("a refused configuration changed the live one", type);
  }

  /// A reliable packet with the sequence number the board expects next.
  void SendReliable(uint8_t type, const uint8_t* body, size_t size) {
    SendPacket(type, h.next_seq++, pp::flags::kReliable, body, size);
  }

  /// One record of the live configuration's blob, edited at a few places, sent directly or as a
  /// staged upload with a correct CRC, so edits reach validation rather than the CRC check.
  void SendEditedRecord(Script& s) {
    std::vector<uint8_t> blob(pc::kMaxConfigBlob);
    const auto n = pc::EncodeConfigBlob(h.board->config(), blob.data(), blob.size());
    if (!n.ok()) Fail("the live configuration does not encode", 0);
    std::vector<std::pair<size_t, size_t>> records;  // offset, size (header included)
    for (size_t at = 0; at + 3 <= n.value;) {
      const size_t body = blob[at] | blob[at + 1] << 8;
      records.emplace_back(at, 3 + body);
      at += 3 + body;
    }
    const auto [offset, size] = records[s.Byte() % records.size()];
    std::vector<uint8_t> record(blob.begin() + offset, blob.begin() + offset + size);
    const uint8_t edits = s.Byte() % 8;
    for (uint8_t e = 0; e < edits && size > 3; ++e) record[3 + s.Word() % (size - 3)] = s.Byte();
    if (s.Byte() % 2 == 0) return SendReliable(record[2], record.data() + 3, size - 3);
    pp::StagedBegin begin{static_cast<uint16_t>(size)};
    uint8_t body[pp::kMaxBodySize];
    SendReliable(static_cast<uint8_t>(pp::MessageType::kStagedBegin), body,
                 pp::EncodeBody(begin, body, sizeof(body)).value);
    for (size_t at = 0; at < size; at += pp::kMaxStagedChunk) {
      pp::StagedPart part{};
      part.offset = static_cast<uint16_t>(at);
      part.data_size = static_cast<uint8_t>(std::min<size_t>(pp::kMaxStagedChunk, size - at));
      std::memcpy(part.data.data(), record.data() + at, part.data_size);
      SendReliable(static_cast<uint8_t>(pp::MessageType::kStagedPart), body,
                   pp::EncodeBody(part, body, sizeof(body)).value);
    }
    const pp::StagedCommit commit{static_cast<uint16_t>(size), pp::Crc32(record.data(), size)};
    SendReliable(static_cast<uint8_t>(pp::MessageType::kStagedCommit), body,
                 pp::EncodeBody(commit, body, sizeof(body)).value);
  }

  /// A compensator for a finger, sent as ConfigureFinger: a kind and parameters in its layout,
  /// either plausible (climbing thresholds and curves, weights of either sign over ten decades,
  /// so many sets pass validation and run) or raw bit patterns (NaN, infinities, denormals).
  void SendCompensator(Script& s) {
    const pc::BoardConfig& c = h.board->config();
    if (c.finger_count == 0) return;
    pp::ConfigureFinger f = c.fingers[s.Byte() % c.finger_count];
    const uint8_t kind = s.Byte() % 4, size = 1 + s.Byte() % 31;
    auto spread = [&s](bool sign) {  // a mantissa and a decade from 1e-6 to 1e3
      const uint8_t b = s.Byte();
      const float v = (1.0f + static_cast<float>(s.Byte()) / 64.0f) *
                      std::pow(10.0f, static_cast<float>(b % 10) - 6.0f);
      return sign && (b & 0x80) != 0 ? -v : v;
    };
    std::vector<float> p;
    auto climb = [&](uint8_t n, float step) {
      float v = 0;
      for (uint8_t i = 0; i < n; ++i) p.push_back(v += step * static_cast<float>(s.Byte()));
    };
    auto weights = [&](uint8_t n) {
      for (uint8_t i = 0; i < n; ++i) p.push_back(spread(true));
    };
    if (kind == 0) {
      f.compensator = pp::CompensatorKind::kBranch;  // band, dead band, y, rising, falling
      p = {spread(false) * 1000.0f, 20.0f * static_cast<float>(s.Byte())};
      climb(size, 20.0f);
      climb(size, 400.0f);
      climb(size, 400.0f);
    } else if (kind == 1 || kind == 2) {  // [n,] offset, w0, r, w[, d, g]
      const bool api = kind == 2;
      f.compensator =
          api ? pp::CompensatorKind::kAsymmetricPi : pp::CompensatorKind::kPrandtlIshlinskii;
      if (api) p.push_back(static_cast<float>(size));
      p.push_back(spread(true));
      p.push_back(spread(false));
      climb(size, 400.0f);
      weights(size);
      if (api) {
        const uint8_t zones = 1 + s.Byte() % 8;
        climb(zones, 20.0f);
        weights(zones);
      }
    } else {
      f.compensator = static_cast<pp::CompensatorKind>(s.Byte() % 4);
      for (uint8_t i = 0; i < size; ++i) {
        uint32_t bits =
            s.Byte() | s.Byte() << 8 | s.Byte() << 16 | static_cast<uint32_t>(s.Byte()) << 24;
        float v;
        std::memcpy(&v, &bits, sizeof(v));
        p.push_back(v);
      }
    }
    f.param_count = static_cast<uint8_t>(std::min(p.size(), f.params.size()));
    std::copy(p.begin(), p.begin() + f.param_count, f.params.begin());
    uint8_t body[pp::kMaxBodySize];
    const auto n = pp::EncodeBody(f, body, sizeof(body));
    if (n.ok())
      SendReliable(static_cast<uint8_t>(pp::MessageType::kConfigureFinger), body, n.value);
  }

  /// Every configured line at its safe code (a failing DAC keeps its old codes: not judged).
  void CheckAllSafe(const char* what) {
    const pc::BoardConfig& c = h.board->config();
    if (h.dac.fail) return;
    for (uint8_t i = 0; i < c.line_count; ++i) {
      if (std::fabs(PressureOfCounts(c.lines[i], h.dac.counts[i]) -
                    static_cast<float>(c.lines[i].safe_pa)) > PressurePerCount(c.lines[i]))
        Fail(what, i);
    }
  }

  /// An unsequenced message, one loop pass, and the board's answer to it.
  template <class M>
  pp::Status SendUnsequenced(const M& m) {
    uint8_t body[pp::kMaxBodySize];
    const auto n = pp::EncodeBody(m, body, sizeof(body));
    uint8_t packet[pp::kMaxPacketSize];
    pp::WriteHeader(pp::Header{pp::kProtocolVersion, static_cast<uint8_t>(M::kInfo.type), 0, 0},
                    packet);
    std::memcpy(packet + pp::kHeaderSize, body, n.value);
    // A delimiter first: raw bytes an earlier operation sent may have left a frame unfinished.
    uint8_t frame[1 + pp::kMaxFrameSize] = {pp::kFrameDelimiter};
    const auto f = pp::EncodeFrame(packet, pp::kHeaderSize + n.value, frame + 1, sizeof(frame) - 1);
    h.link.Inject(frame, 1 + f.value);
    Step(0);
    const auto answers = h.Drain();
    return BoardHarness::AnswerFor(answers, M::kInfo.type);
  }

  /// Close and Release of this session or another, repeated, during an update; a second host's
  /// Hello. Neither Close nor Release latches a fault; both leave every line safe at the next tick.
  void EndSession(Script& s) {
    Step(0);  // a tick due now runs first (host silence may end the session there, rightly)
    h.link.tx.clear();
    const uint8_t what = s.Byte();
    const bool foreign = (what & 0x10) != 0;
    // The session's own nonce: the harness's Hello's, or a raw Hello's a packet opened one with.
    const uint32_t own = h.board->session_nonce();
    const uint32_t tag = foreign ? own + 1 + s.Byte() : own;
    const bool was_open = h.board->session_open();
    const bool updating = update.engine().in_update_mode();
    const uint8_t slot = update.engine().inactive_slot();
    const uint32_t written = update.engine().Query(slot).written_bytes;
    const uint32_t latched = h.board->latched_faults();
    const uint32_t not_for_this =
        pp::FaultBit(pp::Fault::kHostSilence) | pp::FaultBit(pp::Fault::kEStopCommand);
    pp::Status answer = pp::Status::kOk;
    switch (what % 4) {
      case 0:
      case 3:  // a Close, or a Close and its repeat
        answer = SendUnsequenced(pp::Close{tag});
        if (was_open && !foreign) {
          if (answer != pp::Status::kOk)
            Fail("the session's Close was refused", static_cast<unsigned>(answer));
          if (h.board->session_open()) Fail("a Close left the session open", 0);
          if (updating && update.engine().in_update_mode())
            Fail("a Close left the board in update mode", 0);
          if (update.engine().Query(slot).written_bytes != written)
            Fail("a Close lost what the update had written", written);
          if (what % 4 == 3 && SendUnsequenced(pp::Close{tag}) != pp::Status::kNoSession)
            Fail("a repeated Close was not answered no_session", 0);
        }
        break;
      case 1:
        answer = SendUnsequenced(pp::Release{tag});
        if (was_open && !foreign) {
          if (answer != pp::Status::kOk)
            Fail("the session's Release was refused", static_cast<unsigned>(answer));
          if (!h.board->session_open()) Fail("a Release ended the session", 0);
        }
        break;
      default:  // a second host's Hello while this session is open
        answer = SendUnsequenced(pp::Hello{own + 1 + s.Byte(), s.Byte()});
        if (was_open && answer != pp::Status::kBusy)
          Fail("a second host's Hello was not refused busy", static_cast<unsigned>(answer));
        if (was_open && !h.board->session_open()) Fail("a second host's Hello ended a session", 0);
        h.link.tx.clear();
        return;
    }
    if (was_open && foreign) {
      if (answer != pp::Status::kNoSession)
        Fail("another session's Close or Release", static_cast<unsigned>(answer));
      if (!h.board->session_open()) Fail("another session's Close ended this one", 0);
      return;
    }
    if ((h.board->latched_faults() & ~latched & not_for_this) != 0)
      Fail("a Close or Release latched a fault", h.board->latched_faults());
    if (!was_open) return;
    h.clock.Advance(pc::Board::kTickUs);
    Step(0);
    h.link.tx.clear();
    CheckAllSafe("a line is not safe the tick after Close or Release");
  }

  void Operate(Script& s) {
    switch (s.Byte() % 11) {
      case 0:  // a new session
        h.Connect(s.Byte());
        break;
      case 1: {  // time passes
        const uint8_t plant = s.Byte();
        RunTicks(1 + s.Byte() % 100, plant, (plant & 0x80) != 0);
        break;
      }
      case 2: {  // a packet of any type, header and body
        const uint8_t type = s.Byte(), mode = s.Byte(), size = s.Byte();
        uint8_t body[pp::kMaxBodySize];
        for (uint8_t i = 0; i < size && i < sizeof(body); ++i) body[i] = s.Byte();
        if (mode % 2 == 0) {
          SendReliable(type, body, size);
        } else {
          SendPacket(type, s.Byte(), mode >> 1, body, size);
        }
        break;
      }
      case 3: {  // raw bytes: garbage, partial frames, delimiters
        uint8_t bytes[64];
        const uint8_t size = s.Byte() % sizeof(bytes);
        for (uint8_t i = 0; i < size; ++i) bytes[i] = s.Byte();
        h.link.Inject(bytes, size);
        Step(0);
        h.link.tx.clear();
        break;
      }
      case 4:
        SendEditedRecord(s);
        break;
      case 5: {  // a finger to a mode, then a target in its unit
        const pc::BoardConfig& c = h.board->config();
        if (c.finger_count == 0) break;
        const uint8_t finger = s.Byte() % c.finger_count;
        h.Send(pp::SetFingerMode{finger,
                                 s.Byte() % 2 ? pp::FingerMode::kRaw : pp::FingerMode::kTarget});
        pp::SetFingerTargets m{};
        m.generation = ++h.generation;
        m.entry_count = 1;
        m.entries[0] = {finger, pc::UnitOf(c.fingers[finger].kind), static_cast<int32_t>(s.Word())};
        h.Send(m);
        h.link.tx.clear();
        break;
      }
      case 6: {  // hardware: a sensor reading, the E-stop pin, a failing DAC, a silence
        const uint8_t what = s.Byte();
        const uint16_t value = s.Word();
        if (what % 4 == 0) h.adc.counts[(what >> 2) % palpa::hal::fake::kChannels] = value;
        if (what % 4 == 1) h.estop.level = (value & 1) != 0;
        if (what % 4 == 2) h.dac.fail = (value & 1) != 0;
        if (what % 4 == 3) h.clock.Advance(static_cast<uint64_t>(value) * 100);
        Step(0);
        h.link.tx.clear();
        break;
      }
      case 7:
        SendCompensator(s);
        break;
      case 8:
        update.Send(s, [this](uint8_t type, const uint8_t* body, size_t size) {
          SendReliable(type, body, size);
        });
        break;
      case 10:
        EndSession(s);
        break;
      default:  // clear faults, or go back to the factory configuration
        h.Send(pp::ClearFault{});
        if (s.Byte() % 4 == 0) h.Send(pp::FactoryReset{});
        h.link.tx.clear();
        break;
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Script s(data, size);
  Fuzzer f(pc::kBoardConfigs[s.Byte() % pc::kBoardConfigCount].name);  // byte 0: the layout
  while (!s.done()) f.Operate(s);
  f.RunTicks(20, 1, true);  // whatever the script left behind, a few more ticks under check
  return 0;
}
