// Message codec: range checks, NaN/Inf, enums, text, lengths, overflow and dispatch, by field name.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "palpa/protocol/codec.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;

namespace {

template <class M>
std::vector<uint8_t> Body(const M& m) {
  std::vector<uint8_t> out(1024);
  const auto n = pp::EncodeBody(m, out.data(), out.size());
  CHECK(n.ok());
  out.resize(n.value);
  return out;
}

template <class M>
pp::FieldError DecodeError(const std::vector<uint8_t>& body) {
  M m{};
  pp::FieldError error;
  pp::DecodeBody(body.data(), body.size(), m, &error);
  return error;
}

template <class M>
pp::FieldError EncodeError(const M& m, size_t capacity = 1024) {
  std::vector<uint8_t> out(capacity);
  pp::FieldError error;
  pp::EncodeBody(m, out.data(), out.size(), &error);
  return error;
}

void CheckError(const pp::FieldError& e, pp::Status status, const char* field) {
  STRCMP_EQUAL(pp::StatusName(status), pp::StatusName(e.status));
  STRCMP_EQUAL(field, e.field);
}

pp::SetLineSetpoints TwoSetpoints() {
  pp::SetLineSetpoints m{};
  m.session = 0x0A0B0C0D;
  m.generation = 3;
  m.entry_count = 2;
  m.entries[0] = {1, 10000};
  m.entries[1] = {2, -5000};
  return m;
}

}  // namespace

TEST_GROUP(Codec){};

TEST(Codec, LittleEndianFieldByField) {
  const auto body = Body(TwoSetpoints());
  const std::vector<uint8_t> expected = {0x0D, 0x0C, 0x0B, 0x0A, 3, 0,    0,    0,    2,   1,
                                         0x10, 0x27, 0,    0,    2, 0x78, 0xEC, 0xFF, 0xFF};
  CHECK(body == expected);
}

TEST(Codec, RoundTripKeepsEveryField) {
  pp::ConfigureLine m{};
  m.line = 5;
  m.kind = pp::LineKind::kVacuum;
  m.dac_bits = 16;
  m.dac_signal = pp::SignalRange::kMilliamp4To20;
  m.command_min_pa = -100000;
  m.limit_min_pa = -100000;
  m.slew_pa_per_s = 123456;
  m.trim_kp = 0.125f;
  m.trim_ki_per_s = 3.5f;
  m.correction_count = 2;
  m.correction[1] = {-50000, -49000, -51000};
  const auto body = Body(m);
  pp::ConfigureLine back{};
  LONGS_EQUAL((int)pp::Status::kOk, (int)pp::DecodeBody(body.data(), body.size(), back));
  LONGS_EQUAL(5, back.line);
  CHECK(back.kind == pp::LineKind::kVacuum);
  CHECK(back.dac_signal == pp::SignalRange::kMilliamp4To20);
  LONGS_EQUAL(-100000, back.command_min_pa);
  LONGS_EQUAL(123456, back.slew_pa_per_s);
  DOUBLES_EQUAL(0.125, back.trim_kp, 0);
  DOUBLES_EQUAL(3.5, back.trim_ki_per_s, 0);
  LONGS_EQUAL(2, back.correction_count);
  LONGS_EQUAL(-51000, back.correction[1].falling_pa);
}

TEST(Codec, OutOfRangeSetpointIsRejectedOnBothSidesNamingTheField) {
  auto m = TwoSetpoints();
  m.entries[1].setpoint_pa = 100001;
  CheckError(EncodeError(m), pp::Status::kOutOfRange, "setpoint_pa");
  auto body = Body(TwoSetpoints());
  body[15] = 0xA1;  // -5000 → 0xFFFFECA1 ... make it 100001 = 0x000186A1
  body[16] = 0x86;
  body[17] = 0x01;
  body[18] = 0x00;
  const auto e = DecodeError<pp::SetLineSetpoints>(body);
  CheckError(e, pp::Status::kOutOfRange, "setpoint_pa");
  LONGS_EQUAL(15, e.offset);
}

TEST(Codec, LineIndexBeyondEightIsOutOfRange) {
  auto m = TwoSetpoints();
  m.entries[0].line = 8;
  CheckError(EncodeError(m), pp::Status::kOutOfRange, "line");
}

TEST(Codec, NanAndInfinityAreRejected) {
  pp::ConfigureLine m{};
  m.trim_kp = std::numeric_limits<float>::quiet_NaN();
  CheckError(EncodeError(m), pp::Status::kBadValue, "trim_kp");
  m.trim_kp = std::numeric_limits<float>::infinity();
  CheckError(EncodeError(m), pp::Status::kBadValue, "trim_kp");

  pp::ConfigureFinger f{};
  f.param_count = 1;
  auto body = Body(f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&body[body.size() - 4], &nan, 4);
  CheckError(DecodeError<pp::ConfigureFinger>(body), pp::Status::kBadValue, "params");
}

TEST(Codec, UnknownEnumeratorIsRejected) {
  auto body = Body(pp::SetFingerMode{1, pp::FingerMode::kRaw});
  body[1] = 2;
  CheckError(DecodeError<pp::SetFingerMode>(body), pp::Status::kBadValue, "mode");
  auto nack = Body(pp::Nack{1, 2, pp::Status::kFaulted, 0});
  nack[5] = 0xFF;
  nack[6] = 0x7F;
  CheckError(DecodeError<pp::Nack>(nack), pp::Status::kBadValue, "status");
}

TEST(Codec, FlagMustBeZeroOrOne) {
  pp::UpdateStatus st{};
  auto body = Body(st);
  body.back() = 2;
  CheckError(DecodeError<pp::UpdateStatus>(body), pp::Status::kBadValue, "in_update_mode");
}

TEST(Codec, TextMustBePrintableAndNulPadded) {
  pp::ConfigureFinger f{};
  f.actuator_serial[0] = 'A';
  f.actuator_serial[1] = '\n';
  CheckError(EncodeError(f), pp::Status::kBadValue, "actuator_serial");
  f.actuator_serial[1] = '\0';
  f.actuator_serial[2] = 'B';  // text after the terminator
  CheckError(EncodeError(f), pp::Status::kBadValue, "actuator_serial");
}

TEST(Codec, TextIsAlwaysTerminated) {
  // A name filling all 24 bytes has no NUL: a reader printing it as a C string would run into the
  // next field. Neither side lets one through, so every decoded text is a C string.
  pp::ConfigureBoard b{};
  b.config_name.fill('x');
  CheckError(EncodeError(b), pp::Status::kBadValue, "config_name");
  b.config_name[23] = '\0';  // 23 characters and the terminator: fine
  std::vector<uint8_t> body = Body(b);
  LONGS_EQUAL(0, static_cast<int>(DecodeError<pp::ConfigureBoard>(body).status));
  body[23] = 'x';  // the same body with the terminator overwritten, as another sender might
  CheckError(DecodeError<pp::ConfigureBoard>(body), pp::Status::kBadValue, "config_name");
  pp::HelloReply r{};
  r.rx_buffer_bytes = 1024;
  r.config_name.fill('y');
  CheckError(EncodeError(r), pp::Status::kBadValue, "config_name");
}

TEST(Codec, ShortBodyNamesTheFieldThatIsCutOff) {
  auto body = Body(TwoSetpoints());
  body.resize(12);
  CheckError(DecodeError<pp::SetLineSetpoints>(body), pp::Status::kBadLength, "setpoint_pa");
  CheckError(DecodeError<pp::SetLineSetpoints>({}), pp::Status::kBadLength, "session");
}

TEST(Codec, TrailingBytesAreRejected) {
  auto body = Body(pp::Heartbeat{7, 1});
  body.push_back(0);
  const auto e = DecodeError<pp::Heartbeat>(body);
  LONGS_EQUAL((int)pp::Status::kBadLength, (int)e.status);
  LONGS_EQUAL(8, e.offset);
}

TEST(Codec, ArrayCountBeyondCapacityIsRejected) {
  auto body = Body(TwoSetpoints());
  body[8] = 9;
  CheckError(DecodeError<pp::SetLineSetpoints>(body), pp::Status::kOutOfRange, "entries");
}

TEST(Codec, TelemetryNeedsOneSamplePerLinePerTick) {
  pp::Telemetry t{};
  t.tick_count = 2;
  t.line_count = 3;
  t.sample_count = 5;
  CheckError(EncodeError(t), pp::Status::kBadValue, "sample_count");
  t.sample_count = 6;
  const auto body = Body(t);
  pp::Telemetry back{};
  LONGS_EQUAL((int)pp::Status::kOk, (int)pp::DecodeBody(body.data(), body.size(), back));
}

TEST(Codec, FactoryResetNeedsItsConfirmationWord) {
  CheckError(EncodeError(pp::FactoryReset{0}), pp::Status::kOutOfRange, "confirm");
}

TEST(Codec, LargeCompensatorDoesNotFitOnePacketAndSaysSo) {
  pp::ConfigureFinger f{};
  f.param_count = pp::kMaxCompensatorParams;
  uint8_t packet[pp::kMaxPacketSize];
  pp::FieldError e;
  const auto n = pp::EncodePacket(f, 0, 0, packet, sizeof(packet), &e);
  LONGS_EQUAL((int)pp::Status::kOverflow, (int)n.status);
  STRCMP_EQUAL("params", e.field);
  CHECK(Body(f).size() > pp::kMaxBodySize);  // fine in a staged blob
}

TEST(Codec, DispatchCallsTheHandlerWithTheDecodedMessage) {
  uint8_t frame_bytes[pp::kMaxFrameSize];
  const auto n = pp::EncodeMessageFrame(TwoSetpoints(), 0, 0, frame_bytes, sizeof(frame_bytes));
  pp::OwningFrameDecoder decoder;
  pp::FrameDecoder::Event ev = pp::FrameDecoder::Event::kNone;
  for (size_t i = 0; i < n.value; ++i) ev = decoder.Process(frame_bytes[i]);
  CHECK(ev == pp::FrameDecoder::Event::kFrame);
  int calls = 0;
  const auto status = pp::DispatchFrame(decoder.frame(), [&](const auto& m, const pp::Header&) {
    using M = std::decay_t<decltype(m)>;
    if constexpr (std::is_same_v<M, pp::SetLineSetpoints>) {
      LONGS_EQUAL(-5000, m.entries[1].setpoint_pa);
      ++calls;
    }
  });
  LONGS_EQUAL((int)pp::Status::kOk, (int)status);
  LONGS_EQUAL(1, calls);
}

TEST(Codec, DispatchOfUnknownTypeIsUnsupported) {
  const uint8_t body[] = {0};
  pp::Frame frame{pp::Header{1, 0x7E, 0, 0}, body, 1};
  int calls = 0;
  pp::FieldError e;
  LONGS_EQUAL((int)pp::Status::kUnsupported,
              (int)pp::DispatchFrame(
                  frame, [&](const auto&, const pp::Header&) { ++calls; }, &e));
  LONGS_EQUAL(0, calls);
  CHECK(pp::FindMessageInfo(0x7E) == nullptr);
  STRCMP_EQUAL("SetLineSetpoints", pp::FindMessageInfo(0x21)->name);
}
