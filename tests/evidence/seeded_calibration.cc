// A seeded calibration on the in-process simulated rig (virtual time, so every run is the same):
// DIR/SERIAL.json, .csv and .html of finger 1 (p) or 4 (j) with the quick protocol. Built from two
// trees, it shows a refactoring leaves what a session writes byte for byte alone.
// usage: seeded_calibration DIR p|j
#include <cstdio>

#include "palpa/calibration/session.h"
#include "sim_rig.h"

namespace cal = palpa::calibration;
namespace pt = palpa::testing;

int main(int argc, char** argv) {
  if (argc < 3) return 2;
  const bool jamming = argv[2][0] == 'j';
  pt::SimRig sim({"thesis-5finger", static_cast<uint8_t>(jamming ? 3 : 0), 0, 33});
  cal::SessionOptions o;
  o.finger = jamming ? 3 : 0;
  o.protocol = cal::QuickProtocol();
  o.protocol.dwell_s = 1;
  o.protocol.contact.speed_mm_s = 0.5;
  o.out_dir = argv[1];
  o.date = "2026-11-22T12:00:00Z";
  cal::Session s(sim.rig(), jamming ? "JM-4" : "PN-1", 7, jamming, o);
  if (!s.OpenOutput().ok() || !s.LoadPrevious().ok()) return 3;
  auto r = s.Run(nullptr);
  if (!r.ok()) {
    std::fprintf(stderr, "%s\n", r.message.c_str());
    return 1;
  }
  return s.Write().ok() ? 0 : 4;
}
