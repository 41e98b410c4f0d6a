// A discrete Preisach hysteresis model: relays on a grid over the (alpha, beta) half-plane with
// a density given per cell. Host only (level 2 of the plant).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace palpa::sim {

class PreisachModel {
 public:
  /// Relays on an n x n grid over [0, range]: up when the input reaches alpha, down when it falls
  /// to beta. density(alpha, beta) gives each cell's weight (output units per relay).
  PreisachModel(int cells, float range, const std::function<float(float, float)>& density);

  /// All relays down (the state after venting to 0).
  void Reset();
  /// Applies an input; returns the hysteretic output.
  float Apply(float input);
  float output() const { return output_; }

  /// Output of the major loop from a fully reset state: rising to x, and falling from the top of
  /// the range back to x. Their difference is the loop's width at x.
  float RisingMajor(float x) const;
  float FallingMajor(float x) const;

 private:
  struct Cell {
    float alpha;
    float beta;
    float weight;
  };
  std::vector<Cell> cells_;
  std::vector<uint8_t> up_;
  float output_ = 0;
  float last_input_ = 0;
  bool has_input_ = false;
};

}  // namespace palpa::sim
