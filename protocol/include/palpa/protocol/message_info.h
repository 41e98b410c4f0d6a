// Message type ids and how each message travels (sender, delivery rule, bootstrap membership).
#pragma once

#include <cstdint>

namespace palpa::protocol {

/// Type ids. 0x01-0x1F: the bootstrap set, frozen across versions and spoken by the
/// bootloader. 0x20 and up: the versioned catalog, covered by the catalog hash.
enum class MessageType : uint8_t {
  kHello = 0x01,
  kHelloReply = 0x02,
  kAck = 0x03,
  kNack = 0x04,
  kEStop = 0x05,
  kUpdateEnter = 0x10,
  kUpdateErase = 0x11,
  kUpdateWrite = 0x12,
  kUpdateQuery = 0x13,
  kUpdateStatus = 0x14,
  kUpdateActivate = 0x15,
  kUpdateReboot = 0x16,
  kUpdateConfirm = 0x17,
  kSlotsQuery = 0x18,
  kSlotsReport = 0x19,
  kHeartbeat = 0x20,
  kSetLineSetpoints = 0x21,
  kSetFingerTargets = 0x22,
  kSetFingerMode = 0x23,
  kClose = 0x24,
  kRelease = 0x25,
  kConfigureLine = 0x30,
  kConfigureFinger = 0x31,
  kConfigureBoard = 0x32,
  kStagedBegin = 0x33,
  kStagedPart = 0x34,
  kStagedCommit = 0x35,
  kGetConfig = 0x36,
  kConfigReport = 0x37,
  kSaveConfig = 0x38,
  kFactoryReset = 0x39,
  kClearFault = 0x3A,
  kTelemetry = 0x40,
  kGetLoopStats = 0x41,
  kLoopStats = 0x42,
  kGetDiagnostics = 0x43,
  kDiagnostics = 0x44,
};

inline constexpr uint8_t kFirstCatalogType = 0x20;

constexpr bool IsBootstrap(uint8_t type) { return type < kFirstCatalogType; }

enum class Sender : uint8_t { kHost, kBoard };

/// How a message is delivered.
enum class Delivery : uint8_t {
  kUnsequenced,  ///< host→board, outside the window, acted on at once (Hello, EStop, Close)
  kReliable,     ///< host→board, go-back-N window, applied exactly once in order
  kStream,       ///< host→board, latest-wins by u32 generation
  kResponse,     ///< board→host, answers one host message
  kBoardStream,  ///< board→host, periodic (telemetry)
};

inline constexpr const char* const kDeliveryNames[] = {"unsequenced", "reliable", "stream",
                                                       "response", "board-stream"};

struct MessageInfo {
  MessageType type;
  const char* name;
  Sender sender;
  Delivery delivery;
  const char* summary;
};

}  // namespace palpa::protocol
