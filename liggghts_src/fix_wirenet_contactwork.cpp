/* WireNet: fix wirenet/contactwork. See doc/fix_wirenet_contactwork.md.

   A 'mark' instance copies the force and torque of every atom at its place in the post_force
   sequence; a 'since' instance, defined after the fixes to be measured, takes the increments
   since the mark and integrates their power with the velocities at the end of the step (the
   convention of fix wirenet/damping: F(t+dt) . v(t+dt) dt, which summed over all forces is the
   change of the half-step kinetic energy). */

#include "fix_wirenet_contactwork.h"

#include <cstring>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_wirenet_bonds.h"
#include "force.h"
#include "modify.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

FixWirenetContactWork::FixWirenetContactWork(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), is_mark(false), is_pair(false), bonds(NULL), mark(NULL), rotational(false),
  nheld(-1)
{
  const char *usage = "fix wirenet/contactwork: expected 'fix ID GROUP wirenet/contactwork mark', "
                      "'... since MARK-ID' or '... pair'";
  if (narg == 4 && strcmp(arg[3], "mark") == 0) {
    is_mark = true;
  } else if (narg == 4 && strcmp(arg[3], "pair") == 0) {
    is_pair = true;
  } else if (narg == 5 && strcmp(arg[3], "since") == 0) {
    mark_id = arg[4];
  } else if (narg >= 4 && strcmp(arg[3], "mark") != 0 && strcmp(arg[3], "since") != 0 &&
             strcmp(arg[3], "pair") != 0) {
    error->all(FLERR, (std::string("fix wirenet/contactwork: unknown mode '") + arg[3] +
                       "' (use 'mark', 'since MARK-ID' or 'pair')").c_str());
  } else {
    error->all(FLERR, usage);
  }
  for (int k = 0; k < 5; k++) sums_mine[k] = sums_all[k] = 0.0;
  if (!is_mark) {
    scalar_flag = 1;
    vector_flag = 1;
    size_vector = 5;
    global_freq = 1;
    extscalar = 1;
    extvector = 1;
    restart_global = 1;
  }
}

int FixWirenetContactWork::setmask()
{
  return is_mark ? POST_FORCE : (POST_FORCE | END_OF_STEP);
}

void FixWirenetContactWork::init()
{
  rotational = atom->torque_flag && atom->omega_flag;
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix wirenet/contactwork does not support run_style respa");
  if (is_mark) return;
  if (is_pair) {
    bonds = dynamic_cast<FixWirenetBonds *>(modify->find_fix_id("wirenet_bonds"));
    if (!bonds) error->all(FLERR, "fix wirenet/contactwork pair: needs bond_style wirenet (it takes the pair forces)");
    if (force->newton_pair)
      error->all(FLERR, "fix wirenet/contactwork pair: needs newton_pair off ('newton off on'): with newton_pair on the "
                        "pair forces of ghost atoms are not summed yet when they are taken");
    bonds->request_pair_forces();
    return;
  }
  const int imark = modify->find_fix(mark_id.c_str());
  if (imark < 0)
    error->all(FLERR, ("fix wirenet/contactwork: mark fix '" + mark_id + "' does not exist").c_str());
  mark = dynamic_cast<FixWirenetContactWork *>(modify->fix[imark]);
  if (!mark || !mark->is_mark)
    error->all(FLERR, ("fix wirenet/contactwork: fix '" + mark_id +
                       "' is not a 'fix wirenet/contactwork mark'").c_str());
  if (imark > modify->find_fix(id))
    error->all(FLERR, ("fix wirenet/contactwork: define the mark fix '" + mark_id +
                       "' before this fix (the measured fixes go between them)").c_str());
}

// The setup forces are taken too (they drive the first half step), but not accounted: the
// budget runs from the end of one step to the end of the next.
void FixWirenetContactWork::setup(int vflag)
{
  post_force(vflag);
  nheld = -1;
}

void FixWirenetContactWork::post_force(int)
{
  const int nlocal = atom->nlocal;
  double **f = atom->f, **t = rotational ? atom->torque : NULL;
  if (!is_pair) snap.resize(6 * (size_t)nlocal);
  if (is_mark) {
    for (int i = 0; i < nlocal; i++) {
      double *s = &snap[6 * (size_t)i];
      for (int k = 0; k < 3; k++) {
        s[k] = f[i][k];
        s[3 + k] = t ? t[i][k] : 0.0;
      }
    }
    return;
  }
  const int *mask = atom->mask;
  if (is_pair) {
    // the pair forces (force and torque when the bond style started, before any bond force)
    // stay in the bond fix until the end of the step: summed from there, not copied
    if (bonds->pair_forces().size() != 6 * (size_t)nlocal)
      error->one(FLERR, "fix wirenet/contactwork pair: no pair forces taken this step (atoms changed?)");
    nheld = nlocal;
    return;
  }
  const std::vector<double> &before = mark->snap;
  if (before.size() != snap.size())
    error->one(FLERR, "fix wirenet/contactwork: atoms changed between the mark fix and this one");
  for (int i = 0; i < nlocal; i++) {
    double *s = &snap[6 * (size_t)i];
    const double *b = &before[6 * (size_t)i];
    if (!(mask[i] & groupbit)) {
      for (int k = 0; k < 6; k++) s[k] = 0.0;
      continue;
    }
    for (int k = 0; k < 3; k++) {
      s[k] = f[i][k] - b[k];
      s[3 + k] = t ? t[i][k] - b[3 + k] : 0.0;
    }
  }
  nheld = nlocal;
}

void FixWirenetContactWork::end_of_step()
{
  if (nheld < 0) return;
  if (nheld != atom->nlocal) error->one(FLERR, "fix wirenet/contactwork: atoms changed between force and end of step");
  const double dt = update->dt;
  double **v = atom->v, **w = rotational ? atom->omega : NULL;
  // this step's sums in registers, then added to the totals (a member sum would be stored and
  // reloaded at every atom: a chain through memory; the totals' last digits differ from an
  // atom-by-atom sum, as in fix wirenet/damping)
  double work_f = 0.0, work_t = 0.0, jx = 0.0, jy = 0.0, jz = 0.0;
  // 'since' zeroed the increments of atoms outside the group; 'pair' reads the bond fix's record
  const double *s = is_pair ? bonds->pair_forces().data() : snap.data();
  const int *mask = atom->mask;
  const int masked = is_pair && igroup != 0;  // group all: every atom counts
  for (int i = 0; i < nheld; i++, s += 6) {
    if (masked && !(mask[i] & groupbit)) continue;
    const double *vi = v[i];
    work_f += s[0] * vi[0] + s[1] * vi[1] + s[2] * vi[2];
    if (w) work_t += s[3] * w[i][0] + s[4] * w[i][1] + s[5] * w[i][2];
    jx += s[0];
    jy += s[1];
    jz += s[2];
  }
  sums_mine[0] += dt * work_f;
  sums_mine[1] += dt * work_t;
  sums_mine[2] += dt * jx;
  sums_mine[3] += dt * jy;
  sums_mine[4] += dt * jz;
  nheld = -1;
}

void FixWirenetContactWork::reduce()
{
  MPI_Allreduce(sums_mine, sums_all, 5, MPI_DOUBLE, MPI_SUM, world);
}

double FixWirenetContactWork::compute_scalar()
{
  reduce();
  return sums_all[0] + sums_all[1];
}

double FixWirenetContactWork::compute_vector(int n)
{
  reduce();
  return sums_all[n];
}

// The totals go to rank 0's share on restart; the other ranks start from zero.
void FixWirenetContactWork::write_restart(FILE *fp)
{
  reduce();
  if (comm->me != 0) return;
  int n = 5 * sizeof(double);
  fwrite(&n, sizeof(int), 1, fp);
  fwrite(sums_all, sizeof(double), 5, fp);
}

void FixWirenetContactWork::restart(char *buf)
{
  const double *list = (const double *)buf;
  for (int k = 0; k < 5; k++) sums_mine[k] = comm->me == 0 ? list[k] : 0.0;
}
