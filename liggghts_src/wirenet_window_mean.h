/* WireNet: sums of per-step values over windows of N steps, (k N - N, k N], kept on one MPI
   rank and reduced only when a mean is asked for. A fix that reports the mean of a force over
   an output interval thus needs one collective per output row instead of one per step (the
   window means of fix ave/time evaluate a reduced quantity at every step). Every rank counts
   the same steps, so the ranks' sums add up to the global sums of the same samples.
   No LIGGGHTS dependency; allocation only in reset(). */

#ifndef WIRENET_WINDOW_MEAN_H
#define WIRENET_WINDOW_MEAN_H

#include <cstdint>
#include <vector>

namespace WireNet {

class WindowSums {
 public:
  // windows of `width` steps (>= 1) over `nvalues` values; forgets every earlier sample
  void reset(int width, int nvalues)
  {
    width_ = width;
    open_.assign(nvalues, 0.0);
    closed_.assign(nvalues, 0.0);
    zeros_.assign(nvalues, 0.0);
    open_id_ = closed_id_ = -1;
    open_count_ = closed_count_ = 0;
    last_step_ = -1;
  }

  int width() const { return static_cast<int>(width_); }

  // The sums to add the values of `step` into, or NULL if that step was counted already (the
  // setup of a run that continues at the step the last run ended on). A step before the last
  // one counted (reset_timestep) starts the windows anew.
  double *add_step(int64_t step)
  {
    if (step == last_step_) return nullptr;
    if (step < last_step_) reset(static_cast<int>(width_), static_cast<int>(open_.size()));
    last_step_ = step;
    const int64_t id = window_of(step);
    if (id != open_id_) {
      closed_.swap(open_);
      closed_id_ = open_id_;
      closed_count_ = open_count_;
      for (double &v : open_) v = 0.0;
      open_id_ = id;
      open_count_ = 0;
    }
    open_count_++;
    return open_.data();
  }

  // This rank's sums of the last window complete at `step` (the one ending at the last multiple
  // of the width at or before it) and its number of samples (0 if none was counted: the sums
  // are then zeros).
  const double *complete(int64_t step, int &count) const
  {
    const int64_t id = step / width_;    // every step of window id is <= step
    if (id == open_id_) {
      count = open_count_;
      return open_.data();
    }
    if (id == closed_id_) {
      count = closed_count_;
      return closed_.data();
    }
    count = 0;
    return zeros_.data();
  }

 private:
  int64_t width_ = 1;
  std::vector<double> open_, closed_, zeros_;
  int64_t open_id_ = -1, closed_id_ = -1;
  int open_count_ = 0, closed_count_ = 0;
  int64_t last_step_ = -1;

  // window k holds the steps k N - N + 1 .. k N (step 0: window 0 alone)
  int64_t window_of(int64_t step) const { return (step + width_ - 1) / width_; }
};

}  // namespace WireNet

#endif
