// The Modbus analogue I/O module: watchdog and safe values at start, one transfer per scan.
#include "palpa/hal/linux/modbus_aio.h"

#include <arpa/inet.h>
#include <modbus.h>
#include <netdb.h>
#include <netinet/in.h>

#include <cerrno>
#include <cstdio>

namespace palpa::hal::linux_aio {

using protocol::Status;

namespace {

constexpr uint16_t kWriteTelegramWatchdog = 0;  // reads alone do not keep the outputs alive
constexpr uint16_t kFallbackToZero = 0;
constexpr int kMaxWords = 2 * 16;

std::string Hex(uint16_t address) {
  char text[8];
  std::snprintf(text, sizeof(text), "0x%04X", address);
  return text;
}

}  // namespace

Opened<std::string> ResolveModuleHost(const std::string& host) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int rc = getaddrinfo(host.c_str(), nullptr, &hints, &found);
  char text[INET_ADDRSTRLEN] = {};
  if (rc == 0 && found != nullptr) {
    const auto* in = reinterpret_cast<const sockaddr_in*>(found->ai_addr);
    inet_ntop(AF_INET, &in->sin_addr, text, sizeof(text));
  }
  if (found != nullptr) freeaddrinfo(found);
  if (text[0] == '\0') {
    return {Status::kNotFound, "'" + host + "' does not resolve to an IPv4 address (" +
                                   (rc != 0 ? gai_strerror(rc) : "no address") + ")"};
  }
  return std::string(text);
}

ModbusAioModule::ModbusAioModule(const ModbusAioConfig& config) : config_(config) {}

ModbusAioModule::~ModbusAioModule() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
}

Opened<std::unique_ptr<ModbusAioModule>> ModbusAioModule::Open(const ModbusAioConfig& config) {
  std::unique_ptr<ModbusAioModule> m(new ModbusAioModule(config));
  if (config.tcp) {
    // libmodbus (3.1.6) takes an IPv4 literal only: a name is resolved here; messages keep it.
    const Opened<std::string> address = ResolveModuleHost(config.host);
    if (!address.ok()) return {address.status, config.Describe() + ": " + address.message};
    m->ctx_ = modbus_new_tcp(address.value.c_str(), config.port);
  } else {
    m->ctx_ = modbus_new_rtu(config.host.c_str(), config.baud, config.parity, config.data_bits,
                             config.stop_bits);
  }
  if (m->ctx_ == nullptr)
    return {Status::kBadValue, config.Describe() + ": " + modbus_strerror(errno)};
  modbus_set_slave(m->ctx_, config.unit);
  const auto ms = static_cast<uint32_t>(config.response_timeout_ms);
  modbus_set_response_timeout(m->ctx_, ms / 1000, (ms % 1000) * 1000);
  modbus_set_byte_timeout(m->ctx_, ms / 1000, (ms % 1000) * 1000);
  const ModuleClass& c = *config.module;
  // The watchdog first: the first write to the process image starts it, and that first write is
  // the safe values, so from then on a silent controller leaves the outputs at zero.
  const uint16_t settings[][2] = {{c.watchdog_time_at, static_cast<uint16_t>(config.watchdog_ms)},
                                  {c.watchdog_type_at, kWriteTelegramWatchdog},
                                  {c.fallback_at, kFallbackToZero}};
  for (const auto& [address, value] : settings) {
    if (const Status s = m->WriteCodes(address, &value, 1); s != Status::kOk)
      return {s, m->last_error_};
    uint16_t back = 0;
    if (modbus_read_registers(m->ctx_, address, 1, &back) != 1) {
      const Status s = m->Fail("reading back " + Hex(address));
      return {s, m->last_error_};
    }
    if (back != value) {
      return {Status::kUnsupported, config.Describe() + ": register " + Hex(address) + " holds " +
                                        std::to_string(back) + " after writing " +
                                        std::to_string(value) + " (not a " + c.name + "?)"};
    }
  }
  if (const Status s = m->WriteSafe(); s != Status::kOk) return {s, m->last_error_};
  return m;
}

Status ModbusAioModule::Connect() {
  if (connected_) return Status::kOk;
  if (modbus_connect(ctx_) != 0) return Fail("connecting");
  connected_ = true;
  return Status::kOk;
}

Status ModbusAioModule::Fail(const std::string& what) {
  const int why = errno;
  last_error_ = config_.Describe() + ": " + what + ": " + modbus_strerror(why);
  ++failures_;
  // A late answer may still arrive: drop the connection so it is never taken for the next one.
  modbus_close(ctx_);
  connected_ = false;
  return why == ETIMEDOUT ? Status::kTimeout : Status::kIoError;
}

Status ModbusAioModule::WriteCodes(uint16_t first, const uint16_t* codes, int count) {
  if (const Status s = Connect(); s != Status::kOk) return s;
  const int written = count == 1 ? modbus_write_register(ctx_, first, codes[0])
                                 : modbus_write_registers(ctx_, first, count, codes);
  if (written != count) {
    return Fail("writing " + std::to_string(count) + " at " + Hex(first));
  }
  Succeeded();
  return Status::kOk;
}

Status ModbusAioModule::WriteSafe() {
  uint16_t zeros[16] = {};
  return config_.output_count == 0
             ? Status::kOk
             : WriteCodes(config_.module->outputs_at, zeros, config_.output_count);
}

uint16_t ModbusAioModule::OutputCode(uint32_t counts) const {
  const uint32_t max = (1u << config_.output_bits) - 1u;
  return static_cast<uint16_t>((counts * config_.module->full_scale_code + max / 2) / max);
}

uint32_t ModbusAioModule::InputCounts(uint16_t code) const {
  const uint32_t max = (1u << config_.input_bits) - 1u, full = config_.module->full_scale_code;
  if (code > full) return AnalogInput::kConversionFailed;  // negative or over range: no reading
  return (code * max + full / 2) / full;
}

Status ModbusAioModule::Outputs::DoWrite(uint8_t channel, uint32_t counts) {
  if (channel >= m_.config_.output_count) return Status::kNotFound;
  if (counts > DoSpec(channel).max_counts()) return Status::kOutOfRange;
  const uint16_t code = m_.OutputCode(counts);
  return m_.WriteCodes(static_cast<uint16_t>(m_.config_.module->outputs_at + channel), &code, 1);
}

uint8_t ModbusAioModule::Outputs::DoWriteAll(const uint32_t* codes, uint8_t count) {
  // One transfer for every channel: the module never holds half a tick's outputs.
  if (count > m_.config_.output_count) return m_.config_.output_count;
  uint16_t words[16];
  for (uint8_t i = 0; i < count; ++i) {
    if (codes[i] > DoSpec(i).max_counts()) return i;
    words[i] = m_.OutputCode(codes[i]);
  }
  if (count == 0) return kAllWritten;
  return m_.WriteCodes(m_.config_.module->outputs_at, words, count) == Status::kOk ? kAllWritten
                                                                                   : 0;
}

AnalogOutputSpec ModbusAioModule::Outputs::DoSpec(uint8_t) const {
  return {m_.config_.output_bits, SignalRange::kVolt0To10};
}

Result<uint32_t> ModbusAioModule::Inputs::DoRead(uint8_t channel) {
  uint32_t counts[16];
  if (channel >= m_.config_.input_count) return Status::kNotFound;
  DoReadAll(counts, static_cast<uint8_t>(channel + 1));
  if (counts[channel] == kConversionFailed) return Status::kIoError;
  return counts[channel];
}

void ModbusAioModule::Inputs::DoReadAll(uint32_t* counts, uint8_t count) {
  for (uint8_t i = 0; i < count; ++i) counts[i] = kConversionFailed;
  const uint8_t have = count < m_.config_.input_count ? count : m_.config_.input_count;
  if (have == 0) return;
  const int words = have * m_.config_.input_words;
  uint16_t image[kMaxWords];
  if (m_.Connect() != Status::kOk) return;
  if (modbus_read_input_registers(m_.ctx_, m_.config_.module->inputs_at, words, image) != words) {
    m_.Fail("reading " + std::to_string(words) + " inputs at " + Hex(m_.config_.module->inputs_at));
    return;
  }
  m_.Succeeded();
  const int words_per = m_.config_.input_words;
  for (uint8_t i = 0; i < have; ++i) {
    const uint16_t* channel = image + i * words_per;
    // With the status word, a terminal that says its value is invalid (wire break, range) wins.
    const bool invalid = words_per == 2 && (channel[0] & m_.config_.module->input_invalid) != 0;
    counts[i] = invalid ? kConversionFailed : m_.InputCounts(channel[words_per - 1]);
  }
}

}  // namespace palpa::hal::linux_aio
