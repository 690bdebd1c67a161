/* WireNet: bond_style wirenet. See doc/bond_wirenet.md. */

#include "bond_wirenet.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_wirenet_bonds.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace WireNet;

static const char HISTORY_FIX_ID[] = "wirenet_bonds";

BondWirenet::BondWirenet(LAMMPS *lmp) :
  Bond(lmp), nbeam(0), ncircular(0), list_version(-1), history(NULL), any_beam(0), any_strength(0),
  any_beam_damping(0), any_damping(0), keep_damp_loads(false), computes(0), plastic_synced(0), law_scale(1.0), inv_scale2(1.0), duplicates_checked(false) {}

BondWirenet::~BondWirenet()
{
  if (allocated) memory->destroy(setflag);
}

void BondWirenet::allocate()
{
  allocated = 1;
  const int n = atom->nbondtypes;
  memory->create(setflag, n + 1, "bond:setflag");
  for (int t = 0; t <= n; t++) setflag[t] = 0;
  specs.assign(n + 1, BondTypeSpec());
  wires.resize(n + 1);
  beams.resize(n + 1);
}

void BondWirenet::settings(int narg, char **)
{
  if (narg != 0) error->all(FLERR, "bond_style wirenet takes no arguments (laws are set per type with bond_coeff)");
}

void BondWirenet::set_type(int type, const BondTypeSpec &spec)
{
  specs[type] = spec;
  // a brake is a wire bond with a force-elongation envelope: the same force loop, history,
  // plastic-work and rupture tallies, damping and output
  if (spec.kind == LawKind::WIRE) wires[type].reset(new WireLaw(spec.wire));
  else if (spec.kind == LawKind::BRAKE) wires[type].reset(new WireLaw(BrakeLaw(spec.brake).envelope()));
  else wires[type].reset();
  beams[type].reset(spec.kind == LawKind::BEAM ? new BeamLaw(spec.beam) : nullptr);
  setflag[type] = 1;
}

void BondWirenet::coeff(int narg, char **arg)
{
  if (narg < 2) error->all(FLERR, "bond_coeff for bond_style wirenet: expected 'bond_coeff T wire ...' (see doc/bond_wirenet.md)");
  if (!allocated) allocate();
  int ilo, ihi;
  force->bounds(arg[0], atom->nbondtypes, ilo, ihi);
  if (ilo < 1 || ihi > atom->nbondtypes || ilo > ihi) {
    std::string msg = std::string("bond_coeff ") + arg[0] + ": bond type out of range 1.." + std::to_string(atom->nbondtypes);
    error->all(FLERR, msg.c_str());
  }
  std::vector<std::string> args(arg + 1, arg + narg);
  try {
    const BondTypeSpec spec = parse_bond_coeff(args);
    for (int t = ilo; t <= ihi; t++) set_type(t, spec);
  } catch (const std::invalid_argument &e) {
    std::string msg = std::string("bond_coeff ") + arg[0] + ": " + e.what();
    error->all(FLERR, msg.c_str());
  }
}

/* ------------------------------------------------------------------------------------------- */

void BondWirenet::init()
{
  if (!allocated) error->all(FLERR, "bond_style wirenet: no bond_coeff given (every bond type needs one)");
  for (int t = 1; t <= atom->nbondtypes; t++)
    if (!setflag[t]) {
      std::string msg = "bond_style wirenet: bond type " + std::to_string(t) + " has no bond_coeff";
      error->all(FLERR, msg.c_str());
    }
  Bond::init();
}

void BondWirenet::init_style()
{
  if (!atom->molecular || !atom->radius_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "bond_style wirenet needs spheres with bonds: use atom_style hybrid granular molecular");
  if (!force->newton_bond)
    error->all(FLERR, "bond_style wirenet needs newton_bond on: put 'newton off on' (or 'newton on') before read_data");
  ensure_history_fix();
  if (!duplicates_checked) check_duplicate_bonds();

  any_beam = any_strength = any_beam_damping = any_damping = 0;
  for (int t = 1; t <= atom->nbondtypes; t++) {
    if (wires[t] && wires[t]->params().damping > 0.0) any_damping = 1;
    if (beams[t]) {
      any_beam = 1;
      if (beams[t]->breakable()) any_strength = 1;
      if (beams[t]->damped()) any_beam_damping = any_damping = 1;
    }
  }
  // damping reads the velocities of both nodes, also of a ghost partner
  history->use_velocities(any_damping);
  list_version = -1;  // the damping coefficients of the beam list may have changed
  // Node orientations cost a pass over the beam ends and a ghost exchange every step: track
  // them only when a beam bond exists (a hexagonal net with the deck's rope type declared has none;
  // bonds are never created during a run, so the answer holds until the next init).
  std::vector<char> beam_types;
  if (any_beam && beam_bonds_present()) {
    beam_types.assign(atom->nbondtypes + 1, 0);
    for (int t = 1; t <= atom->nbondtypes; t++) beam_types[t] = beams[t] ? 1 : 0;
  }
  history->use_orientations(beam_types);
  // the ghosts reach the longest bond now; the history fix follows it as the net stretches
  history->set_bond_reach(history->max_bond_length_global());
  if (comm->me == 0) report_types();
}

// A bond listed twice (as 1 2 and 1 2, or 1 2 and 2 1) would act twice. With the default
// special_bonds LIGGGHTS' read_data stops on it first ("1-3 bond count is inconsistent"); with
// special_bonds lj/coul 0 1 1 it passes read_data. Every rank gathers all bonds as (smaller tag,
// larger tag) once: a few bytes per bond, at the first run only.
void BondWirenet::check_duplicate_bonds()
{
  duplicates_checked = true;
  std::vector<int> mine;
  for (int i = 0; i < atom->nlocal; i++)
    for (int m = 0; m < atom->num_bond[i]; m++) {
      const int a = atom->tag[i], b = atom->bond_atom[i][m];
      mine.push_back(a < b ? a : b);
      mine.push_back(a < b ? b : a);
    }
  const int nprocs = comm->nprocs, count = (int)mine.size();
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<int> all(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), count, MPI_INT, all.data(), counts.data(), displs.data(), MPI_INT, world);
  std::vector<long long> keys(all.size() / 2);
  for (size_t k = 0; k < keys.size(); k++)
    keys[k] = ((long long)all[2 * k] << 32) | (long long)(unsigned int)all[2 * k + 1];
  std::sort(keys.begin(), keys.end());
  for (size_t k = 1; k < keys.size(); k++)
    if (keys[k] == keys[k - 1]) {
      char msg[256];
      snprintf(msg, sizeof(msg),
               "bond_style wirenet: the bond between atoms %lld and %lld is listed twice in the data file "
               "(it would act twice); remove one of the two lines", keys[k] >> 32, keys[k] & 0xffffffffLL);
      error->all(FLERR, msg);
    }
}

bool BondWirenet::beam_bonds_present() const
{
  int mine = 0;
  for (int i = 0; i < atom->nlocal && !mine; i++)
    for (int m = 0; m < atom->num_bond[i]; m++) {
      const int t = atom->bond_type[i][m];
      if (t > 0 && beams[t]) { mine = 1; break; }
    }
  int all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, world);
  return all != 0;
}

void BondWirenet::ensure_history_fix()
{
  int ifix = modify->find_fix(HISTORY_FIX_ID);
  if (ifix < 0) {
    char id[] = "wirenet_bonds", group[] = "all", style[] = "wirenet/bonds";
    char *args[3] = { id, group, style };
    modify->add_fix(3, args);
    ifix = modify->find_fix(HISTORY_FIX_ID);
  }
  history = dynamic_cast<FixWirenetBonds *>(modify->fix[ifix]);
  if (!history) error->all(FLERR, "bond_style wirenet: fix ID wirenet_bonds is taken by another fix style; rename that fix");
  list_version = -1;
}

void BondWirenet::report_types()
{
  for (int t = 1; t <= atom->nbondtypes; t++) {
    char line[512];
    const BondTypeSpec &s = specs[t];
    if (s.kind == LawKind::WIRE) {
      const WireLaw &w = *wires[t];
      // lambda_u 0 is no slack (the decks always pass the keyword, materials.in slack_u)
      char slack[96] = "";
      if (s.wire.slack && s.wire.lambda_u > 0.0)
        snprintf(slack, sizeof(slack), ", random slack lambda_u %g lambda_f %g seed %ld", s.wire.lambda_u,
                 s.wire.lambda_f, s.wire.seed);
      snprintf(line, sizeof(line),
               "bond_style wirenet: type %d wire (%s): d = %g m, A = %g m^2, %zu curve points, rupture strain %g%s%s, damping %g\n",
               t, s.family.c_str(), s.wire.diameter, w.area(), s.wire.strain.size(), s.wire.strain.back(),
               s.wire.derived ? ", derived double twist" : "", slack, s.wire.damping);
    }
    if (s.kind == LawKind::BRAKE) {
      const BrakeLaw b(s.brake);
      char rupture[64] = "never breaks";
      if (b.breakable()) snprintf(rupture, sizeof(rupture), "breaks at %g N", *s.brake.breaking);
      snprintf(line, sizeof(line),
               "bond_style wirenet: type %d brake (%s): force %g N, stroke %g m, stiffness %g N/m, lock %g N/m, %s, damping %g\n",
               t, s.family.c_str(), s.brake.force, s.brake.stroke, s.brake.stiffness, b.lock_stiffness(), rupture,
               s.brake.damping);
    }
    if (s.kind == LawKind::BEAM) {
      const BeamLawParams &b = s.beam;
      char strength[96] = "no strength";
      if (b.strength) snprintf(strength, sizeof(strength), "strength %g Pa (tension) %g Pa (shear)", b.sigma_t, b.tau_c);
      char shape[192];
      if (b.section)
        snprintf(shape, sizeof(shape), "section A = %g m^2, Iy = %g m^4, Iz = %g m^4, J = %g m^4, orient (%g, %g, %g)",
                 b.area, b.iy, b.iz, b.torsion, b.orient[0], b.orient[1], b.orient[2]);
      else
        snprintf(shape, sizeof(shape), "d = %g m", b.diameter);
      snprintf(line, sizeof(line),
               "bond_style wirenet: type %d beam (%s): %s, E = %g Pa, nu = %g, bending %g EI, twist %g GJ, shear %s, %s, damping %g\n",
               t, s.family.c_str(), shape, b.young, b.nu, b.bending, b.twist < 0 ? b.bending : b.twist,
               b.shear == ShearModel::EULER_BERNOULLI ? "eb (12 f EI/L0^3)" : "pb (GA/L0)", strength, b.damping);
    }
    if (screen) fputs(line, screen);
    if (logfile) fputs(line, logfile);
  }
}

/* ------------------------------------------------------------------------------------------- */

void BondWirenet::build_list()
{
  wire_list.clear();
  beam_list.clear();
  section_list.clear();
  // beams of a general section, paired after the circular ones
  struct Pending { BeamConst<double> b; BeamSection<double> s; int i, j, m, type; };
  std::vector<Pending> sections;
  const int nlocal = atom->nlocal;
  const int *num_bond = atom->num_bond;
  int **bond_atom = atom->bond_atom;
  int **bond_type = atom->bond_type;
  double **x = atom->x;
  nbeam = 0;
  law_scale = history->law_scale();
  inv_scale2 = 1.0 / (law_scale * law_scale);
  for (int i = 0; i < nlocal; i++)
    for (int m = 0; m < num_bond[i]; m++) {
      const int type = bond_type[i][m];
      if (type <= 0) continue;
      const int j = domain->closest_image(i, atom->map(bond_atom[i][m]));
      const Entry e = { i, j, type, m, history->record(i, m) };
      if (wires[type]) {
        // a wire record is set at the bond's first run, like a beam's (below)
        if (e.h[FixWirenetBonds::L0] == 0.0) {
          const double d[3] = { x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2] };
          init_record(e, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
        if (e.h[FixWirenetBonds::L0] < 0.0) continue;  // broken, awaiting removal
        WireEntry w;
        static_cast<Entry &>(w) = e;
        wires[type]->prepare(e.h, w.k, law_scale);
        w.zeta = wires[type]->params().damping;  // a brake's too
        w.law = wires[type].get();
        wire_list.push_back(w);
        continue;
      }
      // a beam record is set at the bond's first run (the lists are built in compute()) and
      // never changes afterwards, so the force loop can work on a copy
      if (e.h[FixWirenetBonds::L0] == 0.0) {
        const double d[3] = { x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2] };
        init_record(e, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
      }
      if (e.h[FixWirenetBonds::L0] < 0.0) continue;  // broken, awaiting removal
      BeamConst<double> b;
      beams[type]->prepare(e.h, b, law_scale);
      if (beams[type]->has_section()) {  // no damping, no strength (refused by the law)
        sections.push_back({ b, BeamSection<double>(), i, j, m, type });
        beams[type]->prepare_section(e.h, sections.back().s);
        continue;
      }
      if (beams[type]->damped()) {
        const double *rm = atom->rmass, *rad = atom->radius;
        beams[type]->set_damping(b.l0, rm[i], rm[j], 0.4 * rm[i] * rad[i] * rad[i], 0.4 * rm[j] * rad[j] * rad[j], b);
      }
      if (nbeam % 2 == 0) beam_list.emplace_back();
      BeamPair &p = beam_list.back();
      const int k = nbeam++ % 2;
      set_lane(p.c, k, b);
      p.i[k] = i;
      p.j[k] = j;
      p.m[k] = m;
      p.type[k] = type;
      p.n = k + 1;
    }
  pad_last_pair(nullptr);
  ncircular = (int)beam_list.size();
  for (size_t q = 0; q < sections.size(); q++) {
    const Pending &s = sections[q];
    const int k = q % 2;
    if (k == 0) {
      beam_list.emplace_back();
      section_list.emplace_back();
    }
    BeamPair &p = beam_list.back();
    set_lane(p.c, k, s.b);
    set_lane(section_list.back(), k, s.s);
    p.i[k] = s.i;
    p.j[k] = s.j;
    p.m[k] = s.m;
    p.type[k] = s.type;
    p.n = k + 1;
  }
  nbeam += (int)sections.size();
  if (!sections.empty()) pad_last_pair(&section_list.back());
  // at most one damping load per bond and compute(): reserved with the list, so that the
  // kernels' push_back never allocates
  if (any_damping) {
    wire_damp.reserve(wire_list.size());
    beam_damp.reserve(2 * beam_list.size());
  }
  list_version = history->list_version();
}

// A pair with one bond repeats it in lane 1: computed, not applied (n = 1). s: the pair's
// section constants, if it is a pair of general sections.
void BondWirenet::pad_last_pair(BeamSection<Lanes> *s)
{
  if (beam_list.empty() || beam_list.back().n != 1) return;
  BeamPair &p = beam_list.back();
  set_lane(p.c, 1, lane(p.c, 0));
  p.i[1] = p.i[0];
  p.j[1] = p.j[0];
  p.m[1] = p.m[0];
  p.type[1] = p.type[0];
  if (s) set_lane(*s, 1, lane(*s, 0));
}

void BondWirenet::init_record(const Entry &e, double length)
{
  if (length <= 0.0) {
    char msg[256];
    snprintf(msg, sizeof(msg), "bond_style wirenet: bond %d-%d has zero length (two nodes at one point)",
             atom->tag[e.i], atom->tag[e.j]);
    error->one(FLERR, msg);
  }
  if (wires[e.type]) {
    wires[e.type]->init_bond(e.h, length, atom->tag[e.i], atom->tag[e.j]);
  } else {
    try {
      beams[e.type]->init_bond(e.h, Eigen::Vector3d(atom->x[e.i]), Eigen::Vector3d(atom->x[e.j]),
                               BeamLaw::Rotation(history->rotation(e.i)), BeamLaw::Rotation(history->rotation(e.j)));
    } catch (const std::invalid_argument &err) {
      char msg[512];
      snprintf(msg, sizeof(msg), "bond_style wirenet: bond %d-%d (type %d): %s", atom->tag[e.i], atom->tag[e.j], e.type,
               err.what());
      error->one(FLERR, msg);
    }
  }
}

// f (the force array) comes from the caller, read once per compute: the rupture path's call
// would otherwise make the compiler reload it for every bond. The plastic work is a function of
// the bond's state, summed when the tally is read (sync_plastic), not here. DAMPED false
// compiles the damper out: its branch alone (a push_back) cost the undamped loop 12 % (perf of
// the YADE punch, 2026-11-28).
template <bool DAMPED>
__attribute__((always_inline)) inline void BondWirenet::compute_wire(int index, const WireEntry &e, double dx, double dy, double dz, double r, int eflag,
                                                                     double **f)
{
  double *h = e.h;
  double tension;
  if (!e.law->tension(e.k, r - h[W_L0], h, tension)) {
    double **x = atom->x;
    const double mid[3] = { x[e.i][0] + 0.5 * dx, x[e.i][1] + 0.5 * dy, x[e.i][2] + 0.5 * dz };
    // a rupture leaves the state as it was: its plastic work goes to the tally for good, and the
    // elastic energy of the last state (on the envelope, at the largest elongation) is released
    // (both at scale 1, as sum_plastic)
    history->add_tally(e.type, FixWirenetBonds::PLASTIC, e.law->plastic_work(e.k, h, law_scale) * inv_scale2);
    history->break_bond(e.i, e.m, mid, r - h[W_L0], 0.5 * h[W_FMAX] * h[W_FMAX] / h[W_KU] * inv_scale2);
    return;
  }
  if (tension == 0.0) return;  // slack or shortened: no force, no damping
  double pull = tension;
  const double zeta = e.zeta;
  if (DAMPED && zeta > 0.0) {
    // viscous damping of the taut wire along its axis, c = 2 zeta sqrt(k_u m_eff); the wire
    // never pushes: the damped force is at least zero
    const double *vi = atom->v[e.i], *vj = atom->v[e.j];
    const double vn = ((vj[0] - vi[0]) * dx + (vj[1] - vi[1]) * dy + (vj[2] - vi[2]) * dz) / r;
    const double mi = atom->rmass[e.i], mj = atom->rmass[e.j];
    const double c = 2.0 * zeta * sqrt(e.k.ku * mi * mj / (mi + mj));
    pull = tension + c * vn;
    if (pull < 0.0) pull = 0.0;
    if (keep_damp_loads) wire_damp.push_back({ index, (pull - tension) / r });
  }
  const double fr = pull / r;
  f[e.i][0] += fr * dx; f[e.i][1] += fr * dy; f[e.i][2] += fr * dz;
  f[e.j][0] -= fr * dx; f[e.j][1] -= fr * dy; f[e.j][2] -= fr * dz;
  if (evflag) {
    // recoverable elastic energy of the unloading branch
    const double ebond = eflag ? 0.5 * tension * tension / h[W_KU] : 0.0;
    elastic_energy[e.type] += ebond;
    ev_tally(e.i, e.j, atom->nlocal, force->newton_bond, ebond, -fr, -dx, -dy, -dz);
  }
}

template <bool DAMPED>
void BondWirenet::compute_wires(int eflag, double **x, double **f)
{
  const int n = (int)wire_list.size();
  for (int q = 0; q < n; q++) {
    const WireEntry &e = wire_list[q];
    if (e.h[FixWirenetBonds::L0] < 0.0) continue;  // broken since the list was built
    const double dx = x[e.j][0] - x[e.i][0];
    const double dy = x[e.j][1] - x[e.i][1];
    const double dz = x[e.j][2] - x[e.i][2];
    compute_wire<DAMPED>(q, e, dx, dy, dz, sqrt(dx * dx + dy * dy + dz * dz), eflag, f);
  }
}

namespace {

inline double at(double v, int) { return v; }
inline double at(Lanes v, int k) { return v[k]; }

// Add lane k of a bond load to nodes i and j (flat force and torque arrays).
template <typename T>
inline void apply(const BeamLoad<T> &o, int k, int i, int j, double *f, double *t)
{
  double *fi = f + 3 * i, *fj = f + 3 * j, *ti = t + 3 * i, *tj = t + 3 * j;
  for (int d = 0; d < 3; d++) {
    const double fd = at(o.force_i[d], k);
    fi[d] += fd;
    fj[d] -= fd;
    ti[d] += at(o.torque_i[d], k);
    tj[d] += at(o.torque_j[d], k);
  }
}

}  // namespace

// Positions and orientations of a beam bond's two nodes, as the beam law reads them.
static inline void gather_nodes(const double *x, const double *rot, int i, int j,
                                BeamNodes<double> &n)
{
  for (int c = 0; c < 3; c++) {
    n.xi[c] = x[3 * i + c];
    n.xj[c] = x[3 * j + c];
  }
  for (int c = 0; c < 9; c++) {
    n.ri[c] = rot[9 * i + c];
    n.rj[c] = rot[9 * j + c];
  }
}

// A beam bond reached its strength: record the rupture as a wire's (released energy = its strain
// energy at this step) and zero its lane, so the bond exerts nothing until it is removed from
// the bond list at the next re-neighbouring.
void BondWirenet::break_beam(BeamPair &p, int k)
{
  const int i = p.i[k], j = p.j[k];
  BeamConst<double> b = lane(p.c, k);
  BeamNodes<double> n;
  gather_nodes(atom->x[0], history->rotations(), i, j, n);
  BeamResult out;
  BeamLaw::load<true>(b, n, out);
  const double d[3] = { n.xj[0] - n.xi[0], n.xj[1] - n.xi[1], n.xj[2] - n.xi[2] };
  const double mid[3] = { n.xi[0] + 0.5 * d[0], n.xi[1] + 0.5 * d[1], n.xi[2] + 0.5 * d[2] };
  const double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  history->break_bond(i, p.m[k], mid, length - b.l0, out.energy);
  b.ka = b.kp = b.km = b.kf = b.kt = 0.0;
  b.sa = b.sm = b.ss = b.st = 0.0;
  b.ca = b.cs = b.cb = b.ct = 0.0;
  set_lane(p.c, k, b);
  // the copy in lane 1 of an odd last pair is not applied; keep it identical all the same
  if (p.n == 1 && k == 0) set_lane(p.c, 1, b);
}

// The beam bonds of pairs q0..q1-1, a pair per step of the loop, on flat views of the per-atom
// arrays (LAMMPS' 2d arrays are one block each). Bonds bent beyond the series, and all bonds when
// energy or virial are tallied, go one at a time. STRENGTH: check each bond's failure index (a
// type has `strength`); a bond that fails exerts nothing from this step on. SECTION: the pairs
// of general sections (after the circular ones; never with strength).
template <int EVFLAG, bool STRENGTH, bool SECTION>
void BondWirenet::compute_beams(int eflag, int q0, int q1)
{
  static_assert(!(STRENGTH && SECTION), "a general section has no strength");
  const double *x = atom->x[0], *rot = history->rotations();
  double *f = atom->f[0], *t = atom->torque[0];
  const int nlocal = atom->nlocal, newton_bond = force->newton_bond;
  for (int q = q0; q < q1; q++) {
    BeamPair &p = beam_list[q];
    const int nb = p.n;  // bonds to apply: lane 1 of a pair with one bond is a copy
    if constexpr (!EVFLAG) {
      const double *xi0 = x + 3 * p.i[0], *xi1 = x + 3 * p.i[1];
      const double *xj0 = x + 3 * p.j[0], *xj1 = x + 3 * p.j[1];
      const double *ri0 = rot + 9 * p.i[0], *ri1 = rot + 9 * p.i[1];
      const double *rj0 = rot + 9 * p.j[0], *rj1 = rot + 9 * p.j[1];
      BeamNodes<Lanes> n;
      for (int c = 0; c < 3; c++) {
        n.xi[c] = Lanes{ xi0[c], xi1[c] };
        n.xj[c] = Lanes{ xj0[c], xj1[c] };
      }
      for (int c = 0; c < 9; c++) {
        n.ri[c] = Lanes{ ri0[c], ri1[c] };
        n.rj[c] = Lanes{ rj0[c], rj1[c] };
      }
      BeamLoad<Lanes> out;
      bool done;
      if constexpr (SECTION) done = BeamLaw::load_section<false>(p.c, section_list[q - ncircular], n, out);
      else done = BeamLaw::load<false, STRENGTH>(p.c, n, out);
      if (done) {
        for (int k = 0; k < nb; k++) {
          if (STRENGTH && out.fail[k] >= 1.0) break_beam(p, k);
          else apply(out, k, p.i[k], p.j[k], f, t);
        }
        continue;
      }
    }
    for (int k = 0; k < nb; k++) {
      const int i = p.i[k], j = p.j[k];
      BeamNodes<double> n;
      gather_nodes(x, rot, i, j, n);
      BeamResult out;
      if constexpr (SECTION) BeamLaw::load_section<EVFLAG != 0>(lane(p.c, k), lane(section_list[q - ncircular], k), n, out);
      else BeamLaw::load<EVFLAG != 0, STRENGTH>(lane(p.c, k), n, out);
      if (STRENGTH && out.fail >= 1.0) {
        break_beam(p, k);
        continue;
      }
      apply(out, 0, i, j, f, t);
      if (EVFLAG) {
        // energy is exact; the virial holds the axial part only (the bond force is not central)
        const double dx = n.xi[0] - n.xj[0], dy = n.xi[1] - n.xj[1], dz = n.xi[2] - n.xj[2];
        const double r = sqrt(dx * dx + dy * dy + dz * dz);
        ev_tally(i, j, nlocal, newton_bond, eflag ? out.energy : 0.0, -out.axial / r, dx, dy, dz);
        if (eflag) elastic_energy[p.type[k]] += out.energy;
      }
    }
  }
}

void BondWirenet::compute(int eflag, int vflag)
{
  if (eflag || vflag) ev_setup(eflag, vflag);
  else evflag = 0;
  if (history->list_version() != list_version) build_list();
  history->take_pair_forces();  // no-op unless fix wirenet/contactwork pair asked for them

  // A run's set-up: the tally is up to date (the last run's post_run, or a restart file's
  // totals); the sum it follows starts from the bonds present now, with the laws as they are now.
  // (A bond_coeff between runs that moves a yielded wire's envelope at its largest elongation
  // changes its force there without work: its elastic energy and plastic work then move by
  // opposite amounts, and their sum stays.)
  if (update->setupflag) {
    sum_plastic(plastic_seen);
    plastic_synced = computes;
  }
  computes++;

  double **x = atom->x, **f = atom->f;
  const size_t ntypes = (size_t)atom->nbondtypes + 1;
  elastic_energy.assign(ntypes, 0.0);
  wire_damp.clear();
  beam_damp.clear();
  keep_damp_loads = any_damping && history->damping_tallied();
  if (any_damping) compute_wires<true>(eflag, x, f);
  else compute_wires<false>(eflag, x, f);
  if (!beam_list.empty()) {
    const int npair = (int)beam_list.size();
    if (any_strength) {
      if (evflag) compute_beams<1, true, false>(eflag, 0, ncircular);
      else compute_beams<0, true, false>(eflag, 0, ncircular);
    } else {
      if (evflag) compute_beams<1, false, false>(eflag, 0, ncircular);
      else compute_beams<0, false, false>(eflag, 0, ncircular);
    }
    if (ncircular < npair) {
      if (evflag) compute_beams<1, false, true>(eflag, ncircular, npair);
      else compute_beams<0, false, true>(eflag, ncircular, npair);
    }
    if (any_beam_damping) damp_beams();
  }
  // the tally at the end of the step (every rank asks: its ghost update is collective); the
  // set-up's velocities are full-step ones already
  if (keep_damp_loads) {
    if (update->setupflag) tally_damping();
    else history->request_damping_tally(this);
  }
  if (eflag) history->set_elastic_energy(elastic_energy);
  if (update->setupflag) report_timestep();
}

// At a scale s != 1 (fix_modify wirenet_bonds scale) the work is the law's at scale 1, s^-2
// times that at s: a change of scale maps every state onto the same place of its envelope, so
// the sum does not jump, and the tally counts what the net at scale 1 would have done.
void BondWirenet::sum_plastic(std::vector<double> &per_type) const
{
  per_type.assign((size_t)atom->nbondtypes + 1, 0.0);
  for (const WireEntry &e : wire_list)
    if (e.h[FixWirenetBonds::L0] > 0.0) per_type[e.type] += e.law->plastic_work(e.k, e.h, law_scale) * inv_scale2;
}

// A bond's state at the new scale: its largest elongation and the force there, ratio times.
void BondWirenet::rescale_wire_states(double ratio)
{
  const int *num_bond = atom->num_bond;
  int **bond_type = atom->bond_type;
  for (int i = 0; i < atom->nlocal; i++)
    for (int m = 0; m < num_bond[i]; m++) {
      const int type = bond_type[i][m];
      if (type <= 0 || !wires[type]) continue;
      double *h = history->record(i, m);
      if (h[FixWirenetBonds::L0] <= 0.0) continue;  // not initialised yet, or broken
      h[W_UMAX] *= ratio;
      h[W_FMAX] *= ratio;
    }
}

// Each bond is on one rank at a time; a bond that moved to another rank leaves this rank's sum
// and enters that rank's, so the ranks' changes add up to the change of the whole net. A bond
// broken since the last call left the sum with its plastic work already in the tally (rupture).
void BondWirenet::sync_plastic()
{
  if (plastic_synced == computes || !history) return;
  sum_plastic(plastic_now);
  for (size_t t = 1; t < plastic_now.size(); t++)
    history->add_tally((int)t, FixWirenetBonds::PLASTIC, plastic_now[t] - plastic_seen[t]);
  plastic_seen.swap(plastic_now);
  plastic_synced = computes;
}

// Bond damping of the beam bonds (after their elastic forces; a broken bond's lane has zero
// coefficients): forces and torques, kept for the tally at the end of the step.
void BondWirenet::damp_beams()
{
  const double *x = atom->x[0], *v = atom->v[0], *w = atom->omega[0];
  double *f = atom->f[0], *t = atom->torque[0];
  for (int q = 0; q < (int)beam_list.size(); q++) {
    const BeamPair &p = beam_list[q];
    for (int k = 0; k < p.n; k++) {
      const double ca = p.c.ca[k], cs = p.c.cs[k], cb = p.c.cb[k], ct = p.c.ct[k];
      if (ca == 0.0 && cs == 0.0 && cb == 0.0 && ct == 0.0) continue;  // undamped type or broken
      const int i = p.i[k], j = p.j[k];
      BeamDampLoad d;
      d.i = i;
      d.j = j;
      d.type = p.type[k];
      BeamLaw::damp(ca, cs, cb, ct, x + 3 * i, x + 3 * j, v + 3 * i, v + 3 * j, w + 3 * i, w + 3 * j, d.f, d.ti, d.tj);
      for (int c = 0; c < 3; c++) {
        f[3 * i + c] += d.f[c];
        f[3 * j + c] -= d.f[c];
        t[3 * i + c] += d.ti[c];
        t[3 * j + c] += d.tj[c];
      }
      if (keep_damp_loads) beam_damp.push_back(d);
    }
  }
}

// The power the dampers of this step's compute() take out of the nodes' motion at the end of the
// step, P = -sum F.v, per bond type (positions have not moved since the forces). A force applied
// at step n works over the half kicks on either side of it: the kinetic energy at step n holds
// P(n) dt/2, the rest (pending) goes in at step n + 1. The set-up's forces start a run's first
// step: their half goes in at step 1 (a restart's or a new run's set-up replaces the last half of
// the run before, whose forces were evaluated again).
void BondWirenet::tally_damping()
{
  double **x = atom->x, **v = atom->v, **w = atom->omega;
  const size_t ntypes = (size_t)atom->nbondtypes + 1;
  damping_power.assign(ntypes, 0.0);
  if (damping_pending.size() != ntypes) damping_pending.assign(ntypes, 0.0);
  for (const WireDampLoad &d : wire_damp) {
    const WireEntry &e = wire_list[d.e];
    double vn = 0.0;
    for (int c = 0; c < 3; c++) vn += (v[e.j][c] - v[e.i][c]) * (x[e.j][c] - x[e.i][c]);
    damping_power[e.type] += d.fr * vn;
  }
  for (const BeamDampLoad &d : beam_damp) {
    double p = 0.0;
    for (int c = 0; c < 3; c++)
      p += d.f[c] * (v[d.j][c] - v[d.i][c]) - d.ti[c] * w[d.i][c] - d.tj[c] * w[d.j][c];
    damping_power[d.type] += p;
  }
  const double half = 0.5 * update->dt;
  for (size_t t = 1; t < ntypes; t++) {
    const double now = damping_power[t] * half;
    if (!update->setupflag && (now != 0.0 || damping_pending[t] != 0.0))
      history->add_tally((int)t, FixWirenetBonds::DAMPING, damping_pending[t] + now);
    damping_pending[t] = now;
  }
  wire_damp.clear();
  beam_damp.clear();
}

// Stable time step of the bonds present: per bond, the two-node axial and rotational
// frequencies doubled (a node shared by two bonds moving in antiphase), dt = 2 / omega_max.
void BondWirenet::stable_frequencies(double w2[2]) const
{
  const double *rmass = atom->rmass, *radius = atom->radius;
  double w2_trans = 0.0, w2_rot = 0.0;
  for (const WireEntry &e : wire_list) {
    if (e.h[FixWirenetBonds::L0] <= 0.0) continue;
    w2_trans = fmax(w2_trans, 2.0 * e.h[W_KU] * (1.0 / rmass[e.i] + 1.0 / rmass[e.j]));
  }
  for (int q = 0; q < (int)beam_list.size(); q++)
    for (int k = 0; k < beam_list[q].n; k++) {
      const BeamPair &p = beam_list[q];
      BeamConst<double> b = lane(p.c, k);
      if (q >= ncircular) {
        // a general section: the stiffer axis (mean + |half difference|)
        const BeamSection<double> s = lane(section_list[q - ncircular], k);
        b.kp += fabs(s.kpd);
        b.km = fabs(b.km) + fabs(s.kmd);
        b.kf += fabs(s.kfd);
      }
      const int i = p.i[k], j = p.j[k];
      // axial or shear (4 Cs / l0^2) translation; rotation: the larger eigenvalue of the end
      // moments, Kb + Cs + |Cs - Kb|, plus twist
      const double kt = fmax(b.ka, 2.0 * b.kf / (b.l0 * b.l0));
      const double kr = b.kp + fabs(b.km) + 2.0 * b.kt;
      const double inv_m = 1.0 / rmass[i] + 1.0 / rmass[j];
      const double inv_i = 1.0 / (0.4 * rmass[i] * radius[i] * radius[i]) +
                           1.0 / (0.4 * rmass[j] * radius[j] * radius[j]);
      w2_trans = fmax(w2_trans, 2.0 * kt * inv_m);
      w2_rot = fmax(w2_rot, 2.0 * kr * inv_i);
    }
  w2[0] = w2_trans;
  w2[1] = w2_rot;
}

void BondWirenet::report_timestep()
{
  double local[2], global[2];
  stable_frequencies(local);
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, world);
  if (comm->me != 0 || (global[0] == 0.0 && global[1] == 0.0)) return;
  const double dt_trans = global[0] > 0 ? 2.0 / sqrt(global[0]) : INFINITY;
  const double dt_rot = global[1] > 0 ? 2.0 / sqrt(global[1]) : INFINITY;
  const double dt = fmin(dt_trans, dt_rot);
  char line[256];
  snprintf(line, sizeof(line), "bond_style wirenet: stable time step estimate %g s (translation %g s, rotation %g s)\n",
           dt, dt_trans, dt_rot);
  if (screen) fputs(line, screen);
  if (logfile) fputs(line, logfile);
  if (update->dt > dt) {
    snprintf(line, sizeof(line), "bond_style wirenet: timestep %g s exceeds the stable estimate %g s", update->dt, dt);
    error->warning(FLERR, line);
  }
}

bool BondWirenet::bond_state(int i, int m, int j, BondState &s) const
{
  const double *h = history ? static_cast<const FixWirenetBonds *>(history)->record(i, m) : NULL;
  const int type = atom->bond_type[i][m];
  if (!h || type <= 0 || h[FixWirenetBonds::L0] <= 0.0) return false;
  double **x = atom->x;
  const double d[3] = { x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2] };
  s.length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  s.length0 = h[FixWirenetBonds::L0];
  if (wires[type]) {
    s.tension = wires[type]->tension_const(s.length - s.length0, h, history->law_scale());
    s.shear = s.moment = 0.0;
  } else {
    BeamResult out;
    beams[type]->evaluate(h, x[i], x[j], history->rotation(i), history->rotation(j), out);
    s.tension = out.axial;
    s.shear = out.shear;
    s.moment = out.moment;
  }
  return true;
}

double BondWirenet::single(int, double, int, int, double &fforce)
{
  // The force depends on per-bond history that single() cannot reach: use compute wirenet/local.
  fforce = 0.0;
  return 0.0;
}

/* ------------------------------------------------------------------------------------------- */

void BondWirenet::write_restart(FILE *fp)
{
  for (int t = 1; t <= atom->nbondtypes; t++) {
    const std::vector<double> v = specs[t].serialize();
    const int n = (int)v.size(), nf = (int)specs[t].family.size();
    fwrite(&n, sizeof(int), 1, fp);
    fwrite(v.data(), sizeof(double), n, fp);
    fwrite(&nf, sizeof(int), 1, fp);
    fwrite(specs[t].family.data(), 1, nf, fp);
  }
}

void BondWirenet::read_restart(FILE *fp)
{
  allocate();
  for (int t = 1; t <= atom->nbondtypes; t++) {
    int n = 0, nf = 0;
    if (comm->me == 0 && fread(&n, sizeof(int), 1, fp) != 1) error->one(FLERR, "bond_style wirenet: truncated restart file");
    MPI_Bcast(&n, 1, MPI_INT, 0, world);
    std::vector<double> v(n);
    if (comm->me == 0 && fread(v.data(), sizeof(double), n, fp) != (size_t)n) error->one(FLERR, "bond_style wirenet: truncated restart file");
    MPI_Bcast(v.data(), n, MPI_DOUBLE, 0, world);
    if (comm->me == 0 && fread(&nf, sizeof(int), 1, fp) != 1) error->one(FLERR, "bond_style wirenet: truncated restart file");
    MPI_Bcast(&nf, 1, MPI_INT, 0, world);
    std::string family(nf, ' ');
    if (comm->me == 0 && nf && fread(&family[0], 1, nf, fp) != (size_t)nf) error->one(FLERR, "bond_style wirenet: truncated restart file");
    MPI_Bcast(&family[0], nf, MPI_CHAR, 0, world);
    try {
      set_type(t, BondTypeSpec::deserialize(v, family));
    } catch (const std::exception &e) {
      error->all(FLERR, "bond_style wirenet: corrupt bond coefficients in the restart file");
    }
  }
}

double BondWirenet::memory_usage()
{
  return Bond::memory_usage() + (double)wire_list.capacity() * sizeof(WireEntry) +
         (double)beam_list.capacity() * sizeof(BeamPair) +
         (double)section_list.capacity() * sizeof(WireNet::BeamSection<WireNet::Lanes>);
}
