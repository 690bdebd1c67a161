/* WireNet: fix wirenet/damping, Cundall's local (non-viscous) damping of force and torque, with
   an optional mass-proportional viscous part.
   See doc/fix_wirenet_damping.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/damping,FixWirenetDamping)

#else

#ifndef LMP_FIX_WIRENET_DAMPING_H
#define LMP_FIX_WIRENET_DAMPING_H

#include "fix.h"
#include <vector>

namespace LAMMPS_NS {

class FixWirenetDamping : public Fix {
 public:
  FixWirenetDamping(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void post_force(int);
  void initial_integrate(int);
  void final_integrate();
  void reset_dt();
  void end_of_step();
  double compute_scalar();
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);

 private:
  double alpha;
  // keyword viscous: -C m v and -C I w on top of the local damping (1/s; default 0). Local
  // damping acts on the unbalanced force only, so it cannot stop parts that move at a steady
  // speed under balanced forces (a net creeping along its ropes, a brake sliding at its plateau)
  double viscous;
  bool rotational;            // the atom style has torque and omega
  bool tally;                 // keep the work and impulse (keyword tally, default yes)
  // keyword integrate: the fix is also the velocity-Verlet integrator of its atoms (as
  // nve/sphere) and damps in the same pass as the second half kick: one pass over force,
  // velocity, torque and angular velocity instead of two (both passes are bound by memory)
  bool integrate;
  double dtv, dtf;            // integrate: dt and dt/2
  // integrate: dt/2m per force component (3 per local atom, so that the kick is one elementwise
  // pass) and dt/2I per local atom (renew_kicks)
  std::vector<double> kick_v, kick_w;
  bigint kicks_at;            // the neighbour-list build they belong to; -1 = to be worked out
  void renew_kicks();
  // integrate: the group's local atoms with a torque after the damping (most nodes of a net
  // have none: wires pull along their axis), for the next first half step's rotational kicks
  std::vector<int> turning;
  bigint turning_step;        // the step whose damping listed them
  int turning_nlocal;
  template <bool KICK> void damp_all();
  void kick_all();
  template <bool TALLY, bool KICK, bool VISC> void damp();
  template <bool TALLY, bool KICK> void damp_forces_flat();
  template <bool TALLY, bool KICK, bool VISC> void damp_torque(int i, double cm);
  void kick_torque(int i);
  // Damping force and torque of this step per local atom (3 doubles each), kept from post_force
  // to end_of_step, when the velocities of the same instant are known.
  std::vector<double> fdamp_f, fdamp_t;
  int ndamped;                // local atoms in fdamp_f/fdamp_t; -1 = nothing to account this step
  double work_mine[2];        // work of damping forces / torques done on this rank's atoms
  double work_all[2];         // reduced over ranks (by reduce_work)
  double impulse_mine[3];     // impulse of the damping forces on this rank's atoms (momentum budget)
  double impulse_all[3];
  void reduce_work();
};

}

#endif
#endif
