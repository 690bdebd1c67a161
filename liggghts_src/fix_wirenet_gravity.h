/* WireNet: fix wirenet/gravity, the weight m g of every atom of the group, added to its force.
   The vector form of LIGGGHTS' fix gravity with the same arithmetic (the same trajectories, bit
   for bit), without the per-step sum of m g . x that fix gravity keeps at every atom for its
   energy (the WireNet budgets take the potential energy from the positions). See
   doc/fix_wirenet_gravity.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/gravity,FixWirenetGravity)

#else

#ifndef LMP_FIX_WIRENET_GRAVITY_H
#define LMP_FIX_WIRENET_GRAVITY_H

#include "fix.h"

namespace LAMMPS_NS {

class FixWirenetGravity : public Fix {
 public:
  FixWirenetGravity(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void post_force(int);
  double compute_vector(int);

 private:
  double acc[3];   // g times the unit direction [m/s^2]
};

}  // namespace LAMMPS_NS

#endif
#endif
