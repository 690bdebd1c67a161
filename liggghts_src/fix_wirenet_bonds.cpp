/* WireNet: per-bond history and node orientations for bond_style wirenet.

   Each atom carries one history record per bond slot, aligned with atom->bond_atom[i][m], so the
   records travel with the bonds they belong to (exchange, sort, restart). A bond that ruptures is
   flagged in its record and removed from the atom's bond list at the next exchange, when the bond
   style's list is rebuilt anyway. */

#include "fix_wirenet_bonds.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "atom.h"
#include "bond_wirenet.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "update.h"
#include "wirenet_fix_args.h"

using namespace LAMMPS_NS;
using namespace FixConst;

static const int RUPTURE_COLS = 8;

FixWirenetBonds::FixWirenetBonds(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  hist(NULL), quat(NULL), rot(NULL), orient_flag(0), vel_flag(0), version(0), ghost_extent(0.0), reach_grown(false),
  nbroken_total(0), nbroken_pending(0), elastic_step(-1), pair_wanted(false), damping_source(nullptr), damping_tally(true), law_scale_(1.0), maxlocal(0)
{
  if (narg != 3) error->all(FLERR, "fix wirenet/bonds takes no arguments (it is created by bond_style wirenet)");
  if (!atom->molecular) error->all(FLERR, "fix wirenet/bonds needs an atom style with bonds");

  restart_global = 1;
  restart_peratom = 1;
  // Not create_attribute: LIGGGHTS' Modify::setup() would then re-initialise every atom of a new
  // fix after the setup force pass, wiping the initial lengths just taken. Atoms present now are
  // initialised here; nets gain no bonded atoms during a run.
  create_attribute = 0;
  scalar_flag = 1;
  extscalar = 0;
  // global vector: broken bonds, energy released at ruptures, plastic work of the wire bonds,
  // energy dissipated by bond damping
  vector_flag = 1;
  size_vector = 1 + NTALLY;
  extvector = 0;
  // global array, a row per bond type: elastic energy, then the three tallies
  array_flag = 1;
  size_array_rows = atom->nbondtypes;
  size_array_cols = 1 + NTALLY;
  extarray = 0;
  tally_mine.assign((size_t)(atom->nbondtypes + 1) * NTALLY, 0.0);
  elastic_mine.assign((size_t)atom->nbondtypes + 1, 0.0);
  global_freq = 1;
  local_flag = 1;
  // The rupture rows are current at every step. Fix() leaves both frequencies uninitialised;
  // dump local checks local_freq and compute reduce checks peratom_freq, even for local data.
  local_freq = 1;
  peratom_freq = 1;
  size_local_cols = RUPTURE_COLS;
  size_local_rows = 0;
  array_local = NULL;
  comm_forward = 6;   // the most sent per ghost: velocity and omega (6), or a beam-end mark (1)
  comm_reverse = 1;   // beam-end marks of ghost atoms, to their owners (find_beam_ends)
  comm_border = 4;    // orientation of a new ghost (advanced in step with its owner after that)

  nslots = atom->bond_per_atom;
  grow_arrays(atom->nmax);
  atom->add_callback(0);
  atom->add_callback(1);
  atom->add_callback(2);
  for (int i = 0; i < atom->nlocal; i++) reset_atom(i);
}

FixWirenetBonds::~FixWirenetBonds()
{
  atom->delete_callback(id, 0);
  atom->delete_callback(id, 1);
  atom->delete_callback(id, 2);
  memory->destroy(hist);
  memory->destroy(quat);
  memory->destroy(rot);
  memory->destroy(array_local);
}

int FixWirenetBonds::setmask()
{
  return PRE_EXCHANGE | PRE_NEIGHBOR | PRE_FORCE | END_OF_STEP | POST_RUN;
}

void FixWirenetBonds::init()
{
  if (atom->bond_per_atom != nslots)
    error->all(FLERR, "bond_style wirenet: bonds per atom changed after the bond history was created "
                      "(adding bonds after a run is not supported)");
}

/* ------------------------------------------------------------------------------------------- */

void FixWirenetBonds::reset_atom(int i)
{
  if (nslots) memset(hist[i], 0, sizeof(double) * nslots * NHIST);
  quat[i][0] = 1.0;
  quat[i][1] = quat[i][2] = quat[i][3] = 0.0;
}

void FixWirenetBonds::grow_arrays(int nmax)
{
  memory->grow(hist, nmax, nslots > 0 ? nslots * NHIST : 1, "wirenet/bonds:hist");
  memory->grow(quat, nmax, 4, "wirenet/bonds:quat");
  memory->grow(rot, nmax, 9, "wirenet/bonds:rot");
}

void FixWirenetBonds::copy_arrays(int i, int j, int)
{
  if (nslots) memcpy(hist[j], hist[i], sizeof(double) * nslots * NHIST);
  memcpy(quat[j], quat[i], sizeof(double) * 4);
}

int FixWirenetBonds::pack_exchange(int i, double *buf)
{
  int m = 0;
  for (int k = 0; k < nslots * NHIST; k++) buf[m++] = hist[i][k];
  for (int k = 0; k < 4; k++) buf[m++] = quat[i][k];
  return m;
}

int FixWirenetBonds::unpack_exchange(int i, double *buf)
{
  int m = 0;
  for (int k = 0; k < nslots * NHIST; k++) hist[i][k] = buf[m++];
  for (int k = 0; k < 4; k++) quat[i][k] = buf[m++];
  return m;
}

int FixWirenetBonds::pack_restart(int i, double *buf)
{
  int m = 1;
  for (int k = 0; k < nslots * NHIST; k++) buf[m++] = hist[i][k];
  for (int k = 0; k < 4; k++) buf[m++] = quat[i][k];
  buf[0] = m;
  return m;
}

void FixWirenetBonds::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(extra[nlocal][m]) != maxsize_restart())
    error->one(FLERR, "bond_style wirenet: the restart file's bond history does not match the bonds per atom");
  m++;
  for (int k = 0; k < nslots * NHIST; k++) hist[nlocal][k] = extra[nlocal][m++];
  for (int k = 0; k < 4; k++) quat[nlocal][k] = extra[nlocal][m++];
}

int FixWirenetBonds::size_restart(int) { return maxsize_restart(); }
int FixWirenetBonds::maxsize_restart() { return 1 + nslots * NHIST + 4; }

// Forward messages: velocities and angular velocities when LIGGGHTS does not send them itself
// (bond damping, orientations without 'vel yes').
int FixWirenetBonds::pack_comm(int n, int *list, double *buf, int, int *)
{
  int m = 0;
  double **v = atom->v, **omega = atom->omega;
  for (int k = 0; k < n; k++) {
    const int i = list[k];
    for (int c = 0; c < 3; c++) buf[m++] = v[i][c];
    for (int c = 0; c < 3; c++) buf[m++] = omega[i][c];
  }
  return 6;  // values per atom (LIGGGHTS' forward_comm_fix convention)
}

void FixWirenetBonds::unpack_comm(int n, int first, double *buf)
{
  int m = 0;
  double **v = atom->v, **omega = atom->omega;
  for (int i = first; i < first + n; i++) {
    for (int c = 0; c < 3; c++) v[i][c] = buf[m++];
    for (int c = 0; c < 3; c++) omega[i][c] = buf[m++];
  }
}

int FixWirenetBonds::pack_border(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++)
    for (int c = 0; c < 4; c++) buf[m++] = quat[list[k]][c];
  return m;
}

int FixWirenetBonds::unpack_border(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int c = 0; c < 4; c++) quat[i][c] = buf[m++];
  return m;
}

// Layout: { -(number of values that follow), broken bonds, the three tallies' sums, number of
// bond types, the tallies of rows 0..types, the laws' scale (fix_modify scale: the bonds'
// states are at it) }; files without the scale are at scale 1. Files written before the per-type tallies end
// after the sums (and before the damping tally, files hold { broken bonds (>= 0), released
// energy, plastic work }): the sign of the first value and the count tell them apart
// (restart() is not told the size of its state).
void FixWirenetBonds::write_restart(FILE *fp)
{
  const int ntypes = atom->nbondtypes;
  sync_tallies();
  std::vector<double> all(tally_mine.size());
  MPI_Reduce(tally_mine.data(), all.data(), (int)all.size(), MPI_DOUBLE, MPI_SUM, 0, world);
  if (comm->me != 0) return;
  std::vector<double> list = { 0.0, (double)nbroken_total };
  for (int k = 0; k < NTALLY; k++) {
    double sum = 0.0;
    for (int t = 0; t <= ntypes; t++) sum += all[(size_t)t * NTALLY + k];
    list.push_back(sum);
  }
  list.push_back(ntypes);
  list.insert(list.end(), all.begin(), all.end());
  list.push_back(law_scale_);
  list[0] = -(double)(list.size() - 1);
  // Modify::read_restart reads this many BYTES of state (not values).
  int size = (int)(sizeof(double) * list.size());
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(list.data(), sizeof(double), list.size(), fp);
}

// The tallies go to rank 0's share; the other ranks start from zero. An older file's sums go
// to row 0 (no type).
void FixWirenetBonds::restart(char *buf)
{
  const double *list = (const double *)buf;
  int n = 3;  // oldest layout: count, released energy, plastic work
  if (list[0] < 0.0) {
    n = (int)(-list[0]);
    list++;
  }
  nbroken_total = (bigint)list[0];
  std::fill(tally_mine.begin(), tally_mine.end(), 0.0);
  const int ntypes = atom->nbondtypes;
  const int n_tallies = 2 + NTALLY + (ntypes + 1) * NTALLY;
  law_scale_ = n == n_tallies + 1 ? list[n_tallies] : 1.0;
  if (comm->me != 0) return;
  if (n > 1 + NTALLY) {
    if ((int)list[1 + NTALLY] != ntypes || (n != n_tallies && n != n_tallies + 1))
      error->one(FLERR, "bond_style wirenet: the restart file's energy tallies are for another number of bond types");
    for (size_t k = 0; k < tally_mine.size(); k++) tally_mine[k] = list[2 + NTALLY + k];
  } else {
    for (int k = 0; k < NTALLY; k++) tally_mine[k] = 1 + k < n ? list[1 + k] : 0.0;
  }
}

/* ------------------------------------------------------------------------------------------- */

// The rupture record goes straight into the local array that dump local reads: one row appended,
// storage doubled when full (ruptures come in bursts when a net tears).
void FixWirenetBonds::break_bond(int i, int m, const double *mid, double elongation, double energy)
{
  hist[i][m * NHIST + L0] = -1.0;
  add_tally(atom->bond_type[i][m], RELEASED, energy);
  nbroken_pending++;
  const int n = size_local_rows;
  if (n == maxlocal) {
    maxlocal = maxlocal ? 2 * maxlocal : 64;
    memory->grow(array_local, maxlocal, RUPTURE_COLS, "wirenet/bonds:ruptures");
  }
  double *row = array_local[n];
  row[0] = update->ntimestep;
  row[1] = atom->tag[i];
  row[2] = atom->bond_atom[i][m];
  row[3] = atom->bond_type[i][m];
  row[4] = mid[0]; row[5] = mid[1]; row[6] = mid[2];
  row[7] = elongation;
  size_local_rows = n + 1;
}

// Remove flagged bonds from the owning atoms, keeping bond slots and history records aligned.
// scan_all: look at every record, not only when this rank flagged bonds itself. Needed at setup:
// a restart file written by the `restart` command in the middle of a run holds bonds flagged
// at that step, which the new process has never counted as pending.
void FixWirenetBonds::remove_broken_bonds(bool scan_all)
{
  int removed = 0;
  if (nbroken_pending || scan_all) {
    int *num_bond = atom->num_bond;
    int **bond_type = atom->bond_type;
    int **bond_atom = atom->bond_atom;
    for (int i = 0; i < atom->nlocal; i++) {
      for (int m = 0; m < num_bond[i];) {
        if (hist[i][m * NHIST + L0] >= 0.0) { m++; continue; }
        const int last = num_bond[i] - 1;
        bond_type[i][m] = bond_type[i][last];
        bond_atom[i][m] = bond_atom[i][last];
        memcpy(&hist[i][m * NHIST], &hist[i][last * NHIST], sizeof(double) * NHIST);
        memset(&hist[i][last * NHIST], 0, sizeof(double) * NHIST);
        num_bond[i]--;
        removed++;
      }
    }
    nbroken_pending = 0;
  }
  int all = 0;
  MPI_Allreduce(&removed, &all, 1, MPI_INT, MPI_SUM, world);
  if (all) {
    atom->nbonds -= all;
    nbroken_total += all;
    version++;
  }
}

void FixWirenetBonds::setup_pre_exchange() { remove_broken_bonds(true); }

void FixWirenetBonds::pre_exchange()
{
  remove_broken_bonds(false);
  // the slabs of the ghost exchange that follows (borders) take the grown reach; every rank
  // decided alike (follow_bond_reach), and Comm::setup() is collective
  if (reach_grown) comm->setup();
  reach_grown = false;
}
// The plastic-work tally is summed from the bonds' state when it is read (BondWirenet::
// sync_plastic): before every read and write of the tallies, and at the end of a run, while the
// bond style's list still matches the bonds.
void FixWirenetBonds::sync_tallies()
{
  if (BondWirenet *bond = dynamic_cast<BondWirenet *>(force->bond)) bond->sync_plastic();
}

// The bond dampers' tally (request_damping_tally): the ghosts' velocities and angular velocities
// are the half-step ones LIGGGHTS sent before the forces; their owners have the full-step ones now.
void FixWirenetBonds::end_of_step()
{
  if (!damping_source) return;
  comm->forward_comm_fix(this);
  damping_source->tally_damping();
  damping_source = nullptr;
}

// fix_modify wirenet_bonds damping_tally yes|no: between runs only; a run's set-up restarts the
// tally's half-step bookkeeping (BondWirenet::tally_damping), so switching it on loses nothing
// of the steps after it.
// fix_modify wirenet_bonds scale S: the wire and brake laws at S times their scale from the next
// run on (WireLaw::prepare), the beams' strengths S times (BeamLaw::prepare); every wire bond's
// state goes from the old scale to S, so a bond keeps its place on its envelope: under S times
// the loads a net is as far from yield and rupture as under its own (a settling under a heavier
// weight, doc/fix_wirenet_bonds.md).
int FixWirenetBonds::modify_param(int narg, char **arg)
{
  const bool tally = strcmp(arg[0], "damping_tally") == 0;
  if (!tally && strcmp(arg[0], "scale") != 0)
    error->all(FLERR, (std::string("fix_modify wirenet_bonds: unknown keyword '") + arg[0] +
                       "' (expected damping_tally or scale)").c_str());
  if (tally) {
    if (narg < 2) error->all(FLERR, "fix_modify wirenet_bonds: expected 'fix_modify wirenet_bonds damping_tally yes|no'");
    if (strcmp(arg[1], "yes") != 0 && strcmp(arg[1], "no") != 0)
      error->all(FLERR, (std::string("fix_modify wirenet_bonds: damping_tally must be yes or no (got '") + arg[1] +
                         "')").c_str());
    damping_tally = strcmp(arg[1], "yes") == 0;
    return 2;
  }
  double s = 0.0;
  try {
    int k = 0;
    s = WireNet::FixArgs::value(narg, arg, k, "scale", 0.0, true);
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, (std::string("fix_modify wirenet_bonds: ") + e.what()).c_str());
  }
  if (s != law_scale_) {
    sync_tallies();  // the plastic work so far, at the old scale
    if (BondWirenet *bond = dynamic_cast<BondWirenet *>(force->bond)) bond->rescale_wire_states(s / law_scale_);
    law_scale_ = s;
    version++;  // the bond style's envelope constants are rebuilt for the new scale
  }
  return 2;
}

void FixWirenetBonds::post_run()
{
  sync_tallies();
  remove_broken_bonds(false);
}

double FixWirenetBonds::compute_scalar()
{
  int pending = nbroken_pending, all = 0;
  MPI_Allreduce(&pending, &all, 1, MPI_INT, MPI_SUM, world);
  return (double)(nbroken_total + all);
}

void FixWirenetBonds::take_pair_forces()
{
  if (!pair_wanted) return;
  const int nlocal = atom->nlocal;
  double **f = atom->f, **t = atom->torque_flag ? atom->torque : NULL;
  pair_snap.resize(6 * (size_t)nlocal);
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < 3; k++) {
      pair_snap[6 * (size_t)i + k] = f[i][k];
      pair_snap[6 * (size_t)i + 3 + k] = t ? t[i][k] : 0.0;
    }
}

double FixWirenetBonds::tally_sum(int k) const
{
  double mine = 0.0, all = 0.0;
  for (size_t q = k; q < tally_mine.size(); q += NTALLY) mine += tally_mine[q];
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

double FixWirenetBonds::compute_vector(int n)
{
  if (n == 0) return compute_scalar();
  sync_tallies();
  return tally_sum(n - 1);
}

void FixWirenetBonds::set_elastic_energy(const std::vector<double> &e)
{
  elastic_mine.assign(e.begin(), e.end());
  elastic_step = update->ntimestep;
}

// Row i: bond type i + 1. The elastic energy exists only for a step whose forces were computed
// with energies (LIGGGHTS does so when a compute pe is due at that step).
double FixWirenetBonds::compute_array(int i, int j)
{
  const int type = i + 1;
  double mine, all = 0.0;
  if (j == 0) {
    if (elastic_step != update->ntimestep)
      error->all(FLERR, "fix wirenet/bonds: the elastic energy per bond type (column 1) is known only at steps "
                        "where the bond energy is computed: output a compute pe bond at the same steps");
    mine = elastic_mine[type];
  } else {
    sync_tallies();
    mine = tally_mine[(size_t)type * NTALLY + (j - 1)];
  }
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

/* ------------------------------------------------------------------------------------------- */

// A bond partner must be a local or ghost atom; name the setting to raise instead of LIGGGHTS'
// generic "Bond atoms missing". Called right after the ghosts were acquired, when their
// positions are exact: the longest local bond is measured on the way.
double FixWirenetBonds::check_partners_present()
{
  const int *num_bond = atom->num_bond;
  int **bond_atom = atom->bond_atom;
  double **x = atom->x;
  double longest_sq = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    for (int m = 0; m < num_bond[i]; m++) {
      const int j = atom->map(bond_atom[i][m]);
      if (j >= 0) {
        double d[3] = { x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2] };
        domain->minimum_image(d);
        longest_sq = fmax(longest_sq, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        continue;
      }
      char msg[512];
      snprintf(msg, sizeof(msg),
               "bond_style wirenet: bond %d-%d reaches beyond the ghost atoms (bond length allowed for: %g m) "
               "at step " BIGINT_FORMAT " (raise it with 'communicate single cutoff C'; node spheres get "
               "ghosts within C/2 + skin/2 + radius, so give C = twice the longest bond)",
               atom->tag[i], bond_atom[i][m], ghost_extent, update->ntimestep);
      error->one(FLERR, msg);
    }
  return sqrt(longest_sq);
}

// Until the next list build every atom moves less than skin/2, so no bond grows by more than the
// skin, which LIGGGHTS adds to the reach (Comm::setup()). The reach therefore holds as long as
// the longest bond at a build is within ghost_extent; past it, the reach grows before the next
// build. A reach from the rupture strain instead (1.35-1.5 times the longest bond) gave a 2-rank
// compound panel 60 % more ghosts to send every step (198 against 122 per rank).
void FixWirenetBonds::follow_bond_reach(double longest_local)
{
  double longest = 0.0;
  MPI_Allreduce(&longest_local, &longest, 1, MPI_DOUBLE, MPI_MAX, world);
  if (longest <= ghost_extent) return;
  set_bond_reach(longest);
  reach_grown = true;
}

void FixWirenetBonds::setup_pre_neighbor() { pre_neighbor(); }

void FixWirenetBonds::pre_neighbor()
{
  follow_bond_reach(check_partners_present());
  find_beam_ends();
  version++;
}

// Comm::setup() takes the ghost cutoff as MAX(..., extend_cut_ghost() + skin). For spheres in an
// orthogonal box (atom radius present) LIGGGHTS' granular border optimisation then copies only the
// atoms within HALF of that cutoff (+ skin/2 + the atom's radius) of a subdomain face, so the
// reach a bond needs is asked for twice there.
double FixWirenetBonds::extend_cut_ghost()
{
  const bool halved = domain->triclinic == 0 && atom->radius != NULL;
  return halved ? 2.0 * ghost_extent : ghost_extent;
}

double FixWirenetBonds::max_bond_length_global()
{
  // Bonds may span ranks before any ghost exists (or after commands that moved atoms between
  // runs): gather every atom's position once.
  const int nlocal = atom->nlocal;
  std::vector<double> mine(4 * nlocal);
  for (int i = 0; i < nlocal; i++) {
    mine[4 * i] = atom->tag[i];
    for (int d = 0; d < 3; d++) mine[4 * i + 1 + d] = atom->x[i][d];
  }
  int nprocs = comm->nprocs, count = 4 * nlocal;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);
  std::unordered_map<long, const double *> where;
  where.reserve(all.size() / 4);
  for (size_t k = 0; k < all.size(); k += 4) where[(long)all[k]] = &all[k + 1];

  double lmax = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int m = 0; m < atom->num_bond[i]; m++) {
      if (hist[i][m * NHIST + L0] < 0.0) continue;  // broken, awaiting removal
      auto it = where.find(atom->bond_atom[i][m]);
      if (it == where.end()) {
        char msg[256];
        snprintf(msg, sizeof(msg), "bond_style wirenet: bond %d-%d names atom %d, which does not exist",
                 atom->tag[i], atom->bond_atom[i][m], atom->bond_atom[i][m]);
        error->one(FLERR, msg);
      }
      double d[3] = { it->second[0] - atom->x[i][0], it->second[1] - atom->x[i][1], it->second[2] - atom->x[i][2] };
      domain->minimum_image(d);
      lmax = fmax(lmax, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
  double gmax = 0.0;
  MPI_Allreduce(&lmax, &gmax, 1, MPI_DOUBLE, MPI_MAX, world);
  return gmax;
}

/* ------------------------------------------------------------------------------------------- */

// Advance the orientations of the beam ends, local and ghost, with the half-step angular
// velocity: an exact rotation by |omega| dt about omega, so the beam law sees the rigid rotation
// without drift. Done after the ghosts' omega arrived (pre_force): a ghost then takes the same
// arithmetic on the same numbers as its owner and stays bit-identical to it without a message of
// its own (it receives its orientation once, at borders). Other nodes carry no beam, and a wire
// or contact never reads an orientation.
void FixWirenetBonds::advance_orientations()
{
  const double dt = update->dt;
  double **omega = atom->omega;
  for (const int i : oriented) {
    const double *w = omega[i];
    const double wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (wn == 0.0) continue;
    const double half = 0.5 * wn * dt;
    const double s = sin(half) / wn, c = cos(half);
    const double r[4] = { c, s * w[0], s * w[1], s * w[2] };
    double *q = quat[i];
    const double q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
    q[0] = r[0] * q0 - r[1] * q1 - r[2] * q2 - r[3] * q3;
    q[1] = r[0] * q1 + r[1] * q0 + r[2] * q3 - r[3] * q2;
    q[2] = r[0] * q2 - r[1] * q3 + r[2] * q0 + r[3] * q1;
    q[3] = r[0] * q3 + r[1] * q2 - r[2] * q1 + r[3] * q0;
    const double inv = 1.0 / sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++) q[k] *= inv;
  }
}

// The beam law reads rotation matrices: computed once per beam end and step (local and ghost)
// rather than once per bond end.
void FixWirenetBonds::refresh_rotations()
{
  for (const int i : oriented) {
    const double w = quat[i][0], x = quat[i][1], y = quat[i][2], z = quat[i][3];
    double *r = rot[i];
    r[0] = 1 - 2 * (y * y + z * z); r[1] = 2 * (x * y - w * z);     r[2] = 2 * (x * z + w * y);
    r[3] = 2 * (x * y + w * z);     r[4] = 1 - 2 * (x * x + z * z); r[5] = 2 * (y * z - w * x);
    r[6] = 2 * (x * z - w * y);     r[7] = 2 * (y * z + w * x);     r[8] = 1 - 2 * (x * x + y * y);
  }
}

// The atoms whose orientation matters: local atoms at either end of any beam bond (an owner's
// orientation goes to its ghost images at borders), and the ghost ends of this rank's own beam
// bonds. Bonds are stored once (newton_bond on), so the end that is a ghost here is marked and
// the mark sent to its owner. A ghost image no local bond reads is not turned: it receives its
// owner's orientation afresh at the next borders, before any bond can read it (the bond lists
// change only there). The image is the one LIGGGHTS' bond list takes (closest_image). Called
// after every exchange (local indices change there) with the ghosts and the atom map current.
void FixWirenetBonds::find_beam_ends()
{
  oriented.clear();
  if (!orient_flag) return;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int *num_bond = atom->num_bond;
  int **bond_atom = atom->bond_atom, **bond_type = atom->bond_type;
  end_mark.assign(nall, 0.0);
  for (int i = 0; i < nlocal; i++)
    for (int m = 0; m < num_bond[i]; m++) {
      const int t = bond_type[i][m];
      if (t <= 0 || t >= (int)beam_type.size() || !beam_type[t]) continue;
      end_mark[i] = 1.0;
      // present: check_partners_present()
      end_mark[domain->closest_image(i, atom->map(bond_atom[i][m]))] = 1.0;
    }
  comm->reverse_comm_fix(this);
  for (int i = 0; i < nall; i++)
    if (end_mark[i] > 0.0) oriented.push_back(i);
}

int FixWirenetBonds::pack_reverse_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) buf[k] = end_mark[first + k];
  return 1;
}

void FixWirenetBonds::unpack_reverse_comm(int n, int *list, double *buf)
{
  for (int k = 0; k < n; k++) end_mark[list[k]] += buf[k];
}

// Before the forces: the velocities of the ghost atoms (bond damping, and the orientations'
// update) unless LIGGGHTS sent them already ('communicate ... vel yes'), then the orientations.
void FixWirenetBonds::refresh_ghosts(bool advance)
{
  if ((orient_flag || vel_flag) && !comm->ghost_velocity) comm->forward_comm_fix(this);
  if (!orient_flag) return;
  if (advance) advance_orientations();
  refresh_rotations();
}

void FixWirenetBonds::setup_pre_force(int) { refresh_ghosts(false); }
void FixWirenetBonds::pre_force(int) { refresh_ghosts(true); }

double FixWirenetBonds::memory_usage()
{
  return (double)atom->nmax * (nslots * NHIST + 13) * sizeof(double) +
         (double)maxlocal * RUPTURE_COLS * sizeof(double);
}
