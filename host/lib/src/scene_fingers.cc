// Finger layouts: checks, the thesis's triangle, rows, rotation, and sampling under each finger.
#include "palpa/host/scene_fingers.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "number_text.h"

namespace palpa::host {
namespace {

std::string Spacing(double mm) { return Num(mm) + " mm"; }

}  // namespace

Outcome CheckLayout(const FingerLayout& layout) {
  auto fail = [](const std::string& why) { return Outcome::Fail(Status::kInvalidArgument, why); };
  if (layout.fingers.empty() || layout.fingers.size() > kMaxLayoutFingers) {
    return fail("fingers: " + std::to_string(layout.fingers.size()) +
                " of them, a layout has 1 … " + std::to_string(kMaxLayoutFingers));
  }
  for (size_t f = 0; f < layout.fingers.size(); ++f) {
    const std::string at = "fingers[" + std::to_string(f) + "]";
    const FingerPlace& p = layout.fingers[f];
    if (!(std::fabs(p.dx_mm) <= 500))
      return fail(at + ".dx_mm: " + Num(p.dx_mm) + " is not within ±500 mm");
    if (!(std::fabs(p.dy_mm) <= 500))
      return fail(at + ".dy_mm: " + Num(p.dy_mm) + " is not within ±500 mm");
  }
  if (!(layout.contact_diameter_mm >= 0 && layout.contact_diameter_mm <= 100)) {
    return fail("contact_diameter_mm: " + Num(layout.contact_diameter_mm) +
                " is not within 0 … 100 mm");
  }
  return {};
}

FingerLayout RightTriangleLayout(double spacing_mm, double contact_diameter_mm) {
  return {"right triangle, " + Spacing(spacing_mm),
          {{0, 0}, {spacing_mm, 0}, {0, spacing_mm}},
          contact_diameter_mm};
}

FingerLayout RowLayout(size_t count, double spacing_mm, double contact_diameter_mm) {
  FingerLayout layout{
      "row of " + std::to_string(count) + ", " + Spacing(spacing_mm), {}, contact_diameter_mm};
  for (size_t f = 0; f < count; ++f) {
    const double centred = static_cast<double>(f) - static_cast<double>(count - 1) / 2;
    layout.fingers.push_back({centred * spacing_mm, 0});
  }
  return layout;
}

FingerLayout JammingPairLayout(double spacing_mm, double contact_diameter_mm) {
  FingerLayout layout = RowLayout(2, spacing_mm, contact_diameter_mm);
  layout.name = "jamming pair, " + Spacing(spacing_mm);
  return layout;
}

FingerLayout Rotated(FingerLayout layout, double degrees) {
  const double a = degrees * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
  for (FingerPlace& p : layout.fingers) p = {c * p.dx_mm - s * p.dy_mm, s * p.dx_mm + c * p.dy_mm};
  layout.name += ", turned " + Num(degrees) + "°";
  return layout;
}

std::vector<ContactSample> SampleFingers(const TissueMap& map, const FingerLayout& layout,
                                         double x_mm, double y_mm) {
  std::vector<ContactSample> out;
  out.reserve(layout.fingers.size());
  for (const FingerPlace& p : layout.fingers) {
    out.push_back(SampleDisc(map, x_mm + p.dx_mm, y_mm + p.dy_mm, layout.contact_diameter_mm));
  }
  return out;
}

}  // namespace palpa::host
