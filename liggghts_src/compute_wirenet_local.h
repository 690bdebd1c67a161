/* WireNet: compute wirenet/local, one row per intact bond of bond_style wirenet.
   Columns: atom1 atom2 type length0 strain tension length xm ym zm shear moment
   (see doc/compute_wirenet_local.md). */

#ifdef COMPUTE_CLASS

ComputeStyle(wirenet/local,ComputeWirenetLocal)

#else

#ifndef LMP_COMPUTE_WIRENET_LOCAL_H
#define LMP_COMPUTE_WIRENET_LOCAL_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeWirenetLocal : public Compute {
 public:
  static const int NCOLS = 12;
  ComputeWirenetLocal(class LAMMPS *, int &, int, char **);
  ~ComputeWirenetLocal();
  void init();
  void compute_local();
  double memory_usage();

 private:
  int nmax;
  class BondWirenet *bond;
  int fill(bool store);
};

}

#endif
#endif
