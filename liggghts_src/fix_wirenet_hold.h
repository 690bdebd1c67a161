/* WireNet: fix wirenet/hold, a support: zeroes the held force components of its atoms (as
   fix setforce 0) and reports the support reaction, at the current step and as the mean over
   windows of N steps, summed on each rank and reduced once per output (fix setforce is reduced
   at every step a window mean samples it). Optionally one row per atom (anchors, post bases).
   See doc/fix_wirenet_hold.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/hold,FixWirenetHold)

#else

#ifndef LMP_FIX_WIRENET_HOLD_H
#define LMP_FIX_WIRENET_HOLD_H

#include "fix.h"
#include "wirenet_window_mean.h"
#include <vector>

namespace LAMMPS_NS {

class FixWirenetHold : public Fix {
 public:
  static const int NVECTOR = 6;     // reaction x y z at this step, window mean x y z
  static const int NCOLUMNS = 7;    // per atom: ID, reaction x y z, window mean x y z
  static const int MAX_EACH = 10000;

  FixWirenetHold(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void min_setup(int);
  void post_force(int);
  void min_post_force(int);
  double compute_vector(int);
  double compute_array(int, int);

 private:
  bool held[3];
  int width;                         // steps per mean window (keyword mean)
  bool each;                         // one row per atom (keyword each)
  std::vector<int> tags;             // the rows' atom IDs, ascending (each)
  std::vector<double> current;       // this rank's reaction of the last step: total (3), rows (3 per row)
  WireNet::WindowSums windows;       // the same values summed over the mean windows
  std::vector<double> reduced;       // current (total, rows) then window mean (total, rows), all ranks
  long long reduced_at;              // step of `reduced`; -1: stale
  std::vector<int> members;          // local indices of the group's atoms, ascending
  std::vector<int> member_rows;      // their rows (each), else -1
  long long members_at;              // neighbor->ncalls when members was listed

  void collect_rows();
  void collect_members();
  int row_of(int tag) const;
  void reduce();
};

}

#endif
#endif
