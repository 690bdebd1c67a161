/* WireNet: fix wirenet/kinetic. See doc/fix_wirenet_kinetic.md.

   Kinetic damping (Cundall 1976; Barnes 1977, 1999, the dynamic relaxation of cable nets): the
   group's kinetic energy is followed step by step; the step after it has peaked, every velocity
   of the group is set to zero. A vibrating mode's kinetic energy peaks where the mode passes its
   static equilibrium, so each stop leaves the structure near that equilibrium, with the energy of
   the other modes only; repeated stops converge on the static state. It removes energy without a
   force, so it slows no mode down (a viscous or local damping strong enough to stop a net's slow
   sag and its creep along its ropes makes those modes take longer). For static states only: it
   is not a physical damping, and a run that needs the dynamics must not use it. */

#include "fix_wirenet_kinetic.h"

#include <cstring>
#include <string>

#include "atom.h"
#include "error.h"
#include "force.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

FixWirenetKinetic::FixWirenetKinetic(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), rotational(false), ke_last(0.0), ke_peak(0.0), ke_now(0.0), stops(0), stopped_at(update->ntimestep)
{
  if (narg != 3)
    error->all(FLERR, (std::string("fix wirenet/kinetic: expected 'fix ID GROUP wirenet/kinetic' (no arguments; got '") +
                       arg[3] + "')").c_str());
  vector_flag = 1;
  size_vector = 4;   // stops, latest peak's kinetic energy, this step's kinetic energy, steps since the latest stop
  global_freq = 1;
  extvector = 0;
}

int FixWirenetKinetic::setmask()
{
  return END_OF_STEP;
}

void FixWirenetKinetic::init()
{
  if (!atom->rmass_flag || !atom->radius_flag)
    error->all(FLERR, "fix wirenet/kinetic: needs spheres (per-atom mass and radius)");
  rotational = atom->omega_flag;
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix wirenet/kinetic does not support run_style respa");
}

// A run starts from what it finds: the peak search begins again (a run may follow a change of
// masses or of the time step, which changes the energy's course).
void FixWirenetKinetic::setup(int)
{
  ke_now = kinetic_energy();
  ke_last = ke_now;
}

// The group's translational and rotational kinetic energy (spheres: I = 0.4 m r^2), all ranks.
double FixWirenetKinetic::kinetic_energy() const
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const double *rmass = atom->rmass, *radius = atom->radius;
  double **v = atom->v, **w = rotational ? atom->omega : NULL;
  double mine = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double *vi = v[i];
    double e = rmass[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
    if (w) {
      const double *wi = w[i];
      e += 0.4 * rmass[i] * radius[i] * radius[i] * (wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]);
    }
    mine += e;
  }
  double all = 0.0;
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return 0.5 * force->mvv2e * all;
}

void FixWirenetKinetic::stop_all()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double **v = atom->v, **w = rotational ? atom->omega : NULL;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (int k = 0; k < 3; k++) v[i][k] = 0.0;
    if (w)
      for (int k = 0; k < 3; k++) w[i][k] = 0.0;
  }
}

// The energy fell since the last step: it peaked in between; stop the group and look for the
// next peak from rest. (The velocities are the full step's here, after every fix's final
// integration: the next step starts from rest.)
void FixWirenetKinetic::end_of_step()
{
  ke_now = kinetic_energy();
  if (ke_now < ke_last) {
    stop_all();
    ke_peak = ke_last;
    ke_last = 0.0;
    stops++;
    stopped_at = update->ntimestep;
    return;
  }
  ke_last = ke_now;
}

// 1: stops so far; 2: the latest peak's kinetic energy [J] (0 before the first stop); 3: this
// step's kinetic energy before any stop [J]; 4: steps since the latest stop (since the fix was
// defined before the first)
double FixWirenetKinetic::compute_vector(int n)
{
  if (n == 0) return (double)stops;
  if (n == 1) return ke_peak;
  if (n == 2) return ke_now;
  return (double)(update->ntimestep - stopped_at);
}
