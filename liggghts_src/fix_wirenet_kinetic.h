/* WireNet: fix wirenet/kinetic, kinetic damping (dynamic relaxation): every velocity and angular
   velocity of the group is set to zero at each peak of the group's kinetic energy.
   See doc/fix_wirenet_kinetic.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/kinetic,FixWirenetKinetic)

#else

#ifndef LMP_FIX_WIRENET_KINETIC_H
#define LMP_FIX_WIRENET_KINETIC_H

#include "fix.h"

namespace LAMMPS_NS {

class FixWirenetKinetic : public Fix {
 public:
  FixWirenetKinetic(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void end_of_step();
  double compute_vector(int);

 private:
  bool rotational;   // the atom style has angular velocities (they count and are stopped too)
  double ke_last;    // the group's kinetic energy at the end of the last step (0 after a stop)
  double ke_peak;    // the kinetic energy of the latest peak (the last stop) [J]
  double ke_now;     // the group's kinetic energy at the end of this step, before any stop
  bigint stops;      // stops so far (this fix's life)
  bigint stopped_at; // the step of the latest stop (before the first: the step the fix was defined at)
  double kinetic_energy() const;
  void stop_all();
};

}  // namespace LAMMPS_NS

#endif
#endif
