// Analogue outputs and inputs through a Modbus TCP or RTU I/O module (libmodbus as the client).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "palpa/hal/analog_input.h"
#include "palpa/hal/analog_output.h"
#include "palpa/hal/linux/modbus_aio_config.h"
#include "palpa/hal/linux/opened.h"

typedef struct _modbus modbus_t;

namespace palpa::hal::linux_aio {

/// The IPv4 address a Modbus TCP module's host names (a name or a literal), in its one numeric
/// form: libmodbus's modbus_new_tcp takes an IPv4 literal only. Of several addresses, the first
/// getaddrinfo gives. kNotFound naming the host when it does not resolve.
Opened<std::string> ResolveModuleHost(const std::string& host);

/// One module: its outputs and inputs as the HAL's AnalogOutput and AnalogInput. A failed or late
/// transfer is never hidden: WriteAll names a failed channel (the core latches an output-write
/// fault) and ReadAll gives kConversionFailed for every channel (an implausible-sensor fault),
/// never the last good value. After a failure the next call reconnects.
class ModbusAioModule {
 public:
  /// Connects (a TCP module's host resolved by ResolveModuleHost), arms the module's watchdog
  /// (time, retriggered by writes only, outputs to zero on a timeout), reads those settings back,
  /// and writes every output's safe value (zero volts). A failure names the module, the register
  /// and the reason: kNotFound (a host that does not resolve), kIoError or kTimeout (the module
  /// did not answer), kUnsupported (a register holds another value: not this module class).
  static Opened<std::unique_ptr<ModbusAioModule>> Open(const ModbusAioConfig& config);
  ~ModbusAioModule();
  ModbusAioModule(const ModbusAioModule&) = delete;
  ModbusAioModule& operator=(const ModbusAioModule&) = delete;

  AnalogOutput& outputs() { return outputs_; }
  AnalogInput& inputs() { return inputs_; }

  /// Writes the safe value (zero volts) to every output: on a clean exit and before a fault hold.
  protocol::Status WriteSafe();

  /// The last transfer's failure, e.g. "tcp:10.0.0.5:502 unit 1: reading inputs 0x0000+8:
  /// Connection timed out"; empty once a transfer succeeds again.
  const std::string& last_error() const { return last_error_; }
  uint32_t failures() const { return failures_; }  ///< transfers failed since Open

  /// The register code for `counts` of an output, and the counts of an input's code.
  uint16_t OutputCode(uint32_t counts) const;
  uint32_t InputCounts(uint16_t code) const;

 private:
  class Outputs final : public AnalogOutput {
   public:
    explicit Outputs(ModbusAioModule& m) : m_(m) {}

   private:
    protocol::Status DoWrite(uint8_t channel, uint32_t counts) override;
    uint8_t DoWriteAll(const uint32_t* codes, uint8_t count) override;
    AnalogOutputSpec DoSpec(uint8_t channel) const override;
    ModbusAioModule& m_;
  };
  class Inputs final : public AnalogInput {
   public:
    explicit Inputs(ModbusAioModule& m) : m_(m) {}

   private:
    Result<uint32_t> DoRead(uint8_t channel) override;
    void DoReadAll(uint32_t* counts, uint8_t count) override;
    uint8_t DoBits() const override { return m_.config_.input_bits; }
    ModbusAioModule& m_;
  };

  explicit ModbusAioModule(const ModbusAioConfig& config);
  protocol::Status Connect();
  protocol::Status WriteCodes(uint16_t first, const uint16_t* codes, int count);
  protocol::Status Fail(const std::string& what);
  void Succeeded() { last_error_.clear(); }

  ModbusAioConfig config_;
  modbus_t* ctx_ = nullptr;
  bool connected_ = false;
  std::string last_error_;
  uint32_t failures_ = 0;
  Outputs outputs_{*this};
  Inputs inputs_{*this};
};

}  // namespace palpa::hal::linux_aio
