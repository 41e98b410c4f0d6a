// Board test harness on fakes.
#include "board_harness.h"

namespace palpa::testing {

BoardHarness::BoardHarness(const char* config_name, pp::ResetCause reset_cause,
                           fake::SimulatedNorFlash* shared_flash, pc::UpdateEngine* update)
    : flash(shared_flash != nullptr ? shared_flash : &own_flash) {
  const pc::BoardConfig* config = pc::FindBoardConfig(config_name);
  pc::BoardIo io{clock, dac, &adc, supply, dump, pump, &estop, link, flash, 0, update};
  io.line_vents = &vents;
  pc::BoardIdentity id;
  id.boot_nonce = 0xB0075EED;
  id.reset_cause = reset_cause;
  id.plant_simulated = true;
  clock.now_us = 1000000;
  board = std::make_unique<pc::Board>(*config, io, id);
  board->Start();
  for (uint8_t i = 0; i < config->line_count; ++i) SetMeasured(i, 0);
}

pp::HelloReply BoardHarness::Connect(uint8_t initial_seq) {
  // The session's host closes it, as hosts do, so a new one can open (no Close: busy).
  if (board->session_open()) Send(pp::Close{hello_nonce});
  next_seq = initial_seq;
  Send(pp::Hello{++hello_nonce, initial_seq});  // a new nonce: a new session
  for (const BoardFrame& f : Drain()) {
    if (f.Is<pp::HelloReply>()) return f.As<pp::HelloReply>();
  }
  return {};
}

void BoardHarness::Run(uint32_t ms, bool heartbeat) {
  for (uint32_t i = 0; i < ms; ++i) {
    clock.Advance(pc::Board::kTickUs);
    if (heartbeat && i % 20 == 0) Send(pp::Heartbeat{hello_nonce, ++generation}, false);
    Step();
  }
}

bool BoardHarness::AllLinesSafe() const {
  for (uint8_t i = 0; i < board->config().line_count; ++i) {
    if (dac.counts[i] != 0) return false;
  }
  return true;
}

bool BoardHarness::Step() {
  const size_t before = link.tx.size();
  const bool ticked = board->Step();
  if (after_step) after_step(ticked, link.tx.data() + before, link.tx.size() - before);
  return ticked;
}

std::vector<BoardFrame> BoardHarness::Drain() {
  std::vector<BoardFrame> frames;
  for (uint8_t b : link.tx) {
    if (decoder.Process(b) != pp::FrameDecoder::Event::kFrame) continue;
    const pp::Frame& f = decoder.frame();
    frames.push_back(BoardFrame{f.header, std::vector<uint8_t>(f.body, f.body + f.body_size)});
  }
  link.tx.clear();
  return frames;
}

pp::Status BoardHarness::AnswerFor(const std::vector<BoardFrame>& frames, pp::MessageType type) {
  pp::Status status = pp::Status::kUnavailable;
  for (const BoardFrame& f : frames) {
    if (f.Is<pp::Ack>() && f.As<pp::Ack>().acked_type == static_cast<uint8_t>(type))
      status = pp::Status::kOk;
    if (f.Is<pp::Nack>() && f.As<pp::Nack>().refused_type == static_cast<uint8_t>(type))
      status = f.As<pp::Nack>().status;
  }
  return status;
}

void BoardHarness::SetMeasured(uint8_t line, float pa) {
  const pp::ConfigureLine& c = board->config().lines[line];
  const float fraction = (pa - static_cast<float>(c.sensor_min_pa)) /
                         static_cast<float>(c.sensor_max_pa - c.sensor_min_pa);
  const float counts = static_cast<float>(c.sensor_counts_min) +
                       fraction * static_cast<float>(c.sensor_counts_max - c.sensor_counts_min) +
                       0.5f;
  // An ADC saturates at its ends (a pressure far beyond the sensor's span, or none: NaN).
  const float full_scale = static_cast<float>((1u << c.adc_bits) - 1u);
  adc.counts[line] =
      counts >= 0 ? static_cast<uint32_t>(counts < full_scale ? counts : full_scale) : 0;
}

float BoardHarness::CommandedPa(uint8_t line) const { return board->line_output(line).command_pa; }

void BoardHarness::FollowModel() {
  for (uint8_t i = 0; i < board->config().line_count; ++i)
    SetMeasured(i, board->line_state(i).reference_pa);
}

void BoardHarness::FollowCommands() {
  for (uint8_t i = 0; i < board->config().line_count; ++i) SetMeasured(i, CommandedPa(i));
}

}  // namespace palpa::testing
