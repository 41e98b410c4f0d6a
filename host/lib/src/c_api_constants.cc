// palpa.h's constants checked against the protocol's values at compile time: a status, line
// status bit or fault added on one side and not the other fails the build.
#include "palpa/c/palpa.h"
#include "palpa/protocol/enums.h"
#include "palpa/protocol/faults.h"
#include "palpa/protocol/status.h"

namespace pp = palpa::protocol;

static_assert(PALPA_STATUS_NO_SESSION == static_cast<int>(pp::Status::kNoSession));
static_assert(PALPA_STATUS_OUT_OF_RANGE == static_cast<int>(pp::Status::kOutOfRange));
static_assert(PALPA_STATUS_BAD_VALUE == static_cast<int>(pp::Status::kBadValue));
static_assert(PALPA_STATUS_FAULTED == static_cast<int>(pp::Status::kFaulted));
static_assert(PALPA_STATUS_CONDITION_PERSISTS == static_cast<int>(pp::Status::kConditionPersists));
static_assert(PALPA_STATUS_CATALOG_MISMATCH == static_cast<int>(pp::Status::kCatalogMismatch));
static_assert(PALPA_STATUS_TIMEOUT == static_cast<int>(pp::Status::kTimeout));
static_assert(PALPA_STATUS_OUTCOME_UNKNOWN == static_cast<int>(pp::Status::kOutcomeUnknown));
static_assert(PALPA_STATUS_NOT_FOUND == static_cast<int>(pp::Status::kNotFound));
static_assert(PALPA_STATUS_IO_ERROR == static_cast<int>(pp::Status::kIoError));
static_assert(PALPA_STATUS_UNAVAILABLE == static_cast<int>(pp::Status::kUnavailable));
static_assert(PALPA_STATUS_BUSY == static_cast<int>(pp::Status::kBusy));
static_assert(PALPA_STATUS_DISCONNECTED == static_cast<int>(pp::Status::kDisconnected));
static_assert(PALPA_STATUS_INVALID_ARGUMENT == static_cast<int>(pp::Status::kInvalidArgument));
static_assert(PALPA_STATUS_INVALID_ARGUMENT + 1 == static_cast<int>(pp::Status::kCount),
              "a status code without a PALPA_STATUS_ constant");
static_assert(PALPA_LINE_SAFE == pp::line_status::kSafe);
static_assert(PALPA_LINE_SLEWING == pp::line_status::kSlewing);
static_assert(PALPA_LINE_TRIM_CLAMPED == pp::line_status::kTrimClamped);
static_assert(PALPA_LINE_SATURATED == pp::line_status::kSaturated);
static_assert(PALPA_LINE_OPEN_LOOP == pp::line_status::kOpenLoop);
static_assert(PALPA_LINE_RAW == pp::line_status::kRaw);
static_assert(PALPA_LINE_SENSOR_FAULT == pp::line_status::kSensorFault);
static_assert(PALPA_FAULT_HOST_SILENCE == pp::FaultBit(pp::Fault::kHostSilence));
static_assert(PALPA_FAULT_OVER_LIMIT == pp::FaultBit(pp::Fault::kOverLimit));
static_assert(PALPA_FAULT_IMPLAUSIBLE_SENSOR == pp::FaultBit(pp::Fault::kImplausibleSensor));
static_assert(PALPA_FAULT_CONFIG_CRC == pp::FaultBit(pp::Fault::kConfigCrc));
static_assert(PALPA_FAULT_UNEXPECTED_RESET == pp::FaultBit(pp::Fault::kUnexpectedReset));
static_assert(PALPA_FAULT_LEAK == pp::FaultBit(pp::Fault::kLeak));
static_assert(PALPA_FAULT_ESTOP_COMMAND == pp::FaultBit(pp::Fault::kEStopCommand));
static_assert(PALPA_FAULT_ESTOP_PIN == pp::FaultBit(pp::Fault::kEStopPin));
static_assert(PALPA_FAULT_PUMP_RUN_TIME == pp::FaultBit(pp::Fault::kPumpRunTime));
static_assert(PALPA_FAULT_OUTPUT_WRITE == pp::FaultBit(pp::Fault::kOutputWrite));
static_assert(PALPA_FAULT_OUTPUT_WRITE << 1 == pp::FaultBit(pp::Fault::kCount),
              "a fault without a PALPA_FAULT_ constant");
static_assert(PALPA_FINGER_JAMMING == static_cast<int>(pp::FingerKind::kJamming));
