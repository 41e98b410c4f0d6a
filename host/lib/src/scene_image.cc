// Greyscale PGM images (P2, P5) read into tissue maps with a stated scale.
#include "palpa/host/scene_image.h"
#include "number_text.h"

#include <cctype>
#include <cmath>
#include <cstdio>

namespace palpa::host {
namespace {

/// Reads the PGM header's and P2's whitespace-separated unsigned integers, skipping # comments.
class Tokens {
 public:
  Tokens(const std::string& bytes, size_t from) : b_(bytes), at_(from) {}
  /// The next integer, or -1 when there is none or it is not one (or past 65 535 · 1 024).
  long Next() {
    for (;;) {
      while (at_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[at_]))) ++at_;
      if (at_ < b_.size() && b_[at_] == '#') {
        while (at_ < b_.size() && b_[at_] != '\n') ++at_;
        continue;
      }
      break;
    }
    long v = 0;
    const size_t start = at_;
    while (at_ < b_.size() && std::isdigit(static_cast<unsigned char>(b_[at_])) && v < 1L << 30)
      v = v * 10 + (b_[at_++] - '0');
    const bool ended = at_ == b_.size() || std::isspace(static_cast<unsigned char>(b_[at_]));
    return at_ > start && ended ? v : -1;
  }
  size_t at() const { return at_; }

 private:
  const std::string& b_;
  size_t at_;
};

}  // namespace

Result<TissueMap> ParseTissueImage(const std::string& bytes, const ImageScale& scale,
                                   const std::string& source) {
  auto fail = [&](const std::string& why) -> Result<TissueMap> {
    return {Status::kInvalidArgument, source + ": " + why};
  };
  if (!(scale.mm_per_pixel > 0 && scale.mm_per_pixel <= 1000))
    return fail("the scale's mm per pixel " + Num(scale.mm_per_pixel) + " is not in (0, 1000]");
  if (!std::isfinite(scale.value_at_black) || !std::isfinite(scale.value_at_white))
    return fail("the scale's values at black and white must be finite numbers");
  const std::string magic = bytes.substr(0, 2);
  if ((magic != "P2" && magic != "P5") || bytes.size() < 3 ||
      !std::isspace(static_cast<unsigned char>(bytes[2]))) {
    return fail("not a greyscale PGM image (it starts \"" + magic +
                "\"; expected P2 or P5 — export it as PGM)");
  }
  Tokens header(bytes, 2);
  const long width = header.Next(), height = header.Next(), maxval = header.Next();
  const long most = static_cast<long>(kMaxTissuePoints);
  if (width < 2 || width > most)
    return fail("header: width " + std::to_string(width) + " is not 2 … 1024");
  if (height < 2 || height > most)
    return fail("header: height " + std::to_string(height) + " is not 2 … 1024");
  if (maxval < 1 || maxval > 65535)
    return fail("header: maxval " + std::to_string(maxval) + " is not 1 … 65535");
  TissueMap map;
  map.name = scale.name.empty() ? source : scale.name;
  map.unit = scale.unit.empty() ? "level" : scale.unit;
  map.pitch_x_mm = map.pitch_y_mm = scale.mm_per_pixel;
  map.nx = static_cast<size_t>(width);
  map.ny = static_cast<size_t>(height);
  map.values.resize(map.nx * map.ny);
  const size_t wide = maxval > 255 ? 2 : 1;
  const size_t pixels_at = header.at() + 1;  // one whitespace byte after maxval
  if (magic == "P5" &&
      bytes.size() - std::min(bytes.size(), pixels_at) < map.values.size() * wide) {
    return fail(std::to_string(bytes.size() - std::min(bytes.size(), pixels_at)) +
                " bytes of pixels, expected " + std::to_string(map.values.size() * wide));
  }
  Tokens& ascii = header;
  for (size_t row = 0; row < map.ny; ++row) {
    for (size_t i = 0; i < map.nx; ++i) {
      const size_t k = row * map.nx + i;
      long g = 0;
      if (magic == "P2") {
        g = ascii.Next();
        if (g < 0)
          return fail("pixel (" + std::to_string(i) + ", " + std::to_string(row) +
                      "): missing or not a number");
      } else {
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + pixels_at + k * wide);
        g = wide == 2 ? (p[0] << 8 | p[1]) : p[0];
      }
      if (g > maxval) {
        return fail("pixel (" + std::to_string(i) + ", " + std::to_string(row) +
                    "): " + std::to_string(g) + " is above the maxval " + std::to_string(maxval));
      }
      const double v = scale.value_at_black + static_cast<double>(g) / static_cast<double>(maxval) *
                                                  (scale.value_at_white - scale.value_at_black);
      map.values[(map.ny - 1 - row) * map.nx + i] = v;  // the top row is the largest y
    }
  }
  return map;
}

Result<TissueMap> LoadTissueImage(const std::string& path, const ImageScale& scale) {
  const Result<std::string> bytes = ReadFileWhole(path, kTissueImageLimits);
  if (!bytes.ok()) return bytes.outcome();
  return ParseTissueImage(bytes.value, scale, path);
}

}  // namespace palpa::host
