/* WireNet: fix wirenet/shackle. See doc/fix_wirenet_shackle.md.

   Each shackle is computed on the rank that owns its atom S; the rope atoms it needs must be local
   or ghost atoms there. Forces on ghost rope atoms are kept in fghost and sent to their owners by
   this fix's own reverse communication (LIGGGHTS' reverse communication of forces has already
   happened when post_force runs). The shackle's history (segment index, tangential displacement)
   is per atom and travels with it (exchange, restart). The contact law is WireNet::ShackleLaw. */

#include "fix_wirenet_shackle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

#include "wirenet_fix_args.h"
#include "wirenet_shackle_file.h"

using namespace LAMMPS_NS;
using namespace FixConst;

static const int NHIST = 3;   // segment index, xi, sliding at the last step (0/1)
static const int NVECTOR = 5;

FixWirenetShackle::FixWirenetShackle(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), hist(NULL), elastic_mine(0.0), sliding_mine(0), fmax_mine(0.0)
{
  work_mine[0] = work_mine[1] = 0.0;
  for (int k = 0; k < NVECTOR; k++) sums[k] = 0.0;

  // fix ID GROUP wirenet/shackle file PATH kn KN kt KT mu MU [damping ZETA]
  WireNet::ShackleLawParams p;
  bool have_kn = false, have_kt = false, have_mu = false;
  const char *file = NULL;
  try {
    int k = 3;
    while (k < narg) {
      const std::string key = arg[k];
      if (key == "file") {
        if (k + 1 >= narg) throw std::invalid_argument("'file' needs a path");
        file = arg[k + 1];
        k += 2;
      } else if (key == "kn") {
        p.kn = WireNet::FixArgs::value(narg, arg, k, "kn", 0.0, true);
        have_kn = true;
      } else if (key == "kt") {
        p.kt = WireNet::FixArgs::value(narg, arg, k, "kt", 0.0, true);
        have_kt = true;
      } else if (key == "mu") {
        p.mu = WireNet::FixArgs::value(narg, arg, k, "mu", 0.0, false);
        have_mu = true;
      } else if (key == "damping") {
        p.damping = WireNet::FixArgs::value(narg, arg, k, "damping", 0.0, false);
      } else {
        throw std::invalid_argument("unknown keyword '" + key + "' (expected file, kn, kt, mu, damping)");
      }
    }
    if (!file) throw std::invalid_argument("missing keyword 'file PATH'");
    if (!have_kn) throw std::invalid_argument("missing keyword 'kn KN'");
    if (!have_kt) throw std::invalid_argument("missing keyword 'kt KT'");
    if (!have_mu) throw std::invalid_argument("missing keyword 'mu MU'");
    law.reset(new WireNet::ShackleLaw(p));
  } catch (const std::invalid_argument &e) {
    const std::string msg = std::string("fix wirenet/shackle: ") + e.what();
    error->all(FLERR, msg.c_str());
  }
  if (!atom->map_style)
    error->all(FLERR, "fix wirenet/shackle: needs an atom map ('atom_modify map array' before the box is defined)");
  if (!atom->tag_enable) error->all(FLERR, "fix wirenet/shackle: needs atom IDs");

  path = file;
  read_file(file);
  check_atoms_exist();

  scalar_flag = 1;
  vector_flag = 1;
  size_vector = NVECTOR;
  global_freq = 1;
  extscalar = 1;
  extvector = -1;
  extlist = new int[NVECTOR];
  extlist[0] = 1;  // friction work
  extlist[1] = 1;  // elastic energy
  extlist[2] = 0;  // shackles sliding
  extlist[3] = 0;  // largest force
  extlist[4] = 1;  // damping work
  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 0;
  comm_forward = 3;  // velocities of ghost rope atoms (unless 'communicate ... vel yes')
  comm_reverse = 3;  // forces on ghost rope atoms

  grow_arrays(atom->nmax);
  atom->add_callback(0);
  atom->add_callback(1);
  for (int i = 0; i < atom->nlocal; i++) {
    hist[i][0] = -1.0;
    hist[i][1] = hist[i][2] = 0.0;
  }
}

FixWirenetShackle::~FixWirenetShackle()
{
  atom->delete_callback(id, 0);
  atom->delete_callback(id, 1);
  memory->destroy(hist);
  delete[] extlist;
  extlist = NULL;
}

int FixWirenetShackle::setmask() { return POST_FORCE; }

// Rank 0 reads the file, every rank parses the same text (so every rank stops on the same line).
void FixWirenetShackle::read_file(const char *file)
{
  std::string content;
  long long len = -1;
  if (comm->me == 0) {
    FILE *fp = fopen(file, "rb");
    if (fp) {
      char buf[65536];
      size_t n;
      while ((n = fread(buf, 1, sizeof buf, fp)) > 0) content.append(buf, n);
      len = ferror(fp) ? -1 : (long long)content.size();
      fclose(fp);
    }
  }
  MPI_Bcast(&len, 1, MPI_LONG_LONG, 0, world);
  if (len < 0) {
    const std::string msg = std::string("fix wirenet/shackle: cannot read the shackle file '") + file + "'";
    error->all(FLERR, msg.c_str());
  }
  content.resize(len);
  if (len > 0) MPI_Bcast(&content[0], (int)len, MPI_CHAR, 0, world);

  WireNet::ShackleFile f;
  try {
    f = WireNet::parse_shackle_file(content);
  } catch (const std::invalid_argument &e) {
    const std::string msg = std::string("fix wirenet/shackle: shackle file '") + file + "' " + e.what();
    error->all(FLERR, msg.c_str());
  }
  const long long biggest = MAXSMALLINT;
  for (const auto &r : f.ropes) {
    Rope rope;
    rope.id = r.id;
    for (long long t : r.atoms) rope.tags.push_back(t > biggest ? -1 : (int)t);
    ropes.push_back(rope);
  }
  for (const auto &s : f.shackles) shackles.push_back({ s.atom > biggest ? -1 : (int)s.atom, s.rope });
}

// Every atom named by the file exists (owned by exactly one rank).
void FixWirenetShackle::check_atoms_exist()
{
  std::vector<int> tags;
  for (const auto &s : shackles) tags.push_back(s.tag);
  for (const auto &r : ropes) tags.insert(tags.end(), r.tags.begin(), r.tags.end());
  std::vector<int> mine(tags.size(), 0), all(tags.size(), 0);
  for (size_t k = 0; k < tags.size(); k++) {
    if (tags[k] <= 0 || tags[k] > atom->map_tag_max) continue;
    const int i = atom->map(tags[k]);
    if (i >= 0 && i < atom->nlocal) mine[k] = 1;
  }
  if (!tags.empty()) MPI_Allreduce(mine.data(), all.data(), (int)tags.size(), MPI_INT, MPI_SUM, world);
  for (size_t k = 0; k < tags.size(); k++) {
    if (all[k] == 1) continue;
    std::string msg = "fix wirenet/shackle: shackle file '" + path + "': ";
    if (k < shackles.size())
      msg += "shackle atom " + std::to_string(tags[k]) + " does not exist";
    else {
      size_t m = k - shackles.size();
      size_t r = 0;
      while (m >= ropes[r].tags.size()) m -= ropes[r++].tags.size();
      msg += "rope '" + ropes[r].id + "': atom " + std::to_string(ropes[r].tags[m]) + " does not exist";
    }
    error->all(FLERR, msg.c_str());
  }
}

void FixWirenetShackle::init()
{
  if (strstr(update->integrate_style, "respa"))
    error->all(FLERR, "fix wirenet/shackle does not support run_style respa");
  // the decks damp every internal force with fix wirenet/damping: it must come after this fix
  const int me = modify->find_fix(id);
  for (int k = 0; k < me; k++)
    if (strcmp(modify->fix[k]->style, "wirenet/damping") == 0 && comm->me == 0) {
      const std::string msg = std::string("fix wirenet/shackle: fix ") + modify->fix[k]->id +
                              " (wirenet/damping) comes earlier and does not damp the shackle forces; "
                              "define wirenet/shackle before it";
      error->warning(FLERR, msg.c_str());
    }
}

/* ------------------------------------------------------------------------------------------- */

// Shackles not placed yet (a new fix; not after read_restart) go to the nearest segment of their
// rope: the rope's positions are gathered from every rank once.
void FixWirenetShackle::place_new_shackles()
{
  const int nlocal = atom->nlocal;
  int need = 0, bad = 0;
  for (const auto &sh : shackles) {
    const int i = atom->map(sh.tag);
    if (i < 0 || i >= nlocal) continue;
    const int nseg = (int)ropes[sh.rope].tags.size() - 1;
    if (hist[i][0] < 0.0) need = 1;
    else if (hist[i][0] >= nseg && bad == 0) bad = sh.tag;
  }
  int flags[2] = { need, bad }, any[2];
  MPI_Allreduce(flags, any, 2, MPI_INT, MPI_MAX, world);
  if (any[1]) {
    const std::string msg = "fix wirenet/shackle: shackle atom " + std::to_string(any[1]) +
                            ": its segment from the restart file is not on its rope in '" + path + "'";
    error->all(FLERR, msg.c_str());
  }
  if (!any[0]) return;

  size_t total = 0;
  std::vector<size_t> first;
  for (const auto &r : ropes) {
    first.push_back(total);
    total += r.tags.size();
  }
  std::vector<double> mine(3 * total, 0.0), all(3 * total, 0.0);
  double **x = atom->x;
  for (size_t r = 0; r < ropes.size(); r++)
    for (size_t m = 0; m < ropes[r].tags.size(); m++) {
      const int j = atom->map(ropes[r].tags[m]);
      if (j < 0 || j >= nlocal) continue;
      for (int d = 0; d < 3; d++) mine[3 * (first[r] + m) + d] = x[j][d];
    }
  MPI_Allreduce(mine.data(), all.data(), (int)(3 * total), MPI_DOUBLE, MPI_SUM, world);

  for (const auto &sh : shackles) {
    const int i = atom->map(sh.tag);
    if (i < 0 || i >= nlocal || hist[i][0] >= 0.0) continue;
    const Eigen::Vector3d xs(x[i][0], x[i][1], x[i][2]);
    const double *rp = &all[3 * first[sh.rope]];
    const int nseg = (int)ropes[sh.rope].tags.size() - 1;
    int best = 0;
    double best_d2 = INFINITY;
    for (int k = 0; k < nseg; k++) {
      const Eigen::Vector3d a(rp + 3 * k), b(rp + 3 * k + 3);
      double s = WireNet::ShackleLaw::param(xs, a, b);
      s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
      const double d2 = (xs - (a + s * (b - a))).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = k;
      }
    }
    hist[i][0] = best;
    hist[i][1] = hist[i][2] = 0.0;
  }
}

// The setup pass evaluates the forces of the current history without moving it (as LIGGGHTS'
// granular contacts do): a run that follows another, or a restart, continues exactly.
void FixWirenetShackle::setup(int)
{
  place_new_shackles();
  shackle_forces(true);
}

void FixWirenetShackle::post_force(int) { shackle_forces(false); }

void FixWirenetShackle::shackle_forces(bool setup_pass)
{
  // velocities of the ghost rope atoms (v_P), of the same half step as the owners'
  if (!comm->ghost_velocity) comm->forward_comm_fix(this);

  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  if (fghost.size() < 3 * (size_t)nall) fghost.resize(3 * (size_t)atom->nmax, 0.0);
  double **x = atom->x, **v = atom->v, **f = atom->f;
  const double *rmass = atom->rmass, *mass = atom->mass;
  const int *type = atom->type;
  const double dt = setup_pass ? 0.0 : update->dt;

  double work = 0.0, damp_work = 0.0, elastic = 0.0, fmax = 0.0;
  int sliding = 0, ghost_touched = 0, missing = 0;

  for (const auto &sh : shackles) {
    const int i = atom->map(sh.tag);
    if (i < 0 || i >= nlocal) continue;
    const std::vector<int> &tags = ropes[sh.rope].tags;
    const int n = (int)tags.size();
    auto index = [&](int m) { return domain->closest_image(i, atom->map(tags[m])); };
    const Eigen::Vector3d xs(x[i][0], x[i][1], x[i][2]);
    const WireNet::ShackleLocation loc = WireNet::ShackleLaw::locate(
      xs, (int)hist[i][0], n, [&](int m) -> const double * {
        const int j = index(m);
        return j < 0 ? NULL : x[j];
      });
    if (loc.missing >= 0) {
      if (sh.tag > missing) missing = sh.tag;
      continue;
    }
    const int ja = index(loc.seg), jb = index(loc.seg + 1);
    const Eigen::Vector3d a(x[ja][0], x[ja][1], x[ja][2]), b(x[jb][0], x[jb][1], x[jb][2]);
    const Eigen::Vector3d vs(v[i][0], v[i][1], v[i][2]);
    const Eigen::Vector3d va(v[ja][0], v[ja][1], v[ja][2]), vb(v[jb][0], v[jb][1], v[jb][2]);
    const double m = rmass ? rmass[i] : mass[type[i]];
    const WireNet::ShackleResult r = law->step(xs, vs, m, a, b, va, vb, loc.s, hist[i][1], dt);
    hist[i][0] = loc.seg;
    hist[i][1] = r.xi;
    // the setup pass does not move the history: it reports the last step's sliding state
    const bool slides = setup_pass ? hist[i][2] != 0.0 : r.sliding;
    hist[i][2] = slides ? 1.0 : 0.0;

    const Eigen::Vector3d &F = r.force;
    const double wa = 1.0 - loc.s, wb = loc.s;
    for (int d = 0; d < 3; d++) f[i][d] += F[d];
    const int ends[2] = { ja, jb };
    const double weights[2] = { wa, wb };
    for (int e = 0; e < 2; e++) {
      const int j = ends[e];
      double *fj = j < nlocal ? f[j] : &fghost[3 * (size_t)j];
      if (j >= nlocal) ghost_touched = 1;
      for (int d = 0; d < 3; d++) fj[d] -= weights[e] * F[d];
    }
    work += r.slip_work;
    damp_work += r.damping_work;
    elastic += r.elastic;
    if (slides) sliding++;
    const double fn = F.norm();
    if (fn > fmax) fmax = fn;
  }

  // one collective per step: whether any rank has forces for ghosts, and the first shackle whose
  // rope atoms were out of reach
  int flags[2] = { ghost_touched, missing }, any[2];
  MPI_Allreduce(flags, any, 2, MPI_INT, MPI_MAX, world);
  if (any[1]) {
    char msg[640];
    snprintf(msg, sizeof msg,
             "fix wirenet/shackle: shackle atom %d: the rope atoms of its segment are not within the "
             "ghost cutoff at step " BIGINT_FORMAT " (raise it with 'communicate single cutoff C': "
             "node spheres get ghosts within C/2 + skin/2 + radius, so give C above twice the longest "
             "rope segment plus the largest shackle offset)",
             any[1], update->ntimestep);
    error->all(FLERR, msg);
  }
  if (any[0]) {
    comm->reverse_comm_fix(this);
    std::fill(fghost.begin() + 3 * (size_t)nlocal, fghost.begin() + 3 * (size_t)nall, 0.0);
  }

  work_mine[0] += work;
  work_mine[1] += damp_work;
  elastic_mine = elastic;
  sliding_mine = sliding;
  fmax_mine = fmax;
}

/* ------------------------------------------------------------------------------------------- */

void FixWirenetShackle::reduce()
{
  double mine[4] = { work_mine[0], work_mine[1], elastic_mine, (double)sliding_mine }, all[4];
  MPI_Allreduce(mine, all, 4, MPI_DOUBLE, MPI_SUM, world);
  double fmax_all;
  MPI_Allreduce(&fmax_mine, &fmax_all, 1, MPI_DOUBLE, MPI_MAX, world);
  sums[0] = all[0];
  sums[1] = all[2];
  sums[2] = all[3];
  sums[3] = fmax_all;
  sums[4] = all[1];
}

double FixWirenetShackle::compute_scalar()
{
  reduce();
  return sums[0];
}

// [1] friction work, [2] elastic energy, [3] shackles sliding, [4] largest |F|, [5] damping work
double FixWirenetShackle::compute_vector(int n)
{
  reduce();
  return sums[n];
}

/* ------------------------------------------------------------------------------------------- */

void FixWirenetShackle::grow_arrays(int nmax)
{
  memory->grow(hist, nmax, NHIST, "wirenet/shackle:hist");
}

void FixWirenetShackle::copy_arrays(int i, int j, int)
{
  for (int k = 0; k < NHIST; k++) hist[j][k] = hist[i][k];
}

int FixWirenetShackle::pack_exchange(int i, double *buf)
{
  for (int k = 0; k < NHIST; k++) buf[k] = hist[i][k];
  return NHIST;
}

int FixWirenetShackle::unpack_exchange(int i, double *buf)
{
  for (int k = 0; k < NHIST; k++) hist[i][k] = buf[k];
  return NHIST;
}

int FixWirenetShackle::pack_restart(int i, double *buf)
{
  buf[0] = 1 + NHIST;
  for (int k = 0; k < NHIST; k++) buf[1 + k] = hist[i][k];
  return 1 + NHIST;
}

void FixWirenetShackle::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(extra[nlocal][m]) != 1 + NHIST)
    error->one(FLERR, "fix wirenet/shackle: the restart file's shackle history has the wrong size");
  for (int k = 0; k < NHIST; k++) hist[nlocal][k] = extra[nlocal][m + 1 + k];
}

int FixWirenetShackle::size_restart(int) { return 1 + NHIST; }
int FixWirenetShackle::maxsize_restart() { return 1 + NHIST; }

int FixWirenetShackle::pack_comm(int n, int *list, double *buf, int, int *)
{
  double **v = atom->v;
  int m = 0;
  for (int k = 0; k < n; k++)
    for (int d = 0; d < 3; d++) buf[m++] = v[list[k]][d];
  return 3;
}

void FixWirenetShackle::unpack_comm(int n, int first, double *buf)
{
  double **v = atom->v;
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int d = 0; d < 3; d++) v[i][d] = buf[m++];
}

int FixWirenetShackle::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int d = 0; d < 3; d++) buf[m++] = fghost[3 * (size_t)i + d];
  return 3;
}

// A receiving atom may itself be a ghost of an earlier swap: its share goes on with that swap.
void FixWirenetShackle::unpack_reverse_comm(int n, int *list, double *buf)
{
  const int nlocal = atom->nlocal;
  double **f = atom->f;
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    double *fj = j < nlocal ? f[j] : &fghost[3 * (size_t)j];
    for (int d = 0; d < 3; d++) fj[d] += buf[m++];
  }
}

// The work totals go to rank 0's share on restart; the other ranks start from zero.
void FixWirenetShackle::write_restart(FILE *fp)
{
  double all[2];
  MPI_Reduce(work_mine, all, 2, MPI_DOUBLE, MPI_SUM, 0, world);
  if (comm->me != 0) return;
  int size = (int)sizeof(all);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(all, sizeof(double), 2, fp);
}

void FixWirenetShackle::restart(char *buf)
{
  const double *list = (const double *)buf;
  work_mine[0] = comm->me == 0 ? list[0] : 0.0;
  work_mine[1] = comm->me == 0 ? list[1] : 0.0;
}

double FixWirenetShackle::memory_usage()
{
  return (double)atom->nmax * NHIST * sizeof(double) + fghost.capacity() * sizeof(double);
}
