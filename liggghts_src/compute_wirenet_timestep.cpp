/* WireNet: compute wirenet/timestep. See doc/compute_wirenet_timestep.md.

   The one estimate of the stable time step the WireNet runner uses: the bonds' frequencies as
   bond_style wirenet counts them (the two-node axial and rotational frequencies of each bond,
   doubled for neighbours in antiphase), and a contact of stiffness kn, kt on the lightest atom
   of the group, omega_c^2 = sides (kn + 2.5 kt) / m_min (the tangential spring acts at the
   sphere's surface: 1 + 2.5 kt/kn of the normal frequency squared for a solid sphere). Bonds
   and contact act on the same node at once: omega^2 = max(omega_t^2, omega_r^2) + omega_c^2,
   and dt = 2 / omega. */

#include "compute_wirenet_timestep.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "atom.h"
#include "bond_wirenet.h"
#include "error.h"
#include "force.h"
#include "update.h"
#include "wirenet_fix_args.h"

using namespace LAMMPS_NS;

namespace {
const char *USAGE = "expected 'compute ID GROUP wirenet/timestep [contact KN KT] [sides N]'";
}

ComputeWirenetTimestep::ComputeWirenetTimestep(LAMMPS *lmp, int &iarg, int narg, char **arg) :
  Compute(lmp, iarg, narg, arg), bond(NULL), kn(0.0), kt(0.0), sides(1.0)
{
  try {
    int k = iarg;
    while (k < narg) {
      const std::string key = arg[k];
      if (key == "contact") {
        if (k + 2 >= narg) throw std::invalid_argument("'contact' needs 2 values: KN KT");
        kn = WireNet::FixArgs::number(arg[k + 1], "contact KN");
        kt = WireNet::FixArgs::number(arg[k + 2], "contact KT");
        if (!(kn > 0.0) || kt < 0.0)
          throw std::invalid_argument("contact needs KN > 0 and KT >= 0 (got " + std::string(arg[k + 1]) +
                                      " " + arg[k + 2] + ")");
        k += 3;
      } else if (key == "sides") {
        sides = WireNet::FixArgs::value(narg, arg, k, "sides", 1.0, false);
      } else {
        throw std::invalid_argument("unknown keyword '" + key + "'");
      }
    }
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, (std::string("compute wirenet/timestep: ") + e.what() + " (" + USAGE + ")").c_str());
  }
  vector_flag = 1;
  size_vector = NVALUES;
  extvector = 0;
  vector = new double[NVALUES];
}

ComputeWirenetTimestep::~ComputeWirenetTimestep()
{
  delete[] vector;
}

void ComputeWirenetTimestep::init()
{
  bond = dynamic_cast<BondWirenet *>(force->bond);
  if (!bond) error->all(FLERR, "compute wirenet/timestep needs bond_style wirenet");
  if (!atom->rmass_flag) error->all(FLERR, "compute wirenet/timestep needs per-atom masses");
}

// 1 translation, 2 rotation, 3 bonds (the smaller), 4 contact, 5 the stable step (s);
// infinite where nothing limits it
void ComputeWirenetTimestep::compute_vector()
{
  invoked_vector = update->ntimestep;
  if (!bond->list_built())
    error->all(FLERR, "compute wirenet/timestep: the bonds are listed at the first force evaluation: read it after a 'run 0'");
  double local[3], global[3];
  bond->stable_frequencies(local);
  double m_min = INFINITY;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit) m_min = fmin(m_min, atom->rmass[i]);
  local[2] = m_min > 0.0 && std::isfinite(m_min) ? 1.0 / m_min : 0.0;   // the largest 1/m
  MPI_Allreduce(local, global, 3, MPI_DOUBLE, MPI_MAX, world);
  const double w2_contact = sides * (kn + 2.5 * kt) * global[2];
  const double w2 = fmax(global[0], global[1]) + w2_contact;
  vector[0] = global[0] > 0.0 ? 2.0 / sqrt(global[0]) : INFINITY;
  vector[1] = global[1] > 0.0 ? 2.0 / sqrt(global[1]) : INFINITY;
  vector[2] = fmin(vector[0], vector[1]);
  vector[3] = w2_contact > 0.0 ? 2.0 / sqrt(w2_contact) : INFINITY;
  vector[4] = w2 > 0.0 ? 2.0 / sqrt(w2) : INFINITY;
}
