/* WireNet: fix wirenet/gravity. See doc/fix_wirenet_gravity.md.

   post_force adds rmass[i] * acc to the force of every atom of the group: one pass that only
   reads the masses and updates the forces. LIGGGHTS' fix gravity computes the same products
   (magnitude times the normalised direction, times the mass) but also sums m g . x over the
   atoms into a member at every step, a chain through memory that cost 4.4 % of a compound
   impact's step (docs/PERFORMANCE.md). */

#include "fix_wirenet_gravity.h"
#include "wirenet_fix_args.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "atom.h"
#include "error.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *USAGE = "expected 'fix ID GROUP wirenet/gravity G vector X Y Z'";

}  // namespace

FixWirenetGravity::FixWirenetGravity(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  try {
    if (narg != 8 || strcmp(arg[4], "vector") != 0) throw std::invalid_argument(USAGE);
    const double g = WireNet::FixArgs::number(arg[3], "G");
    double dir[3];
    for (int k = 0; k < 3; k++) dir[k] = WireNet::FixArgs::number(arg[5 + k], std::string("vector ") + "XYZ"[k]);
    // as fix gravity: the direction normalised, then scaled by the magnitude
    const double length = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(length > 0.0) || !std::isfinite(length))
      throw std::invalid_argument("the vector X Y Z must have a finite, non-zero length");
    for (int k = 0; k < 3; k++) acc[k] = g * (dir[k] / length);
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, ("fix wirenet/gravity: " + std::string(e.what())).c_str());
  }
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extvector = 0;
}

int FixWirenetGravity::setmask()
{
  return POST_FORCE;
}

void FixWirenetGravity::init()
{
  if (!atom->rmass_flag)
    error->all(FLERR, "fix wirenet/gravity: needs per-atom masses (atom_style sphere or granular)");
}

void FixWirenetGravity::setup(int vflag)
{
  post_force(vflag);
}

void FixWirenetGravity::post_force(int)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const double *rmass = atom->rmass;
  double **f = atom->f;
  const double ax = acc[0], ay = acc[1], az = acc[2];
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double m = rmass[i];
    double *fi = f[i];
    fi[0] += m * ax;
    fi[1] += m * ay;
    fi[2] += m * az;
  }
}

// the acceleration vector g (x, y, z) [m/s^2]
double FixWirenetGravity::compute_vector(int n)
{
  return acc[n];
}
