// Prints the message reference of docs/protocol.md from the catalog itself, or checks that the
// document still matches it (--check FILE), so the documentation cannot drift from the code.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

#include "palpa/protocol/codec.h"
#include "palpa/protocol/faults.h"

namespace pp = palpa::protocol;

namespace {

template <typename T>
const char* WireType() {
  if constexpr (std::is_same_v<T, float>) return "f32";
  if constexpr (std::is_same_v<T, uint8_t>) return "u8";
  if constexpr (std::is_same_v<T, uint16_t>) return "u16";
  if constexpr (std::is_same_v<T, uint32_t>) return "u32";
  if constexpr (std::is_same_v<T, uint64_t>) return "u64";
  if constexpr (std::is_same_v<T, int32_t>) return "i32";
  return "?";
}

std::string Unit(const std::string& name) {
  auto ends = [&](const char* s) {
    const std::string suffix(s);
    return name.size() > suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends("_pa_per_s")) return "Pa/s";
  if (ends("_pa")) return "Pa";
  if (ends("_us")) return "µs";
  if (ends("_ms")) return "ms";
  if (ends("_per_s")) return "1/s";
  if (ends("_bytes")) return "bytes";
  return "";
}

template <typename T>
std::string Number(T v) {
  std::ostringstream s;
  if constexpr (std::is_same_v<T, float>) {
    s << v;
  } else {
    s << +v;
  }
  return s.str();
}

/// One table row per field, nested fields as parent[].child.
class Describer {
 public:
  explicit Describer(std::string prefix = "") : prefix_(std::move(prefix)) {}
  std::string rows;
  size_t min_size = 0;
  size_t max_size = 0;

  template <typename T>
  void Field(const char* name, const T& v) {
    Field(name, v, std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max());
  }
  template <typename T>
  void Field(const char* name, const T&, pp::Bound<T> lo, pp::Bound<T> hi) {
    std::string range;
    const bool full = lo == std::numeric_limits<T>::lowest() && hi == std::numeric_limits<T>::max();
    if (std::is_same_v<T, float>)
      range = full ? "finite" : "finite, " + Number(lo) + " … " + Number(hi);
    else if (!full)
      range = lo == hi ? "= " + Number(lo) : Number(lo) + " … " + Number(hi);
    Row(name, WireType<T>(), range);
    Add(sizeof(T), sizeof(T));
  }
  void Flag(const char* name, const bool&) {
    Row(name, "u8", "0 or 1");
    Add(1, 1);
  }
  template <typename E>
  void Enum(const char* name, const E&) {
    std::string values;
    const char* const* names = EnumNames(E{});
    for (uint64_t i = 0; i < pp::EnumCount<E>(); ++i) {
      values += (i ? ", " : "") + std::to_string(i) + " " + names[i];
    }
    Row(name, sizeof(E) == 1 ? "u8 enum" : "u16 enum", values);
    Add(sizeof(E), sizeof(E));
  }
  template <typename T, size_t N>
  void Array(const char* name, const std::array<T, N>& items, const uint8_t&) {
    Row(name, "u8 count", "0 … " + std::to_string(N) + ", then that many:");
    Describer element(prefix_ + name + "[].");
    if constexpr (std::is_arithmetic_v<T>) {
      element.Field("item", items[0]);
    } else {
      T::Fields(element, items[0]);
    }
    rows += element.rows;
    Add(1, 1 + N * element.max_size);
  }
  template <size_t N>
  void Bytes(const char* name, const std::array<uint8_t, N>&, const uint8_t&) {
    Row(name, "u8 length + bytes", "0 … " + std::to_string(N) + " bytes");
    Add(1, 1 + N);
  }
  template <size_t N>
  void Fixed(const char* name, const std::array<uint8_t, N>&) {
    Row(name, std::to_string(N) + " bytes", "");
    Add(N, N);
  }
  template <size_t N>
  void Text(const char* name, const std::array<char, N>&) {
    Row(name, std::to_string(N) + " chars",
        "at most " + std::to_string(N - 1) + " printable ASCII, NUL-terminated and padded");
    Add(N, N);
  }

 private:
  void Row(const char* name, const std::string& type, const std::string& range) {
    const std::string full = prefix_ + name;
    const std::string unit = Unit(name);
    rows +=
        "| `" + full + "` | " + type + " | " + (unit.empty() ? "" : unit) + " | " + range + " |\n";
  }
  void Add(size_t lo, size_t hi) {
    min_size += lo;
    max_size += hi;
  }
  std::string prefix_;
};

constexpr const char* kSenderNames[] = {"host", "board"};

std::string StatusTable() {
  std::string t =
      "#### Status codes (Nack.status and every API result)\n\n| code | name |\n|---|---|\n";
  for (unsigned i = 0; i < static_cast<unsigned>(pp::Status::kCount); ++i) {
    t += "| " + std::to_string(i) + " | `" + pp::kStatusNames[i] + "` |\n";
  }
  return t + "\n";
}

std::string FaultTable() {
  std::string t =
      "#### Fault bits (fault_bitmap, FaultRecord.fault)\n\n| bit | fault |\n|---|---|\n";
  for (unsigned i = 0; i < static_cast<unsigned>(pp::Fault::kCount); ++i) {
    t += "| " + std::to_string(i) + " | `" + pp::kFaultNames[i] + "` |\n";
  }
  return t + "\n";
}

std::string LineStatusTable() {
  std::string t =
      "#### Line status bits (LineSample.status in Telemetry)\n\n| bit | status |\n|---|---|\n";
  for (unsigned i = 0; i < sizeof(pp::kLineStatusNames) / sizeof(pp::kLineStatusNames[0]); ++i) {
    t += "| " + std::to_string(i) + " | `" + pp::kLineStatusNames[i] + "` |\n";
  }
  return t + "\n";
}

/// Worst-case telemetry frame (no zero bytes to shorten COBS, every field at its widest).
size_t TelemetryFrameBytes(uint8_t lines, uint8_t ticks) {
  pp::Telemetry t{};
  t.boot_nonce = 0xFFFFFFFF;
  t.first_sample_us = ~0ull;
  t.sample_interval_us = 0xFFFFFFFF;
  t.tick_count = ticks;
  t.line_count = lines;
  t.setpoint_generation = t.target_generation = t.fault_bitmap = t.dropped_frames = 0xFFFFFFFF;
  t.sample_count = static_cast<uint8_t>(lines * ticks);
  for (uint8_t i = 0; i < t.sample_count; ++i) t.samples[i] = {-99999, -99999, 0xFFFF, 0xFF};
  uint8_t frame[pp::kMaxFrameSize];
  return pp::EncodeMessageFrame(t, 0xFF, pp::flags::kFromBoard, frame, sizeof(frame)).value;
}

/// Telemetry at 1 kHz against each transport's capacity, from real encoded frame sizes.
std::string BudgetTable() {
  struct Transport {
    const char* name;
    double bytes_per_s;
  };
  const Transport transports[] = {{"UART 1 Mbaud (8N1)", 100000},
                                  {"USB FS bulk / CDC", 1000000},
                                  {"USB HID, 64-byte reports at 1 kHz", 64000},
                                  {"pty / TCP (local)", 50000000}};
  std::string t =
      "#### Telemetry budget per transport (1 kHz tick, worst-case frame sizes)\n\n"
      "| lines | ticks per frame | frame bytes | bytes/s at 1 kHz |";
  std::string rule = "|---|---|---|---|";
  for (const auto& tr : transports) {
    t += std::string(" ") + tr.name + " |";
    rule += "---|";
  }
  t += "\n" + rule + "\n";
  for (uint8_t lines : {1, 3, 5, 7, 8}) {
    const uint8_t ticks = static_cast<uint8_t>(
        pp::kMaxTelemetrySamples / lines > 16 ? 16 : pp::kMaxTelemetrySamples / lines);
    const size_t frame = TelemetryFrameBytes(lines, ticks);
    const double frames_per_s = 1000.0 / ticks;
    t += "| " + std::to_string(lines) + " | " + std::to_string(ticks) + " | " +
         std::to_string(frame) + " | " + std::to_string(static_cast<long>(frame * frames_per_s)) +
         " |";
    for (const auto& tr : transports) {
      const double load = static_cast<double>(frame) * frames_per_s / tr.bytes_per_s;
      // Decimation that keeps telemetry at or under half the link, leaving room for answers.
      int decimation = 1;
      while (load / decimation > 0.5) ++decimation;
      char cell[64];
      std::snprintf(
          cell, sizeof(cell), " %.1f %%%s |", load * 100,
          decimation > 1 ? (" → every " + std::to_string(decimation) + " ticks").c_str() : "");
      t += cell;
    }
    t += "\n";
  }
  return t +
         "\nHID carries the byte stream packed into 64-byte reports, one report per 1 ms USB "
         "frame.\n"
         "A cell with \"every N ticks\" needs `telemetry_decimation` ≥ N to stay under half of the "
         "link.\n\n";
}

std::string Generate() {
  std::string summary =
      "| type | message | sender | delivery | body bytes | purpose |\n"
      "|---|---|---|---|---|---|\n";
  std::string details;
  pp::ForEachMessage(pp::Catalog{}, [&]<class M>() {
    Describer d;
    M m{};
    M::Fields(d, m);
    char id[8];
    std::snprintf(id, sizeof(id), "0x%02X", static_cast<unsigned>(M::kInfo.type));
    const std::string sizes = d.min_size == d.max_size
                                  ? std::to_string(d.min_size)
                                  : std::to_string(d.min_size) + "–" + std::to_string(d.max_size);
    summary += std::string("| ") + id + " | " + M::kInfo.name + " | " +
               kSenderNames[static_cast<int>(M::kInfo.sender)] + " | " +
               pp::kDeliveryNames[static_cast<int>(M::kInfo.delivery)] + " | " + sizes + " | " +
               M::kInfo.summary + " |\n";
    details += std::string("#### ") + id + " " + M::kInfo.name +
               (pp::IsBootstrap(static_cast<uint8_t>(M::kInfo.type)) ? " (bootstrap)" : "") +
               "\n\n";
    if (d.rows.empty()) {
      details += "Empty body.\n\n";
    } else {
      details += "| field | wire type | unit | range |\n|---|---|---|---|\n" + d.rows + "\n";
    }
  });
  char hash[64];
  std::snprintf(hash, sizeof(hash), "Catalog hash of this build: `0x%08x`.\n\n", pp::kCatalogHash);
  return hash + summary + "\n" + details + StatusTable() + FaultTable() + LineStatusTable() +
         BudgetTable();
}

constexpr const char* kBegin =
    "<!-- catalog:begin (generated by palpa_catalog_doc; do not edit) -->\n";
constexpr const char* kEnd = "<!-- catalog:end -->";

// Finds the generated region of the document: [begin, end) between the markers.
bool FindRegion(const std::string& doc, size_t& begin, size_t& end) {
  begin = doc.find(kBegin);
  end = doc.find(kEnd);
  if (begin == std::string::npos || end == std::string::npos || end < begin) return false;
  begin += std::string(kBegin).size();
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string generated = Generate();
  if (argc != 3) {
    std::cout << generated;
    return 0;
  }
  const std::string mode = argv[1];
  std::ifstream in(argv[2]);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string doc = buffer.str();
  size_t begin = 0, end = 0;
  if (!FindRegion(doc, begin, end)) {
    std::cerr << argv[2] << ": catalog markers missing\n";
    return 1;
  }
  if (mode == "--check") {
    if (doc.compare(begin, end - begin, generated) != 0) {
      std::cerr << argv[2] << ": message reference is out of date; run ./run docs\n";
      return 1;
    }
    std::cout << argv[2] << " matches the catalog\n";
    return 0;
  }
  if (mode == "--update") {
    doc.replace(begin, end - begin, generated);
    std::ofstream(argv[2]) << doc;
    return 0;
  }
  std::cerr << "usage: palpa_catalog_doc [--check|--update FILE]\n";
  return 2;
}
