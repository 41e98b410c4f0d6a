// palpa render's closing summary, in words on the terminal or as one JSON document.
#include "render_summary.h"

#include <cstdio>

#include "cli.h"
#include "render_record.h"

namespace palpa::cli {

void PrintRenderSummary(const RenderSummary& s) {
  const host::MotionPredictor* p = s.predictor;
  if (JsonOutput()) {
    nlohmann::ordered_json j = {
        {"scene", s.scene},
        {"input", s.input},
        {"samples", s.fed},
        {"of", s.total},
        {"record", s.record.empty() ? nullptr : nlohmann::ordered_json(s.record)}};
    if (p != nullptr) {
      nlohmann::ordered_json not_predicted;
      for (auto k :
           {host::Prediction::kTooFewSamples, host::Prediction::kErratic,
            host::Prediction::kReversing, host::Prediction::kStopped, host::Prediction::kLifted})
        not_predicted[host::PredictionName(k)] = p->count(k);
      j["prediction"] = {{"horizon_s", s.horizon_s},
                         {"predicted", p->count(host::Prediction::kPredicted)},
                         {"not_predicted", not_predicted}};
    }
    if (s.hold) j["tactile"] = {{"late", s.hold->late()}, {"missing", s.hold->missing()}};
    if (s.udp) j["tactile"]["malformed"] = s.udp->malformed();
    if (s.tablet)
      j["tablet"] = {{"device", host::DescribePad(s.tablet->mapping().pad)},
                     {"resyncs", s.tablet->resyncs()}};
    PrintJson(j);
    return;
  }
  // Over UDP the frames that arrive are all there is to count.
  std::fprintf(TextOut(), "%s: %zu of %zu %s rendered%s%s\n", s.scene.c_str(),
               s.tactile ? s.taken : s.fed, s.udp != nullptr ? s.taken : s.total,
               s.tactile ? "frames" : "samples", s.record.empty() ? "" : "; recorded in ",
               s.record.empty() ? ""
               : s.hand         ? (s.record + " and " + SvgPath(s.record)).c_str()
                                : s.record.c_str());
  if (p != nullptr)
    std::fprintf(TextOut(),
                 "prediction: %.1f ms ahead (the fingers' calibrated delay); %zu of %zu "
                 "samples predicted\n",
                 s.horizon_s * 1e3, p->count(host::Prediction::kPredicted), s.fed);
  if (s.hold && (s.hold->late() > 0 || s.hold->missing() > 0))
    std::fprintf(TextOut(), "tactile: %zu frames missing, %zu late (dropped)\n", s.hold->missing(),
                 s.hold->late());
  if (s.udp && s.udp->malformed() > 0)
    std::fprintf(TextOut(), "tactile: %zu malformed datagrams ignored (last: %s)\n",
                 s.udp->malformed(), s.udp->last_problem().c_str());
}

}  // namespace palpa::cli
