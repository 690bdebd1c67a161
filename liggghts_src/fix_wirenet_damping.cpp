/* WireNet: fix wirenet/damping. See doc/fix_wirenet_damping.md.

   Each component of the force on a node is reduced by ALPHA times its magnitude against the
   velocity component (PFC's local damping); the torque likewise against the angular velocity.
   The work of the damping is accounted with the velocity of the same instant, which velocity
   Verlet knows only at the end of the step. */

#include "fix_wirenet_damping.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"
#include "wirenet_fix_args.h"
#include "wirenet_local_damping.h"

using namespace LAMMPS_NS;
using namespace FixConst;

using WireNet::local_damping;

FixWirenetDamping::FixWirenetDamping(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), alpha(0.0), viscous(0.0), rotational(false), tally(true), integrate(false), dtv(0.0), dtf(0.0),
  kicks_at(-1), turning_step(-1), turning_nlocal(-1), ndamped(-1)
{
  if (narg < 4 || narg % 2 != 0)
    error->all(FLERR, "fix wirenet/damping: expected 'fix ID GROUP wirenet/damping ALPHA [tally yes|no] [integrate yes|no] [viscous C]'");
  char *end = NULL;
  errno = 0;
  alpha = strtod(arg[3], &end);
  if (errno || end == arg[3] || *end != '\0') {
    std::string msg = std::string("fix wirenet/damping: ALPHA must be a number (got '") + arg[3] + "')";
    error->all(FLERR, msg.c_str());
  }
  if (!(alpha >= 0.0 && alpha < 1.0)) {
    std::string msg = std::string("fix wirenet/damping: ALPHA must be in [0, 1) (got ") + arg[3] + ")";
    error->all(FLERR, msg.c_str());
  }

  for (int k = 4; k + 1 < narg; k += 2) {
    if (strcmp(arg[k], "viscous") == 0) {
      try {
        int kv = k;
        viscous = WireNet::FixArgs::value(narg, arg, kv, "viscous", 0.0, false);
      } catch (const std::invalid_argument &e) {
        error->all(FLERR, (std::string("fix wirenet/damping: ") + e.what()).c_str());
      }
      continue;
    }
    const bool is_tally = strcmp(arg[k], "tally") == 0, is_integrate = strcmp(arg[k], "integrate") == 0;
    if (!is_tally && !is_integrate) {
      std::string msg = std::string("fix wirenet/damping: unknown keyword '") + arg[k] + "' (expected tally, integrate or viscous)";
      error->all(FLERR, msg.c_str());
    }
    if (strcmp(arg[k + 1], "yes") != 0 && strcmp(arg[k + 1], "no") != 0) {
      std::string msg = std::string("fix wirenet/damping: ") + arg[k] + " must be yes or no (got '" + arg[k + 1] + "')";
      error->all(FLERR, msg.c_str());
    }
    (is_tally ? tally : integrate) = strcmp(arg[k + 1], "yes") == 0;
  }
  time_integrate = integrate ? 1 : 0;

  // without the tally there is no work or impulse: a reference to f_ID stops the run (reduce_work)
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 5;   // work of forces, work of torques, impulse x y z of the forces
  global_freq = 1;
  extscalar = 1;
  extvector = 1;
  restart_global = tally ? 1 : 0;
  work_mine[0] = work_mine[1] = 0.0;
  work_all[0] = work_all[1] = 0.0;
  for (int k = 0; k < 3; k++) impulse_mine[k] = impulse_all[k] = 0.0;
}

int FixWirenetDamping::setmask()
{
  const int damping = integrate ? INITIAL_INTEGRATE | FINAL_INTEGRATE : POST_FORCE;
  return tally ? damping | END_OF_STEP : damping;
}

void FixWirenetDamping::init()
{
  rotational = atom->torque_flag && atom->omega_flag;
  if (viscous > 0.0 && (!atom->rmass_flag || !atom->radius_flag))
    error->all(FLERR, "fix wirenet/damping: 'viscous' needs spheres (per-atom mass and radius)");
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix wirenet/damping does not support run_style respa");
  if (integrate) {
    if (!atom->rmass_flag || !atom->radius_flag || !rotational)
      error->all(FLERR, "fix wirenet/damping: 'integrate yes' needs spheres (per-atom mass, radius, angular velocity and torque, as nve/sphere)");
    if (domain->dimension != 3) error->all(FLERR, "fix wirenet/damping: 'integrate yes' is for 3-d runs");
    reset_dt();
    return;   // it damps in final_integrate, when every force of the step is in
  }

  // Forces added after this fix are not damped; say so for the usual suspects.
  int me = modify->find_fix(id);
  for (int k = me + 1; k < modify->nfix; k++) {
    Fix *other = modify->fix[k];
    if (!(other->setmask() & POST_FORCE)) continue;
    if (strcmp(other->style, "setforce") == 0 || strncmp(other->style, "wirenet/", 8) == 0) continue;
    if (comm->me == 0) {
      std::string msg = std::string("fix wirenet/damping: fix ") + other->id + " (" + other->style +
                        ") comes later and its forces are not damped; define wirenet/damping after it";
      error->warning(FLERR, msg.c_str());
    }
  }
}

// The setup force is damped too (it drives the first half step), but its work is not accounted:
// the budget runs from the end of one step to the end of the next.
void FixWirenetDamping::setup(int vflag)
{
  post_force(vflag);
  ndamped = -1;
}

void FixWirenetDamping::post_force(int)
{
  damp_all<false>();
}

void FixWirenetDamping::reset_dt()
{
  dtv = update->dt;
  dtf = 0.5 * update->dt * force->ftm2v;
  kicks_at = -1;
}

// dt/2m and dt/2I of every local atom, the two divisions of each kick, once per neighbour-list
// build (atoms change places only then) instead of twice per step. The same arithmetic as
// nve/sphere, so the same bits. reset_dt clears them: a new time step, and every run's init,
// which sees a mass set between runs ('run pre no' after such a change is an input error,
// LIGGGHTS' run doc). The build count alone would not: LIGGGHTS starts it from 0 at each set-up.
// dt/2m is kept once per force component, so that the kick is a pass over the flat arrays.
void FixWirenetDamping::renew_kicks()
{
  const int nlocal = atom->nlocal;
  if (kicks_at == neighbor->ncalls && kick_w.size() == (size_t)nlocal) return;
  kick_v.resize(3 * (size_t)nlocal);
  kick_w.resize((size_t)nlocal);
  const double *rmass = atom->rmass, *radius = atom->radius;
  const double dtfrotate = dtf / 0.4;   // nve/sphere's I = 0.4 m r^2
  for (int i = 0; i < nlocal; i++) {
    const double dtfm = dtf / rmass[i];
    for (int k = 0; k < 3; k++) kick_v[3 * i + k] = dtfm;
    kick_w[i] = dtfrotate / (radius[i] * radius[i] * rmass[i]);
  }
  kicks_at = neighbor->ncalls;
}

// The first half kick of atom i's angular velocity.
inline void FixWirenetDamping::kick_torque(int i)
{
  const double *ti = atom->torque[i];
  double *wi = atom->omega[i];
  for (int k = 0; k < 3; k++) wi[k] += kick_w[i] * ti[k];
}

// integrate: the first half kick and the drift, with the damped force of the last step (as
// nve/sphere, the same arithmetic: I = 0.4 m r^2)
void FixWirenetDamping::initial_integrate(int)
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  double **x = atom->x, **v = atom->v, **f = atom->f, **t = atom->torque;
  renew_kicks();
  const double dt = dtv;   // a local: the writes below could alias the member
  if (igroup == 0 && nlocal > 0) {
    // group all: every component's kick and drift is independent of the others, one
    // elementwise pass over the flat arrays (LAMMPS' 2-d arrays are one block), which the
    // compiler vectorises
    double *__restrict xf = x[0], *__restrict vf = v[0];
    const double *__restrict ff = f[0], *__restrict kv = kick_v.data();
    for (int c = 0; c < 3 * nlocal; c++) {
      const double vl = vf[c] + kv[c] * ff[c];
      vf[c] = vl;
      xf[c] += dt * vl;
    }
  } else {
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit)) continue;
      // in locals, stored at the end (the arrays could alias: no reload between components)
      const double *fi = f[i], *kv = &kick_v[3 * i];
      double *vi = v[i], *xi = x[i];
      const double vl[3] = { vi[0] + kv[0] * fi[0], vi[1] + kv[1] * fi[1], vi[2] + kv[2] * fi[2] };
      const double xl[3] = { xi[0] + dt * vl[0], xi[1] + dt * vl[1], xi[2] + dt * vl[2] };
      for (int k = 0; k < 3; k++) vi[k] = vl[k];
      for (int k = 0; k < 3; k++) xi[k] = xl[k];
    }
  }
  // the atoms with a torque, listed by the damping at the end of the last step (atoms move
  // between ranks and places only after this pass); otherwise each atom's torque is looked at
  // (w += 0 where there is none)
  if (turning_step == update->ntimestep - 1 && turning_nlocal == nlocal) {
    for (const int i : turning) kick_torque(i);
    return;
  }
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double *ti = t[i];
    if (ti[0] == 0.0 && ti[1] == 0.0 && ti[2] == 0.0) continue;
    kick_torque(i);
  }
}

void FixWirenetDamping::final_integrate()
{
  damp_all<true>();
}

// The loop instantiated for the options of this fix: a run without viscous damping does not
// multiply every component by a zero coefficient.
template <bool KICK>
void FixWirenetDamping::damp_all()
{
  // ALPHA 0 without a viscous part (the physical model's impacts: the fix is their integrator)
  // damps nothing: each component's damping is a zero, its work and impulse zero. The kick
  // alone then, the same bits (f + 0 = f), without the damping's pass and its tally.
  if (alpha == 0.0 && viscous == 0.0) {
    if (KICK) kick_all();
    return;
  }
  if (viscous > 0.0) {
    if (tally) damp<true, KICK, true>();
    else damp<false, KICK, true>();
  } else {
    if (tally) damp<true, KICK, false>();
    else damp<false, KICK, false>();
  }
}

// One atom's force (or torque) g, damped against its velocity (or angular velocity) u: the local
// damping and, with VISC, the viscous part -c u; the damping into d with TALLY; with KICK the
// half kick u += k g with the damped g. In locals, stored at the end: the arrays could alias, so
// writing one component in place would make the compiler reload the next.
template <bool TALLY, bool KICK, bool VISC>
static inline void damp_vector(double *g, double *u, double a, double c, double k, double *d)
{
  double gl[3] = { g[0], g[1], g[2] }, ul[3] = { u[0], u[1], u[2] };
  for (int n = 0; n < 3; n++) {
    double dn = local_damping(gl[n], ul[n], a);
    if (VISC) dn -= c * ul[n];
    if (TALLY) d[n] = dn;
    gl[n] += dn;
    if (KICK) ul[n] += k * gl[n];
  }
  for (int n = 0; n < 3; n++) g[n] = gl[n];
  if (KICK)
    for (int n = 0; n < 3; n++) u[n] = ul[n];
}

// The damping of every atom of the group; TALLY keeps each atom's damping force and torque for
// end_of_step (the work and impulse), a 48-byte write per atom that a run without the budget
// does not need. KICK (integrate yes, from final_integrate: every force of the step is in) also
// gives the second half kick with the damped force in the same pass; the damped force stays in
// the atom's force for the next step's first half kick.
template <bool TALLY, bool KICK, bool VISC>
void FixWirenetDamping::damp()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  // the per-atom arrays are read once: the force writes below could alias atom's members, which
  // would make the compiler reload them at every atom
  double **f = atom->f, **v = atom->v;
  const double *rmass = VISC ? atom->rmass : NULL;
  if (KICK) renew_kicks();
  const double a = alpha, c = viscous;
  // every entry is written below: grow only, no clearing pass
  if (TALLY && fdamp_f.size() < 3 * (size_t)nlocal) {
    fdamp_f.resize(3 * (size_t)nlocal);
    fdamp_t.resize(3 * (size_t)nlocal);
  }
  if (integrate) {
    turning.clear();
    turning.reserve(nlocal);   // no allocation in the loop
  }
  if (!VISC && igroup == 0) {
    if (nlocal > 0) damp_forces_flat<TALLY, KICK>();
    if (rotational)
      for (int i = 0; i < nlocal; i++) damp_torque<TALLY, KICK, false>(i, 0.0);
    else if (TALLY)
      for (int i = 0; i < 3 * nlocal; i++) fdamp_t[i] = 0.0;
  } else {
    for (int i = 0; i < nlocal; i++) {
      double *fd = TALLY ? &fdamp_f[3 * i] : NULL, *td = TALLY ? &fdamp_t[3 * i] : NULL;
      if (!(mask[i] & groupbit)) {
        if (TALLY)
          for (int k = 0; k < 3; k++) fd[k] = td[k] = 0.0;
        continue;
      }
      const double cm = VISC ? c * rmass[i] : 0.0;
      damp_vector<TALLY, KICK, VISC>(f[i], v[i], a, cm, KICK ? kick_v[3 * i] : 0.0, fd);
      if (rotational) damp_torque<TALLY, KICK, VISC>(i, cm);
      else if (TALLY)
        for (int k = 0; k < 3; k++) td[k] = 0.0;
    }
  }
  if (TALLY) ndamped = nlocal;
  if (integrate) {
    turning_step = update->ntimestep;
    turning_nlocal = nlocal;
  }
}

// The second half kick alone (no damping): v += dt/2m f and w += dt/2I t, the torques of the
// atoms that have one (listed for the next step's first half kick, as damp() lists them).
void FixWirenetDamping::kick_all()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  renew_kicks();
  if (igroup == 0 && nlocal > 0) {
    double *__restrict vf = atom->v[0];
    const double *__restrict ff = atom->f[0], *__restrict kv = kick_v.data();
    for (int c = 0; c < 3 * nlocal; c++) vf[c] += kv[c] * ff[c];
  } else {
    double **f = atom->f, **v = atom->v;
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit)) continue;
      for (int k = 0; k < 3; k++) v[i][k] += kick_v[3 * i + k] * f[i][k];
    }
  }
  turning.clear();
  turning.reserve(nlocal);
  if (rotational) {
    double **t = atom->torque;
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit)) continue;
      const double *ti = t[i];
      if (ti[0] == 0.0 && ti[1] == 0.0 && ti[2] == 0.0) continue;
      kick_torque(i);
      turning.push_back(i);
    }
  }
  turning_step = update->ntimestep;
  turning_nlocal = nlocal;
}

// Group all, no viscous part: each force component's damping and kick depends on that
// component alone, so the forces are one elementwise pass over the flat arrays, two components
// at a time (the same operations in the same order as damp()'s per-atom loop, so the same
// bits). The torques follow per atom: most nodes of a net have none.
template <bool TALLY, bool KICK>
void FixWirenetDamping::damp_forces_flat()
{
  const int n = 3 * atom->nlocal;
  double *__restrict f = atom->f[0], *__restrict v = atom->v[0];
  const double *__restrict kv = KICK ? kick_v.data() : NULL;
  double *__restrict fd = TALLY ? fdamp_f.data() : NULL;
  const double a = alpha;
  const WireNet::Lanes al = { a, a };
  int c = 0;
  for (; c + 2 <= n; c += 2) {
    const WireNet::Lanes fl0 = { f[c], f[c + 1] }, vl = { v[c], v[c + 1] };
    const WireNet::Lanes d = local_damping(fl0, vl, al), fl = fl0 + d;
    if (TALLY) fd[c] = d[0], fd[c + 1] = d[1];
    f[c] = fl[0], f[c + 1] = fl[1];
    if (KICK) {
      const WireNet::Lanes vn = vl + WireNet::Lanes{ kv[c], kv[c + 1] } * fl;
      v[c] = vn[0], v[c + 1] = vn[1];
    }
  }
  for (; c < n; c++) {   // the last component when 3 nlocal is odd
    const double vl = v[c];
    const double d = local_damping(f[c], vl, a);
    const double fl = f[c] + d;
    if (TALLY) fd[c] = d;
    f[c] = fl;
    if (KICK) v[c] = vl + kv[c] * fl;
  }
}

// Atom i's damping torque (with the viscous part cm = C m) and, with KICK, its second half kick.
// No torque (a node held by wires alone, which pull along their axis) and no viscous part:
// no damping torque and no kick, and its angular velocity is not read. The same bits as the
// full update, in which -alpha |0| sign(w) and dt/2I * 0 add only zeros (a zero's sign aside).
template <bool TALLY, bool KICK, bool VISC>
inline void FixWirenetDamping::damp_torque(int i, double cm)
{
  double *ti = atom->torque[i];
  double *td = TALLY ? &fdamp_t[3 * i] : NULL;
  if (!VISC && ti[0] == 0.0 && ti[1] == 0.0 && ti[2] == 0.0) {
    if (TALLY) td[0] = td[1] = td[2] = 0.0;
    return;
  }
  const double radius = VISC ? atom->radius[i] : 0.0;
  const double ci = VISC ? 0.4 * cm * radius * radius : 0.0;
  damp_vector<TALLY, KICK, VISC>(ti, atom->omega[i], alpha, ci, KICK ? kick_w[i] : 0.0, td);
  if (integrate && (ti[0] != 0.0 || ti[1] != 0.0 || ti[2] != 0.0)) turning.push_back(i);
}

// F(t+dt) . v(t+dt) dt with the full-step velocity: summed over all forces this equals the change of
// the half-step kinetic energy exactly, so energy budgets built from such terms close.
void FixWirenetDamping::end_of_step()
{
  if (ndamped < 0) return;
  if (ndamped != atom->nlocal) error->one(FLERR, "fix wirenet/damping: atoms changed between force and end of step");
  const double dt = update->dt;
  double **v = atom->v;
  double **w = rotational ? atom->omega : NULL;
  // this step's sums in locals (the members would be written back at every atom), then added to
  // the totals: the totals' round-off differs from an atom-by-atom sum in the last digits
  double work_f = 0.0, work_t = 0.0, jx = 0.0, jy = 0.0, jz = 0.0;
  const double *fd = fdamp_f.data(), *td = fdamp_t.data();
  for (int i = 0; i < ndamped; i++, fd += 3, td += 3) {
    const double *vi = v[i];
    work_f += dt * (fd[0] * vi[0] + fd[1] * vi[1] + fd[2] * vi[2]);
    jx += dt * fd[0];
    jy += dt * fd[1];
    jz += dt * fd[2];
    if (w) {
      const double *wi = w[i];
      work_t += dt * (td[0] * wi[0] + td[1] * wi[1] + td[2] * wi[2]);
    }
  }
  work_mine[0] += work_f;
  work_mine[1] += work_t;
  impulse_mine[0] += jx;
  impulse_mine[1] += jy;
  impulse_mine[2] += jz;
  ndamped = -1;
}

void FixWirenetDamping::reduce_work()
{
  if (!tally) {
    std::string msg = std::string("fix wirenet/damping: fix ") + id +
                      " keeps no work or impulse (tally no); give it 'tally yes' to output f_" + id;
    error->all(FLERR, msg.c_str());
  }
  MPI_Allreduce(work_mine, work_all, 2, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(impulse_mine, impulse_all, 3, MPI_DOUBLE, MPI_SUM, world);
}

double FixWirenetDamping::compute_scalar()
{
  reduce_work();
  return work_all[0] + work_all[1];
}

double FixWirenetDamping::compute_vector(int n)
{
  reduce_work();
  return n < 2 ? work_all[n] : impulse_all[n - 2];
}

// The totals go to rank 0's share on restart; the other ranks start from zero.
void FixWirenetDamping::write_restart(FILE *fp)
{
  reduce_work();
  if (comm->me != 0) return;
  const double list[5] = { work_all[0], work_all[1], impulse_all[0], impulse_all[1], impulse_all[2] };
  int n = 5 * sizeof(double);
  fwrite(&n, sizeof(int), 1, fp);
  fwrite(list, sizeof(double), 5, fp);
}

void FixWirenetDamping::restart(char *buf)
{
  const double *list = (const double *)buf;
  work_mine[0] = comm->me == 0 ? list[0] : 0.0;
  work_mine[1] = comm->me == 0 ? list[1] : 0.0;
  for (int k = 0; k < 3; k++) impulse_mine[k] = comm->me == 0 ? list[2 + k] : 0.0;
}
