/* WireNet: fix wirenet/contactwork, the work and impulse of the forces that the fixes defined
   between a 'mark' instance and a 'since' instance add to the atoms (e.g. fix wall/gran), or
   of the pair forces ('pair' mode).
   See doc/fix_wirenet_contactwork.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/contactwork,FixWirenetContactWork)

#else

#ifndef LMP_FIX_WIRENET_CONTACTWORK_H
#define LMP_FIX_WIRENET_CONTACTWORK_H

#include "fix.h"
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixWirenetContactWork : public Fix {
 public:
  FixWirenetContactWork(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup(int);
  void post_force(int);
  void end_of_step();
  double compute_scalar();
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);

  // force and torque of every local atom (6 doubles each) when a 'mark' fix last ran
  const std::vector<double> &snapshot() const { return snap; }

 private:
  bool is_mark;
  bool is_pair;               // measure the pair forces (taken by fix wirenet/bonds)
  class FixWirenetBonds *bonds;
  std::string mark_id;
  FixWirenetContactWork *mark;
  bool rotational;
  std::vector<double> snap;   // mark: f and torque at its post_force; since: their increments
  int nheld;                  // since: local atoms in snap; -1 = nothing to account this step
  double sums_mine[5];        // work of forces, work of torques, impulse x y z (this rank)
  double sums_all[5];
  void reduce();
};

}

#endif
#endif
