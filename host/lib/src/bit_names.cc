// Line status and fault bits in words.
#include "palpa/host/bit_names.h"

#include "palpa/host/fault_text.h"
#include "palpa/protocol/enums.h"
#include "palpa/protocol/faults.h"

namespace palpa::host {

namespace pp = palpa::protocol;

std::vector<std::string> LineStatusList(uint8_t status) {
  std::vector<std::string> names;
  constexpr size_t known = sizeof(pp::kLineStatusNames) / sizeof(pp::kLineStatusNames[0]);
  for (uint8_t bit = 0; bit < 8; ++bit) {
    if ((status & (1u << bit)) == 0) continue;
    names.push_back(bit < known ? pp::kLineStatusNames[bit] : "bit_" + std::to_string(bit));
  }
  return names;
}

std::vector<std::string> FaultList(uint32_t bitmap) {
  std::vector<std::string> names;
  for (uint8_t f = 0; f < 32; ++f) {
    if ((bitmap & (1u << f)) != 0) names.push_back(FaultName(f));
  }
  return names;
}

uint32_t FaultBitmap(const std::vector<std::string>& names) {
  uint32_t bitmap = 0;
  for (const std::string& name : names) {
    for (uint8_t f = 0; f < 32; ++f) {
      if (name == FaultName(f)) bitmap |= 1u << f;
    }
  }
  return bitmap;
}

std::string JoinNames(const std::vector<std::string>& names, const char* separator,
                      const char* none) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : separator) + name;
  return text.empty() ? none : text;
}

std::string FaultDetail(uint8_t fault, int32_t detail, int number_from) {
  switch (static_cast<pp::Fault>(fault)) {
    case pp::Fault::kHostSilence:
      return std::to_string(detail) + " ms without the host";
    case pp::Fault::kOverLimit:
      return "reading " + std::to_string(detail) + " Pa";
    case pp::Fault::kImplausibleSensor:
    case pp::Fault::kLeak:
      return "line " + std::to_string(detail + number_from);
    case pp::Fault::kOutputWrite: {
      // Bits 0-7 the line (kNoLine: an output every line shares), 8-15 the output's kind.
      const uint32_t kind = static_cast<uint32_t>(detail) >> 8, line = detail & 0xFFu;
      if (detail < 0 || kind >= static_cast<uint32_t>(pp::OutputKind::kCount)) return "";
      const std::string name = pp::kOutputKindNames[kind];
      if (line == pp::kNoLine) return name;
      return "line " + std::to_string(static_cast<int>(line) + number_from) + "'s " + name;
    }
    case pp::Fault::kPumpRunTime:
      return "pump on for " + std::to_string(detail) + " s";
    case pp::Fault::kUnexpectedReset:
      return detail >= 0 && detail < static_cast<int32_t>(pp::ResetCause::kCount)
                 ? std::string("after ") + pp::kResetCauseNames[detail]
                 : "";
    default:
      return "";
  }
}

}  // namespace palpa::host
