/* WireNet: compute wirenet/local. See doc/compute_wirenet_local.md. */

#include "compute_wirenet_local.h"

#include "atom.h"
#include "bond_wirenet.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "update.h"

using namespace LAMMPS_NS;

ComputeWirenetLocal::ComputeWirenetLocal(LAMMPS *lmp, int &iarg, int narg, char **arg) :
  Compute(lmp, iarg, narg, arg), nmax(0), bond(NULL)
{
  if (narg != iarg) error->all(FLERR, "compute wirenet/local takes no arguments: compute ID GROUP wirenet/local");
  if (!atom->molecular) error->all(FLERR, "compute wirenet/local needs an atom style with bonds");
  local_flag = 1;
  size_local_cols = NCOLS;
  size_local_rows = 0;
  array_local = NULL;
}

ComputeWirenetLocal::~ComputeWirenetLocal()
{
  memory->destroy(array_local);
}

void ComputeWirenetLocal::init()
{
  bond = dynamic_cast<BondWirenet *>(force->bond);
  if (!bond) error->all(FLERR, "compute wirenet/local needs bond_style wirenet");
}

// A bond is reported when both nodes are in the group; each bond once, by the rank that owns it.
int ComputeWirenetLocal::fill(bool store)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const int *num_bond = atom->num_bond;
  int **bond_atom = atom->bond_atom;
  int **bond_type = atom->bond_type;
  double **x = atom->x;
  int n = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (int m = 0; m < num_bond[i]; m++) {
      int j = atom->map(bond_atom[i][m]);
      if (j < 0) continue;
      j = domain->closest_image(i, j);
      if (!(mask[j] & groupbit)) continue;
      BondWirenet::BondState s;
      if (!bond->bond_state(i, m, j, s)) continue;
      if (store) {
        double *row = array_local[n];
        row[0] = atom->tag[i];
        row[1] = bond_atom[i][m];
        row[2] = bond_type[i][m];
        row[3] = s.length0;
        row[4] = (s.length - s.length0) / s.length0;
        row[5] = s.tension;
        row[6] = s.length;
        for (int d = 0; d < 3; d++) row[7 + d] = 0.5 * (x[i][d] + x[j][d]);
        row[10] = s.shear;
        row[11] = s.moment;
      }
      n++;
    }
  }
  return n;
}

void ComputeWirenetLocal::compute_local()
{
  invoked_local = update->ntimestep;
  const int n = fill(false);
  if (n > nmax) {
    nmax = n;
    memory->destroy(array_local);
    memory->create(array_local, nmax, NCOLS, "wirenet/local:array");
  }
  size_local_rows = n;
  fill(true);
}

double ComputeWirenetLocal::memory_usage()
{
  return (double)nmax * NCOLS * sizeof(double);
}
