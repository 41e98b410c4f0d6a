// Discrete Preisach model: relay grid, state update on every input change.
#include "palpa/hal/sim/preisach.h"

namespace palpa::sim {

PreisachModel::PreisachModel(int cells, float range,
                             const std::function<float(float, float)>& density) {
  const float step = range / static_cast<float>(cells);
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j <= i; ++j) {
      const float alpha = (static_cast<float>(i) + 0.5f) * step;
      const float beta = (static_cast<float>(j) + 0.5f) * step;
      cells_.push_back(Cell{alpha, beta, density(alpha, beta)});
    }
  }
  up_.assign(cells_.size(), 0);
}

void PreisachModel::Reset() {
  up_.assign(cells_.size(), 0);
  output_ = 0;
  has_input_ = false;
}

float PreisachModel::Apply(float input) {
  if (has_input_ && input == last_input_) return output_;
  has_input_ = true;
  last_input_ = input;
  float sum = 0;
  for (size_t k = 0; k < cells_.size(); ++k) {
    if (input >= cells_[k].alpha) up_[k] = 1;
    if (input <= cells_[k].beta) up_[k] = 0;
    if (up_[k]) sum += cells_[k].weight;
  }
  output_ = sum;
  return output_;
}

float PreisachModel::RisingMajor(float x) const {
  float sum = 0;
  for (const Cell& c : cells_) {
    if (c.alpha <= x) sum += c.weight;
  }
  return sum;
}

float PreisachModel::FallingMajor(float x) const {
  float sum = 0;
  for (const Cell& c : cells_) {
    if (c.beta < x) sum += c.weight;
  }
  return sum;
}

}  // namespace palpa::sim
