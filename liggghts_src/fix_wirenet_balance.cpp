/* WireNet: fix wirenet/balance. See doc/fix_wirenet_balance.md.

   At each run's set-up (setup_pre_exchange, before Verlet's own exchange and borders) the cuts
   of every named dimension with more than one processor move to the quantiles of the group's
   atoms along it: cut k of P at the position below which k/P of them lie, found by bisection
   on the fraction of the box, one allreduce of the P - 1 counts per halving, each rank
   counting its atoms from a sorted copy of their coordinates; the cut then goes midway between
   the atoms on either side of it. The grid stays a tensor product
   of 1-d cuts (the layout LIGGGHTS' Comm already handles as `uniform = 0`); the atoms move to
   their new owners by Irregular::migrate_atoms, the fixes' per-atom data with them (contact
   history is packed by fix contacthistory's own pre_exchange, which Modify calls first), in the
   order of their senders' ranks (LIGGGHTS patch 0015), so that a balanced run repeats itself. */

#include "fix_wirenet_balance.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "irregular.h"
#include "mpi.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *USAGE = "expected 'fix ID GROUP wirenet/balance DIMS' with DIMS one or more of x, y, z (e.g. x or xy)";
// halvings of a cut's bracket: 2^-60 of the box, below the spacing of doubles in [0, 1]
const int BISECTIONS = 60;
// the thinnest slab a cut may leave, as a fraction of the box (atoms on one plane, as a
// post's nodes on one x, would otherwise put two cuts on it)
const double MIN_SLAB = 1e-9;

}  // namespace

FixWirenetBalance::FixWirenetBalance(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), reported(false)
{
  dims[0] = dims[1] = dims[2] = false;
  imbalance[0] = imbalance[1] = 1.0;
  try {
    if (narg != 4 || arg[3][0] == '\0') throw std::invalid_argument(USAGE);
    for (const char *c = arg[3]; *c; c++) {
      const char *at = strchr("xyz", *c);
      if (!at) throw std::invalid_argument(std::string("DIMS '") + arg[3] + "': '" + *c + "' is not x, y or z");
      if (dims[at - "xyz"]) throw std::invalid_argument(std::string("DIMS '") + arg[3] + "' names " + *c + " twice");
      dims[at - "xyz"] = true;
    }
    if (domain->triclinic) throw std::invalid_argument("needs an orthogonal box");
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, ("fix wirenet/balance: " + std::string(e.what())).c_str());
  }
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extvector = 0;
}

int FixWirenetBalance::setmask()
{
  return PRE_EXCHANGE;
}

void FixWirenetBalance::init()
{
  for (int d = 0; d < 3; d++)
    if (dims[d] && domain->periodicity[d])
      error->all(FLERR, (std::string("fix wirenet/balance: dimension ") + "xyz"[d] +
                         " is periodic; the cuts follow atoms along non-periodic dimensions only").c_str());
}

void FixWirenetBalance::setup_pre_exchange()
{
  if (comm->nprocs == 1) return;
  // the atoms inside the box and a shrink-wrapped box fitted to them, as Verlet does next
  domain->pbc();
  domain->reset_box();
  imbalance[0] = imbalance_now();

  std::vector<double> split[3];
  double *current[3] = {comm->xsplit, comm->ysplit, comm->zsplit};
  for (int d = 0; d < 3; d++) {
    split[d].assign(current[d], current[d] + comm->procgrid[d] + 1);
    if (dims[d] && comm->procgrid[d] > 1) quantile_cuts(d, split[d]);
  }
  for (int d = 0; d < 3; d++) std::copy(split[d].begin(), split[d].end(), current[d]);
  comm->uniform = 0;
  domain->set_local_box();
  Irregular irregular(lmp);
  irregular.migrate_atoms();

  imbalance[1] = imbalance_now();
  if (!reported && comm->me == 0) {
    char line[160];
    snprintf(line, sizeof(line), "fix wirenet/balance: atoms per rank, largest over mean: %.3f before, %.3f after\n",
             imbalance[0], imbalance[1]);
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
  reported = true;
}

// largest rank's count of group atoms over the mean count (1: balanced)
double FixWirenetBalance::imbalance_now() const
{
  const int *mask = atom->mask;
  double mine = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit) mine += 1.0;
  double largest = 0.0, total = 0.0;
  MPI_Allreduce(&mine, &largest, 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  return total > 0.0 ? largest * comm->nprocs / total : 1.0;
}

// split[1 .. P-1] of dimension `dim` (fractions of the box) at the group atoms' quantiles
void FixWirenetBalance::quantile_cuts(int dim, std::vector<double> &split) const
{
  const int P = comm->procgrid[dim];
  const double lo = domain->boxlo[dim], prd = domain->prd[dim];
  std::vector<double> frac;
  const int *mask = atom->mask;
  double **x = atom->x;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit) frac.push_back((x[i][dim] - lo) / prd);
  std::sort(frac.begin(), frac.end());
  double mine = static_cast<double>(frac.size()), total = 0.0;
  MPI_Allreduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  if (!(total > 0.0)) return;

  // bracket [a, b] of each cut: fewer than the target below a, at least the target below b
  std::vector<double> a(P - 1, 0.0), b(P - 1, 1.0), mid(P - 1), below(P - 1), sum(P - 1);
  for (int it = 0; it < BISECTIONS; it++) {
    for (int k = 0; k < P - 1; k++) {
      mid[k] = 0.5 * (a[k] + b[k]);
      below[k] = static_cast<double>(std::lower_bound(frac.begin(), frac.end(), mid[k]) - frac.begin());
    }
    MPI_Allreduce(below.data(), sum.data(), P - 1, MPI_DOUBLE, MPI_SUM, world);
    for (int k = 0; k < P - 1; k++) {
      if (sum[k] < total * (k + 1) / P) a[k] = mid[k];
      else b[k] = mid[k];
    }
  }
  // b[k] lies just above the atom that completes slab k: the cut goes midway between it and the
  // next atom above, so that no atom sits on a cut (where the owner would be round-off's choice)
  std::vector<double> up(P - 1), down(P - 1), next(P - 1), last(P - 1);
  for (int k = 0; k < P - 1; k++) {
    const auto at = std::lower_bound(frac.begin(), frac.end(), b[k]);
    up[k] = at == frac.end() ? 1.0 : *at;
    down[k] = at == frac.begin() ? 0.0 : *(at - 1);
  }
  MPI_Allreduce(up.data(), next.data(), P - 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(down.data(), last.data(), P - 1, MPI_DOUBLE, MPI_MAX, world);
  // every slab at least MIN_SLAB thick, the cuts in order
  split[0] = 0.0;
  split[P] = 1.0;
  for (int k = 1; k < P; k++) {
    const double cut = 0.5 * (last[k - 1] + next[k - 1]);
    split[k] = std::min(std::max(cut, split[k - 1] + MIN_SLAB), 1.0 - (P - k) * MIN_SLAB);
  }
}

// [1] before, [2] after the last balance: the largest rank's group atoms over the mean
double FixWirenetBalance::compute_vector(int n)
{
  return imbalance[n];
}
