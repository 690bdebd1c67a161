/* WireNet: compute wirenet/timestep, the stable time step of the bonds of bond_style wirenet and
   of a contact on the lightest atom of the group (doc/compute_wirenet_timestep.md). */

#ifdef COMPUTE_CLASS

ComputeStyle(wirenet/timestep,ComputeWirenetTimestep)

#else

#ifndef LMP_COMPUTE_WIRENET_TIMESTEP_H
#define LMP_COMPUTE_WIRENET_TIMESTEP_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeWirenetTimestep : public Compute {
 public:
  static const int NVALUES = 5;
  ComputeWirenetTimestep(class LAMMPS *, int &, int, char **);
  ~ComputeWirenetTimestep();
  void init();
  void compute_vector();

 private:
  class BondWirenet *bond;
  double kn, kt;     // the contact's normal and tangential stiffness (0: no contact)
  double sides;      // bodies that can press an atom at once (a compound panel's layers: 2)
};

}

#endif
#endif
