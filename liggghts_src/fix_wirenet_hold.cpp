/* WireNet: fix wirenet/hold. See doc/fix_wirenet_hold.md.

   post_force zeroes the held components of the group's forces (a list of the held atoms' local
   indices, renewed after each neighbour-list build, spares a pass over all atoms) and keeps
   their negatives, the support reaction, on this rank: the total, and per atom with `each`.
   The window sums of WireNet::WindowSums add them up over the mean window; compute_vector /
   compute_array reduce the current values and the last complete window in one MPI_Allreduce,
   once per step asked. */

#include "fix_wirenet_hold.h"
#include "wirenet_fix_args.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "group.h"
#include "neighbor.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *USAGE = "expected 'fix ID GROUP wirenet/hold X Y Z [mean N] [each]' with X, Y, Z each 0 (held) or NULL (free)";

bool parse_component(const char *s, const char *axis)
{
  if (strcmp(s, "NULL") == 0) return false;
  if (strcmp(s, "0") == 0) return true;
  throw std::invalid_argument(std::string("component ") + axis + " must be 0 (held) or NULL (free), got '" + s +
                              "' (a prescribed non-zero force is fix setforce's or fix addforce's job)");
}


}  // namespace

FixWirenetHold::FixWirenetHold(LAMMPS *lmp, int narg, char **arg)
    : Fix(lmp, narg, arg), width(1), each(false), reduced_at(-1), members_at(-1)
{
  try {
    if (narg < 6) throw std::invalid_argument(USAGE);
    held[0] = parse_component(arg[3], "x");
    held[1] = parse_component(arg[4], "y");
    held[2] = parse_component(arg[5], "z");
    if (!held[0] && !held[1] && !held[2]) throw std::invalid_argument("holds nothing: give 0 for at least one of X Y Z");
    for (int k = 6; k < narg;) {
      const std::string key = arg[k];
      if (key == "mean") {
        width = WireNet::FixArgs::steps(narg, arg, k, key);
      } else if (key == "each") {
        each = true;
        k++;
      } else {
        throw std::invalid_argument("unknown keyword '" + key + "' (" + USAGE + ")");
      }
    }
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, ("fix wirenet/hold: " + std::string(e.what())).c_str());
  }
  vector_flag = 1;
  size_vector = NVECTOR;
  global_freq = 1;
  extvector = 0;
  if (each) {
    array_flag = 1;
    size_array_cols = NCOLUMNS;
    size_array_rows = 0;      // set by collect_rows
    extarray = 0;
  }
  collect_rows();
}

int FixWirenetHold::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

void FixWirenetHold::init()
{
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix wirenet/hold does not support run_style respa");
  collect_rows();
}

// The atom IDs of the group, ascending (each); sizes the sums. Called at every init: a window
// open across runs keeps its sums unless the rows changed.
void FixWirenetHold::collect_rows()
{
  std::vector<int> mine;
  if (each) {
    const int *mask = atom->mask, *tag = atom->tag;
    for (int i = 0; i < atom->nlocal; i++)
      if (mask[i] & groupbit) mine.push_back(tag[i]);
    int n = static_cast<int>(mine.size()), total = 0;
    MPI_Allreduce(&n, &total, 1, MPI_INT, MPI_SUM, world);
    if (total > MAX_EACH)
      error->all(FLERR, ("fix wirenet/hold: 'each' gives one row per atom, and group " + std::string(group->names[igroup]) +
                         " has " + std::to_string(total) + " atoms (at most " + std::to_string(MAX_EACH) +
                         "); hold a large group without 'each'").c_str());
    std::vector<int> counts(comm->nprocs), offsets(comm->nprocs, 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
    for (int p = 1; p < comm->nprocs; p++) offsets[p] = offsets[p - 1] + counts[p - 1];
    mine.resize(std::max(n, 1));
    std::vector<int> all(std::max(total, 1));
    MPI_Allgatherv(mine.data(), n, MPI_INT, all.data(), counts.data(), offsets.data(), MPI_INT, world);
    all.resize(total);
    std::sort(all.begin(), all.end());
    mine.swap(all);
  }
  const int nvalues = 3 + 3 * static_cast<int>(mine.size());
  if (mine == tags && static_cast<int>(current.size()) == nvalues && windows.width() == width) return;
  tags.swap(mine);
  size_array_rows = static_cast<int>(tags.size());
  current.assign(nvalues, 0.0);
  reduced.assign(2 * nvalues, 0.0);
  windows.reset(width, nvalues);
  reduced_at = -1;
}

int FixWirenetHold::row_of(int tag) const
{
  return static_cast<int>(std::lower_bound(tags.begin(), tags.end(), tag) - tags.begin());
}

// A run's set-up may follow a `group` command that changed the group without a neighbour-list
// build since (`run ... pre no`): list anew.
void FixWirenetHold::setup(int vflag)
{
  collect_members();
  post_force(vflag);
}

void FixWirenetHold::min_setup(int vflag)
{
  collect_members();
  post_force(vflag);
}

void FixWirenetHold::min_post_force(int vflag)
{
  post_force(vflag);
}

// The held atoms' local indices and rows, in ascending local index (the order of a pass over
// all atoms: the sums are the same to the last bit). Local indices change only where LIGGGHTS
// exchanges or sorts atoms, and a neighbour-list build follows each of those.
void FixWirenetHold::collect_members()
{
  members.clear();
  member_rows.clear();
  const int *mask = atom->mask, *tag = atom->tag;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    int row = -1;
    if (each) {
      const int r = row_of(tag[i]);
      if (r < static_cast<int>(tags.size()) && tags[r] == tag[i]) row = r;
    }
    members.push_back(i);
    member_rows.push_back(row);
  }
  members_at = neighbor->ncalls;
}

void FixWirenetHold::post_force(int)
{
  if (members_at != neighbor->ncalls) collect_members();
  double **f = atom->f;
  std::fill(current.begin(), current.end(), 0.0);
  double total[3] = { 0.0, 0.0, 0.0 };
  for (size_t k = 0; k < members.size(); k++) {
    double *fi = f[members[k]];
    double *row = member_rows[k] >= 0 ? &current[3 + 3 * member_rows[k]] : NULL;
    for (int d = 0; d < 3; d++) {
      if (!held[d]) continue;
      total[d] -= fi[d];
      if (row) row[d] -= fi[d];
      fi[d] = 0.0;
    }
  }
  for (int d = 0; d < 3; d++) current[d] = total[d];
  double *sums = windows.add_step(update->ntimestep);
  if (sums)
    for (size_t k = 0; k < current.size(); k++) sums[k] += current[k];
  reduced_at = -1;
}

// One reduction for everything the outputs can ask at this step.
void FixWirenetHold::reduce()
{
  if (reduced_at == update->ntimestep) return;
  const size_t n = current.size();
  int count = 0;
  const double *sums = windows.complete(update->ntimestep, count);
  std::vector<double> &send = reduced;     // reused: filled, then reduced in place
  std::copy(current.begin(), current.end(), send.begin());
  for (size_t k = 0; k < n; k++) send[n + k] = count ? sums[k] / count : 0.0;
  MPI_Allreduce(MPI_IN_PLACE, send.data(), static_cast<int>(2 * n), MPI_DOUBLE, MPI_SUM, world);
  reduced_at = update->ntimestep;
}

double FixWirenetHold::compute_vector(int n)
{
  reduce();
  const size_t nv = current.size();
  return n < 3 ? reduced[n] : reduced[nv + (n - 3)];
}

double FixWirenetHold::compute_array(int row, int col)
{
  reduce();
  if (col == 0) return tags[row];
  const size_t nv = current.size();
  const size_t k = 3 + 3 * static_cast<size_t>(row);
  return col < 4 ? reduced[k + (col - 1)] : reduced[nv + k + (col - 4)];
}
