// The activation of one modality's factors in the reliability scheduling (docs/METHOD.md "Factor-wise
// reliability scheduling"; paper Sec. III-D): s_k = [D_k <= tau and N_k >= N_min], smoothed by hysteresis
// so that a score hovering about tau does not switch the factors in and out at every keyframe:
//   active     -> suppressed at the first keyframe with D > tau or N < N_min;
//   suppressed -> active again only after release_keyframes consecutive keyframes with
//                 D <= tau - release_margin and N >= N_min (a keyframe outside resets the count).
#pragma once

namespace uf::estimator {

struct ActivationRule {
  double threshold = 0.5;       // tau
  double release_margin = 0.1;  // re-admitted below tau - this
  int release_keyframes = 3;    // consecutive keyframes below it
  int min_count = 0;            // N_min
};

class ActivationGate {
 public:
  explicit ActivationGate(const ActivationRule& rule = {}) : rule_(rule) {}

  // The score of the next keyframe and its valid observation count; returns whether the modality's
  // factors of that keyframe are active.
  bool Update(double score, int count = 0);
  bool active() const { return active_; }
  // Opens the gate now (the caller overrides it, e.g. after the longest time shut it allows).
  void Open() {
    active_ = true;
    calm_ = 0;
  }

 private:
  ActivationRule rule_;
  bool active_ = true;
  int calm_ = 0;  // consecutive keyframes below the release level while suppressed
};

}  // namespace uf::estimator
