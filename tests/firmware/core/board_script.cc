// The board script's operations and the checks after every loop pass (see board_script.h).
#include "board_script.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "dac_pressure.h"
#include "palpa/core/board_configs.h"
#include "palpa/core/ceilings.h"
#include "palpa/protocol/config_records.h"
#include "palpa/protocol/crc32.h"

namespace palpa::testing {
namespace {

constexpr auto Fail = BoardFuzzFail;

bool IsConfigurationChange(uint8_t type) {
  using T = pp::MessageType;
  return type == static_cast<uint8_t>(T::kConfigureBoard) ||
         type == static_cast<uint8_t>(T::kConfigureLine) ||
         type == static_cast<uint8_t>(T::kConfigureFinger) ||
         type == static_cast<uint8_t>(T::kStagedCommit);
}

/// PALPA_BOARD_FUZZ_TRACE set: each answer and each run of ticks is printed (to read a finding).
const bool kTrace = std::getenv("PALPA_BOARD_FUZZ_TRACE") != nullptr;

}  // namespace

BoardScript::BoardScript(const uint8_t* script, size_t size, StepObserver observer)
    : s_(script, size),
      observer_(std::move(observer)),
      h_(pc::kBoardConfigs[s_.Byte() % pc::kBoardConfigCount].name, pp::ResetCause::kPowerOn,
         nullptr, &update_.engine()) {
  ran_with_ = h_.board->config();
  Remember();
  h_.after_step = [this](bool ticked, const uint8_t* sent, size_t n) {
    AfterStep(ticked, sent, n);
  };
}

void BoardScript::Run() {
  while (!s_.done()) Operate();
  RunTicks(20, 1, true);  // whatever the script left behind, a few more ticks under check
}

void BoardScript::Remember() {
  const pc::BoardConfig& c = h_.board->config();
  for (uint8_t i = 0; i < c.line_count; ++i) {
    last_line_[i] = c.lines[i];
    ever_configured_[i] = true;
  }
}

void BoardScript::CheckOutputs(const pc::BoardConfig& ran_with) {
  const pc::BoardConfig& live = h_.board->config();
  for (uint8_t i = 0; i < live.line_count; ++i) {
    if (!std::isfinite(h_.board->line_output(i).command_pa))
      Fail("commanded pressure not finite", i);
  }
  // A failing DAC keeps its last codes (the board latches output_write and the valves take the
  // pressure away); the codes are checked again once writes succeed.
  if (h_.dac.fail) return;
  for (uint8_t i = 0; i < ran_with.line_count; ++i) {
    const pp::ConfigureLine& c = ran_with.lines[i];
    const float pa = PressureOfCounts(c, h_.dac.counts[i]);
    const float lsb = PressurePerCount(c);
    const pc::Ceiling ceiling = pc::CeilingFor(c.kind);
    if (h_.dac.counts[i] > (1u << c.dac_bits) - 1u) Fail("DAC code beyond its resolution", i);
    if (pa < static_cast<float>(c.limit_min_pa) - lsb ||
        pa > static_cast<float>(c.limit_max_pa) + lsb)
      Fail("DAC code outside the line's limits", i);
    if (pa < static_cast<float>(ceiling.min_pa) - lsb ||
        pa > static_cast<float>(ceiling.max_pa) + lsb)
      Fail("DAC code outside the hard ceiling", i);
  }
  if (update_.engine().in_update_mode()) {  // the outputs are safe before anything is erased
    for (uint8_t i = 0; i < ran_with.line_count; ++i) {
      const pp::ConfigureLine& c = ran_with.lines[i];
      if (std::fabs(PressureOfCounts(c, h_.dac.counts[i]) - static_cast<float>(c.safe_pa)) >
          PressurePerCount(c))
        Fail("a line is not at its safe code during an update", i);
    }
  }
  for (uint8_t i = live.line_count; i < hal::fake::kChannels; ++i) {
    if (!ever_configured_[i]) continue;
    const pp::ConfigureLine& c = last_line_[i];
    const float pa = PressureOfCounts(c, h_.dac.counts[i]);
    if (std::fabs(pa - static_cast<float>(c.safe_pa)) > PressurePerCount(c))
      Fail("a dropped channel is not at its safe code", i);
  }
}

// Every loop pass, the harness's own (Send, Connect) included.
void BoardScript::AfterStep(bool ticked, const uint8_t* sent, size_t size) {
  if (ticked) CheckOutputs(ran_with_);
  ran_with_ = h_.board->config();
  Remember();
  if (observer_) observer_(h_, ticked, sent, size);
}

void BoardScript::Step(uint8_t plant) {
  h_.Step();
  if (plant % 3 == 1) h_.FollowModel();
  if (plant % 3 == 2) h_.FollowCommands();
}

void BoardScript::RunTicks(uint32_t ms, uint8_t plant, bool heartbeat) {
  for (uint32_t i = 0; i < ms; ++i) {
    h_.clock.Advance(pc::Board::kTickUs);
    if (heartbeat && i % 20 == 0) {
      uint8_t frame[pp::kMaxFrameSize];
      const auto n = pp::EncodeMessageFrame(pp::Heartbeat{h_.hello_nonce, ++h_.generation}, 0, 0,
                                            frame, sizeof(frame));
      h_.link.Inject(frame, n.value);
    }
    Step(plant);
    h_.link.tx.clear();
  }
  if (!kTrace) return;
  std::fprintf(stderr, "%u ms: safe %d, latched 0x%x, DAC", ms, h_.board->safe(),
               h_.board->latched_faults());
  for (uint8_t i = 0; i < h_.board->config().line_count; ++i)
    std::fprintf(stderr, " %u", h_.dac.counts[i]);
  std::fprintf(stderr, "\n");
}

/// Sends one packet and checks that a refused configuration change applied nothing.
void BoardScript::SendPacket(uint8_t type, uint8_t seq, uint8_t flags, const uint8_t* body,
                             size_t size) {
  if (size > pp::kMaxBodySize) size = pp::kMaxBodySize;
  uint8_t packet[pp::kMaxPacketSize];
  pp::WriteHeader(pp::Header{pp::kProtocolVersion, type, seq, flags}, packet);
  if (size > 0) std::memcpy(packet + pp::kHeaderSize, body, size);
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeFrame(packet, pp::kHeaderSize + size, frame, sizeof(frame));
  if (!n.ok()) Fail("a packet of at most the maximum size did not frame", type);
  const uint32_t before = pc::ConfigCrc(h_.board->config());
  h_.link.Inject(frame, n.value);
  Step(0);
  const pp::Status answer = BoardHarness::AnswerFor(h_.Drain(), static_cast<pp::MessageType>(type));
  const bool refused = answer != pp::Status::kOk && answer != pp::Status::kUnavailable;
  if (kTrace) std::fprintf(stderr, "type %u: %s\n", type, pp::StatusName(answer));
  if (IsConfigurationChange(type) && refused && pc::ConfigCrc(h_.board->config()) != before)
    Fail("a refused configuration changed the live one", type);
}

/// A reliable packet with the sequence number the board expects next.
void BoardScript::SendReliable(uint8_t type, const uint8_t* body, size_t size) {
  SendPacket(type, h_.next_seq++, pp::flags::kReliable, body, size);
}

/// One record of the live configuration's blob, edited at a few places, sent directly or as a
/// staged upload with a correct CRC, so edits reach validation rather than the CRC check.
void BoardScript::SendEditedRecord() {
  std::vector<uint8_t> blob(pc::kMaxConfigBlob);
  const auto n = pc::EncodeConfigBlob(h_.board->config(), blob.data(), blob.size());
  if (!n.ok()) Fail("the live configuration does not encode", 0);
  std::vector<std::pair<size_t, size_t>> records;  // offset, size (header included)
  pp::RecordReader reader(blob.data(), n.value);
  for (pp::Record r; !reader.done() && reader.Next(r) == pp::Status::kOk;) {
    const size_t size = pp::kRecordHeaderSize + r.size;
    records.emplace_back(static_cast<size_t>(r.body - blob.data()) - pp::kRecordHeaderSize, size);
  }
  const auto [offset, size] = records[s_.Byte() % records.size()];
  std::vector<uint8_t> record(blob.begin() + offset, blob.begin() + offset + size);
  const uint8_t edits = s_.Byte() % 8;
  constexpr size_t kHeader = pp::kRecordHeaderSize;
  for (uint8_t e = 0; e < edits && size > kHeader; ++e)
    record[kHeader + s_.Word() % (size - kHeader)] = s_.Byte();
  if (s_.Byte() % 2 == 0) return SendReliable(record[2], record.data() + kHeader, size - kHeader);
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
void BoardScript::SendCompensator() {
  const pc::BoardConfig& c = h_.board->config();
  if (c.finger_count == 0) return;
  pp::ConfigureFinger f = c.fingers[s_.Byte() % c.finger_count];
  FuzzInput& s = s_;
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
    for (uint8_t i = 0; i < size; ++i) p.push_back(s.FloatBits());
  }
  f.param_count = static_cast<uint8_t>(std::min(p.size(), f.params.size()));
  std::copy(p.begin(), p.begin() + f.param_count, f.params.begin());
  uint8_t body[pp::kMaxBodySize];
  const auto n = pp::EncodeBody(f, body, sizeof(body));
  if (n.ok()) SendReliable(static_cast<uint8_t>(pp::MessageType::kConfigureFinger), body, n.value);
}

/// A well-formed message of the session: raw setpoints for a line (across and beyond its
/// limits), an EStop, a configuration read, a save, loop statistics, diagnostics, the slots, or
/// a ClearFault of some bits.
void BoardScript::SendSessionMessage() {
  const pc::BoardConfig& c = h_.board->config();
  const uint8_t what = s_.Byte();
  switch (what % 8) {
    case 0: {
      if (c.line_count == 0) break;
      pp::SetLineSetpoints m{};
      m.generation = ++h_.generation;
      m.entry_count = 1;
      const uint8_t line = s_.Byte() % c.line_count;
      const pp::ConfigureLine& l = c.lines[line];
      // From the lower limit up, in steps of 1/200 of the span: to 127 % of it.
      const int64_t span = static_cast<int64_t>(l.limit_max_pa) - l.limit_min_pa;
      m.entries[0] = {line, static_cast<int32_t>(l.limit_min_pa + span * s_.Byte() / 200)};
      h_.Send(m);
      break;
    }
    case 1:
      h_.Send(pp::EStop{});
      break;
    case 2: {
      const auto section = static_cast<pp::ConfigSection>(s_.Byte() % 3);
      const uint8_t index = s_.Byte() % 10;
      h_.Send(pp::GetConfig{section, index, static_cast<uint16_t>(s_.Byte() * 2)});
      break;
    }
    case 3:
      h_.Send(pp::SaveConfig{});
      break;
    case 4:
      h_.Send(pp::GetLoopStats{});
      break;
    case 5:
      h_.Send(pp::GetDiagnostics{});
      break;
    case 6:
      h_.Send(pp::SlotsQuery{});
      break;
    default:
      h_.Send(pp::ClearFault{static_cast<uint32_t>(s_.Word())});
      break;
  }
  h_.link.tx.clear();
}

/// Every configured line at its safe code (a failing DAC keeps its old codes: not judged).
void BoardScript::CheckAllSafe(const char* what) {
  const pc::BoardConfig& c = h_.board->config();
  if (h_.dac.fail) return;
  for (uint8_t i = 0; i < c.line_count; ++i) {
    if (std::fabs(PressureOfCounts(c.lines[i], h_.dac.counts[i]) -
                  static_cast<float>(c.lines[i].safe_pa)) > PressurePerCount(c.lines[i]))
      Fail(what, i);
  }
}

/// An unsequenced message, one loop pass, and the board's answer to it.
template <class M>
pp::Status BoardScript::SendUnsequenced(const M& m) {
  uint8_t body[pp::kMaxBodySize];
  const auto n = pp::EncodeBody(m, body, sizeof(body));
  uint8_t packet[pp::kMaxPacketSize];
  pp::WriteHeader(pp::Header{pp::kProtocolVersion, static_cast<uint8_t>(M::kInfo.type), 0, 0},
                  packet);
  std::memcpy(packet + pp::kHeaderSize, body, n.value);
  // A delimiter first: raw bytes an earlier operation sent may have left a frame unfinished.
  uint8_t frame[1 + pp::kMaxFrameSize] = {pp::kFrameDelimiter};
  const auto f = pp::EncodeFrame(packet, pp::kHeaderSize + n.value, frame + 1, sizeof(frame) - 1);
  h_.link.Inject(frame, 1 + f.value);
  Step(0);
  const auto answers = h_.Drain();
  return BoardHarness::AnswerFor(answers, M::kInfo.type);
}

/// Close and Release of this session or another, repeated, during an update; a second host's
/// Hello. Neither Close nor Release latches a fault; both leave every line safe at the next tick.
void BoardScript::EndSession() {
  Step(0);  // a tick due now runs first (host silence may end the session there, rightly)
  h_.link.tx.clear();
  const uint8_t what = s_.Byte();
  const bool foreign = (what & 0x10) != 0;
  // The session's own nonce: the harness's Hello's, or a raw Hello's a packet opened one with.
  const uint32_t own = h_.board->session_nonce();
  const uint32_t tag = foreign ? own + 1 + s_.Byte() : own;
  const bool was_open = h_.board->session_open();
  const bool updating = update_.engine().in_update_mode();
  const uint8_t slot = update_.engine().inactive_slot();
  const uint32_t written = update_.engine().Query(slot).written_bytes;
  const uint32_t latched = h_.board->latched_faults();
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
        if (h_.board->session_open()) Fail("a Close left the session open", 0);
        if (updating && update_.engine().in_update_mode())
          Fail("a Close left the board in update mode", 0);
        if (update_.engine().Query(slot).written_bytes != written)
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
        if (!h_.board->session_open()) Fail("a Release ended the session", 0);
      }
      break;
    default:  // a second host's Hello while this session is open
      answer = SendUnsequenced(pp::Hello{own + 1 + s_.Byte(), s_.Byte()});
      if (was_open && answer != pp::Status::kBusy)
        Fail("a second host's Hello was not refused busy", static_cast<unsigned>(answer));
      if (was_open && !h_.board->session_open()) Fail("a second host's Hello ended a session", 0);
      h_.link.tx.clear();
      return;
  }
  if (was_open && foreign) {
    if (answer != pp::Status::kNoSession)
      Fail("another session's Close or Release", static_cast<unsigned>(answer));
    if (!h_.board->session_open()) Fail("another session's Close ended this one", 0);
    return;
  }
  if ((h_.board->latched_faults() & ~latched & not_for_this) != 0)
    Fail("a Close or Release latched a fault", h_.board->latched_faults());
  if (!was_open) return;
  h_.clock.Advance(pc::Board::kTickUs);
  Step(0);
  h_.link.tx.clear();
  CheckAllSafe("a line is not safe the tick after Close or Release");
}

void BoardScript::Operate() {
  switch (s_.Byte() % kOperations) {
    case 0:  // a new session
      h_.Connect(s_.Byte());
      break;
    case 1: {  // time passes
      const uint8_t plant = s_.Byte();
      RunTicks(1 + s_.Byte() % 100, plant, (plant & 0x80) != 0);
      break;
    }
    case 2: {  // a packet of any type, header and body
      const uint8_t type = s_.Byte(), mode = s_.Byte(), size = s_.Byte();
      uint8_t body[pp::kMaxBodySize];
      for (uint8_t i = 0; i < size && i < sizeof(body); ++i) body[i] = s_.Byte();
      if (mode % 2 == 0) {
        SendReliable(type, body, size);
      } else {
        SendPacket(type, s_.Byte(), mode >> 1, body, size);
      }
      break;
    }
    case 3: {  // raw bytes: garbage, partial frames, delimiters
      uint8_t bytes[64];
      const uint8_t size = s_.Byte() % sizeof(bytes);
      for (uint8_t i = 0; i < size; ++i) bytes[i] = s_.Byte();
      h_.link.Inject(bytes, size);
      Step(0);
      h_.link.tx.clear();
      break;
    }
    case 4:
      SendEditedRecord();
      break;
    case 5: {  // a finger to a mode, then a target in its unit
      const pc::BoardConfig& c = h_.board->config();
      if (c.finger_count == 0) break;
      const uint8_t finger = s_.Byte() % c.finger_count;
      h_.Send(pp::SetFingerMode{finger,
                                s_.Byte() % 2 ? pp::FingerMode::kRaw : pp::FingerMode::kTarget});
      pp::SetFingerTargets m{};
      m.generation = ++h_.generation;
      m.entry_count = 1;
      m.entries[0] = {finger, pc::UnitOf(c.fingers[finger].kind), static_cast<int32_t>(s_.Word())};
      h_.Send(m);
      h_.link.tx.clear();
      break;
    }
    case 6: {  // hardware: a sensor reading, the E-stop pin, a failing DAC, a silence
      const uint8_t what = s_.Byte();
      const uint16_t value = s_.Word();
      if (what % 4 == 0) h_.adc.counts[(what >> 2) % hal::fake::kChannels] = value;
      if (what % 4 == 1) h_.estop.level = (value & 1) != 0;
      if (what % 4 == 2) h_.dac.fail = (value & 1) != 0;
      if (what % 4 == 3) h_.clock.Advance(static_cast<uint64_t>(value) * 100);
      Step(0);
      h_.link.tx.clear();
      break;
    }
    case 7:
      SendCompensator();
      break;
    case 8:
      update_.Send(s_, [this](uint8_t type, const uint8_t* body, size_t size) {
        SendReliable(type, body, size);
      });
      break;
    case 10:
      EndSession();
      break;
    case 11:
      SendSessionMessage();
      break;
    default:  // clear faults, or go back to the factory configuration
      h_.Send(pp::ClearFault{});
      if (s_.Byte() % 4 == 0) h_.Send(pp::FactoryReset{});
      h_.link.tx.clear();
      break;
  }
}

}  // namespace palpa::testing
