/* WireNet: fix wirenet/balance, a static load balance for LIGGGHTS 3.8.0, which has no
   `balance` command: at the set-up of every run the processor grid's cuts along the named
   dimensions are moved to the quantiles of the group's atoms, so that each slab of ranks owns
   the same number of them. A net spans a small part of its box (a fence's upslope anchors lie
   10 m behind a net a metre deep, its lateral anchors beyond its posts): uniform cuts leave
   ranks nearly empty. See doc/fix_wirenet_balance.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/balance,FixWirenetBalance)

#else

#ifndef LMP_FIX_WIRENET_BALANCE_H
#define LMP_FIX_WIRENET_BALANCE_H

#include "fix.h"

#include <vector>

namespace LAMMPS_NS {

class FixWirenetBalance : public Fix {
 public:
  FixWirenetBalance(class LAMMPS *, int, char **);
  int setmask();
  void init();
  void setup_pre_exchange();
  void pre_exchange() {}
  double compute_vector(int);

 private:
  bool dims[3];            // the dimensions whose cuts follow the atoms
  double imbalance[2];     // largest rank's group atoms over the mean: before and after the last balance
  bool reported;           // the first balance is written to the screen and log, the others not

  double imbalance_now() const;
  void quantile_cuts(int dim, std::vector<double> &split) const;
};

}  // namespace LAMMPS_NS

#endif
#endif
