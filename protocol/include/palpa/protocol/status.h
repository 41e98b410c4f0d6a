// One status-code enum shared by the wire (Nack bodies) and every API layer.
#pragma once

#include <cstdint>

namespace palpa::protocol {

/// Status codes. The numeric values are part of the wire protocol (Nack.status) and of the C ABI:
/// never renumber, only append. `kCount` is the number of codes, not a code.
enum class Status : uint16_t {
  kOk = 0,
  kNoSession = 1,          ///< no Hello yet in this boot of the board
  kUnsupported = 2,        ///< unknown message type or feature
  kBadLength = 3,          ///< body shorter or longer than its fields
  kOutOfRange = 4,         ///< a field outside its documented range or the configured limits
  kBadValue = 5,           ///< NaN/Inf, a non-monotone curve, an invalid enum or text
  kSeqGap = 6,             ///< reliable command ahead of the expected sequence number
  kWindowFull = 7,         ///< sender window or bytes-in-flight exhausted
  kFaulted = 8,            ///< refused while the board is in its safe state
  kConditionPersists = 9,  ///< ClearFault refused: the fault's cause is still present
  kCatalogMismatch = 10,   ///< peers were built from different message catalogs
  kCrcError = 11,          ///< frame or stored-record checksum wrong
  kVersionError = 12,      ///< header version is not 1
  kReservedFlags = 13,     ///< a reserved header flag bit was set
  kOverflow = 14,          ///< output buffer too small
  kTimeout = 15,           ///< no answer in time
  kOutcomeUnknown = 16,    ///< the board reset while the command was in flight
  kNotFound = 17,          ///< no such line, finger, device or file
  kIoError = 18,           ///< transport or flash error
  kUnavailable = 19,       ///< not possible in the current state (try later)
  kWrongMode = 20,         ///< e.g. a raw setpoint to a finger in target mode
  kStagedIncomplete = 21,  ///< staged configuration committed with parts missing
  kImageInvalid = 22,      ///< firmware image header, hash or kind wrong
  kRollbackRefused = 23,   ///< firmware image older than the anti-rollback counter
  kStale = 24,             ///< latest-wins message older than the one applied
  kBusy = 25,              ///< a long operation is in progress
  kDisconnected = 26,      ///< link lost
  kInvalidArgument = 27,   ///< host-side argument error (never from the board)
  kCount
};

inline constexpr const char* kStatusNames[] = {"ok",
                                               "no_session",
                                               "unsupported",
                                               "bad_length",
                                               "out_of_range",
                                               "bad_value",
                                               "seq_gap",
                                               "window_full",
                                               "faulted",
                                               "condition_persists",
                                               "catalog_mismatch",
                                               "crc_error",
                                               "version_error",
                                               "reserved_flags",
                                               "overflow",
                                               "timeout",
                                               "outcome_unknown",
                                               "not_found",
                                               "io_error",
                                               "unavailable",
                                               "wrong_mode",
                                               "staged_incomplete",
                                               "image_invalid",
                                               "rollback_refused",
                                               "stale",
                                               "busy",
                                               "disconnected",
                                               "invalid_argument"};
static_assert(sizeof(kStatusNames) / sizeof(kStatusNames[0]) ==
              static_cast<unsigned>(Status::kCount));

/// Enumerator names for the catalog hash and for text output (see catalog.h).
constexpr const char* const* EnumNames(Status) { return kStatusNames; }

/// Stable lower-case name of a status code, e.g. "out_of_range"; "unknown" outside the enum.
constexpr const char* StatusName(Status status) {
  const auto index = static_cast<unsigned>(status);
  return index < static_cast<unsigned>(Status::kCount) ? kStatusNames[index] : "unknown";
}

constexpr bool Ok(Status s) { return s == Status::kOk; }

/// A value or a status, for freestanding code (no exceptions, no heap).
template <typename T>
struct Result {
  Status status = Status::kOk;
  T value{};

  constexpr Result(T v) : value(static_cast<T&&>(v)) {}  // NOLINT: implicit, like pw::Result
  constexpr Result(Status s) : status(s) {}              // NOLINT
  constexpr bool ok() const { return status == Status::kOk; }
};

}  // namespace palpa::protocol
