/* WireNet: fix wirenet/body. See doc/fix_wirenet_body.md.

   Each step: initial_integrate moves the body (kinematic: the prescribed pose at the new time;
   free: half kick with the last force and torque, then drift, WireNet::RigidBody); post_force
   finds the contacts of this rank's own nodes with the exact surface (bounding-sphere pre-test,
   then the shape's nearest-point query in the body frame), adds the contact forces to the nodes
   and sums the reaction on the body, over all ranks for a free body (its motion needs it); a
   kinematic body reduces its sums only when an output asks (reduce()). final_integrate gives
   the free body its second half kick; end_of_step integrates the power of the contact forces
   on the nodes. Every rank holds the whole body state and integrates it identically; the floors'
   contacts depend on that state alone, so every rank computes them, identically, without
   communication. */

#include "fix_wirenet_body.h"
#include "wirenet_fix_args.h"
#include "wirenet_local_damping.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "memory.h"
#include "neighbor.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

using WireNet::FixArgs::number;
using WireNet::FixArgs::text;
using WireNet::FixArgs::value;
using WireNet::FixArgs::vector3;
namespace FixArgs = WireNet::FixArgs;

const int NHIST = 4;      // tangential spring x y z, in contact
// The global restart record: its version, the body state (NSTATE values), the floors' sums
// (NFLOOR_SUMS) and their springs (3 per floor and point). Versions 1 (36 or 37 values) and 2 (45)
// had no version number: their first value, the free flag, is 0 or 1.
const int RECORD_VERSION = 3;
const int NSTATE = 45;
const int NFLOOR_SUMS = 7;  // work, dissipation, impulse (3), floors, points per floor

bool is_number(const char *s)
{
  char *end = NULL;
  strtod(s, &end);
  return end != s && *end == '\0';
}

// 'damping A' at arg[k]: Cundall's local damping fraction, 0 <= A < 1; k advances past it
double damping_value(int narg, char **arg, int &k)
{
  const double a = value(narg, arg, k, "damping", 0.0, false);
  if (!(a < 1.0)) throw std::invalid_argument("damping must be in [0, 1) (got " + text(a) + ")");
  return a;
}

// Local damping of a resultant, component by component, as fix wirenet/damping does for the nodes
Vector3d locally_damped(const Vector3d &f, const Vector3d &u, double alpha)
{
  Vector3d out = f;
  for (int d = 0; d < 3; d++) out[d] += WireNet::local_damping(f[d], u[d], alpha);
  return out;
}

void to_array(const Quaterniond &q, double *a) { a[0] = q.w(); a[1] = q.x(); a[2] = q.y(); a[3] = q.z(); }
Quaterniond from_array(const double *a) { return Quaterniond(a[0], a[1], a[2], a[3]).normalized(); }

// An OBJ index: digits only, 1 to INT_MAX ('2.7', '-1', '4294967300' are not)
bool obj_index(const std::string &w, long &i)
{
  if (w.empty() || w.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  i = strtol(w.c_str(), NULL, 10);
  return errno == 0 && i >= 1 && i <= std::numeric_limits<int>::max();
}

// Wavefront OBJ subset: 'v x y z' and 'f i j k ...' (1-based; 'i/t/n' forms allowed). A word
// that is not what it must be is named with the file and line: each vertex 3 finite numbers,
// each face index a whole number naming a vertex of the file.
WireNet::PolyhedronShape read_obj(const std::string &path)
{
  std::ifstream in(path.c_str());
  if (!in) throw std::invalid_argument("polyhedron: cannot open '" + path + "'");
  std::vector<Vector3d> v;
  std::vector<std::vector<int> > f;
  std::vector<int> face_line;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    lineno++;
    const std::string at = "polyhedron: '" + path + "' line " + std::to_string(lineno) + ": ";
    std::istringstream w(line);
    std::string tag;
    if (!(w >> tag) || tag[0] == '#') continue;
    if (tag == "v") {
      std::vector<std::string> words;
      for (std::string x; w >> x;) words.push_back(x);
      if (words.size() != 3) throw std::invalid_argument(at + "a vertex is 'v X Y Z'");
      Vector3d p;
      for (int d = 0; d < 3; d++)
        if (!is_number(words[d].c_str()) || !std::isfinite(p[d] = strtod(words[d].c_str(), NULL)))
          throw std::invalid_argument(at + "vertex coordinate '" + words[d] + "' is not a finite number");
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<int> loop;
      std::string item;
      while (w >> item) {
        // the vertex index, and texture and normal indices if given (i/t/n, i//n)
        std::vector<std::string> parts(1);
        for (char c : item) {
          if (c == '/') parts.push_back("");
          else parts.back().push_back(c);
        }
        long i = 0, other = 0;
        bool ok = parts.size() <= 3 && obj_index(parts[0], i);
        for (size_t k = 1; k < parts.size(); k++) ok = ok && (parts[k].empty() || obj_index(parts[k], other));
        if (!ok)
          throw std::invalid_argument(at + "face index '" + item + "' is not a whole number from 1 to " +
                                      std::to_string(std::numeric_limits<int>::max()));
        loop.push_back((int)(i - 1));
      }
      f.push_back(loop);
      face_line.push_back(lineno);
    }
  }
  for (size_t k = 0; k < f.size(); k++)
    for (int i : f[k])
      if (i >= (int)v.size())
        throw std::invalid_argument("polyhedron: '" + path + "' line " + std::to_string(face_line[k]) + ": face index " +
                                    std::to_string(i + 1) + " names a vertex the file does not have (it has " +
                                    std::to_string(v.size()) + ")");
  return WireNet::PolyhedronShape(v, f, "polyhedron");
}

// 'floor PX PY PZ NX NY NZ kn KN kt KT mu MU [gamma_n G]' at arg[k]; k advances past it
FixWirenetBody::Floor floor_value(int narg, char **arg, int &k)
{
  if (k + 6 >= narg)
    throw std::invalid_argument("'floor' needs a point and a normal: floor PX PY PZ NX NY NZ kn KN kt KT mu MU [gamma_n G]");
  FixWirenetBody::Floor fl;
  Vector3d n;
  for (int d = 0; d < 3; d++) {
    fl.point[d] = number(arg[k + 1 + d], "floor point value");
    n[d] = number(arg[k + 4 + d], "floor normal value");
  }
  if (!(n.norm() > 0.0)) throw std::invalid_argument("floor normal must not be 0 0 0");
  fl.normal = n.normalized();
  k += 7;
  // the law's values follow in this order, so that a node-law keyword after them is not taken
  const auto named = [&](const char *key, const char *after, double lo, bool lo_open) {
    if (k >= narg || strcmp(arg[k], key) != 0)
      throw std::invalid_argument(std::string("floor needs '") + key + "' after " + after + " (got " +
                                  (k < narg ? std::string("'") + arg[k] + "'" : std::string("nothing")) + ")");
    return value(narg, arg, k, std::string("floor ") + key, lo, lo_open);
  };
  fl.law.kn = named("kn", "its normal", 0.0, true);
  fl.law.kt = named("kt", "its kn", 0.0, false);
  fl.law.mu = named("mu", "its kt", 0.0, false);
  fl.law.gamma_n = k < narg && strcmp(arg[k], "gamma_n") == 0 ? value(narg, arg, k, "floor gamma_n", 0.0, false) : 0.0;
  if (fl.law.mu > 0.0 && fl.law.kt == 0.0)
    throw std::invalid_argument("floor mu " + text(fl.law.mu) + " needs a tangential stiffness: floor kt > 0");
  return fl;
}

// One contact point of the body with a floor: `depth` > 0 below the plane of unit normal n, vc
// the body's velocity at the point, m the body's mass (the damping's effective mass: the
// floor's is infinite), s the point's tangential spring (advanced only if advance). A floor
// pushes and never pulls: the damping is capped where it would (a point leaving the floor fast).
// Out: the force F on the body and its viscous part Fd; the slider's dissipation is added to
// `slip`. Returns the elastic energy of the contact.
double floor_contact(const FixWirenetBody::Law &law, double depth, const Vector3d &n, const Vector3d &vc, double m,
                     double dt, bool advance, Vector3d &s, Vector3d &F, Vector3d &Fd, double &slip)
{
  const double fe = law.kn * depth, vn = vc.dot(n);
  const double fn = std::max(0.0, fe - law.gamma_n * m * vn);
  Fd = (fn - fe) * n;
  F = fn * n;
  const double e = 0.5 * fe * depth;
  if (law.mu == 0.0) return e;  // frictionless: no spring (kt may be 0)
  // the plane does not turn: the spring stays in its tangent plane
  const double f_start = law.kt * s.norm();
  Vector3d st = s;
  if (advance) st += dt * (vc - vn * n);
  const double fmax = law.mu * fn, ft = law.kt * st.norm();
  if (ft > fmax) {
    // The slider gives way by (ft - fmax) / kt, its force going from the spring's at the start of
    // the step to the cap (trapezoid): exact for steady sliding (f_start = fmax) and for a cap
    // that shrinks under a spring at rest (ft = f_start: the energy the cap releases). The
    // released energy (ft^2 - fmax^2) / 2kt would count the step's own stretch as slip too.
    if (advance) slip += 0.5 * (f_start + fmax) * (ft - fmax) / law.kt;
    st *= fmax / ft;
  }
  if (advance) s = st;
  F -= law.kt * st;
  return e + 0.5 * law.kt * st.squaredNorm();
}

// Linear spring-dashpot normal force, tangential spring with Coulomb limit. delta > 0 overlap,
// n unit normal from the body to the node, r radius and m mass of the node; x, v, w: position,
// velocity and angular velocity of the node (i) and of the body's reference point (b); h the
// node's history (advanced only if advance). Out: force F and torque T on the node, contact
// point c (middle of the overlap). Returns the elastic energy of the contact.
double node_contact(const FixWirenetBody::Law &law, double delta, const Vector3d &n, double r, double m,
                    const Vector3d &xi, const Vector3d &vi, const Vector3d &wi, const Vector3d &xb,
                    const Vector3d &vb, const Vector3d &wb, double dt, bool advance, double *h,
                    Vector3d &F, Vector3d &T, Vector3d &c)
{
  const Vector3d a = -(r - 0.5 * delta) * n;
  c = xi + a;
  const Vector3d vrel = vi + wi.cross(a) - vb - wb.cross(c - xb);
  const double vn = vrel.dot(n);
  const double fn = law.kn * delta - law.gamma_n * m * vn;
  Vector3d s = Vector3d::Zero();
  if (h[3] != 0.0) {
    // keep the spring in the tangent plane, with its length (the contact turned)
    s = Vector3d(h[0], h[1], h[2]);
    const double len = s.norm();
    s -= s.dot(n) * n;
    const double len2 = s.norm();
    if (len2 > 0.0) s *= len / len2;
  }
  if (advance) s += dt * (vrel - vn * n);
  Vector3d ft = -law.kt * s;
  const double fmax = law.mu * std::fabs(fn), ftm = ft.norm();
  if (ftm > fmax) {
    ft *= fmax / ftm;
    s = law.kt > 0.0 ? Vector3d(-ft / law.kt) : Vector3d::Zero();
  }
  if (advance) {
    h[0] = s[0]; h[1] = s[1]; h[2] = s[2];
    h[3] = 1.0;
  }
  F = fn * n + ft;
  T = a.cross(ft);
  return 0.5 * law.kn * delta * delta + (law.kt > 0.0 ? 0.5 * ft.squaredNorm() / law.kt : 0.0);
}

}

FixWirenetBody::FixWirenetBody(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), soften(1.0), free_body(false), gravity(Vector3d::Zero()), damping(0.0), work_damping(0.0),
  x0(Vector3d::Zero()), vel_from(Vector3d::Zero()),
  vel_kin(Vector3d::Zero()), omega_kin(Vector3d::Zero()), q0(Quaterniond::Identity()), ramp(0.0),
  elapsed(0.0), motion_modified(false), pos(Vector3d::Zero()), vel(Vector3d::Zero()), omega(Vector3d::Zero()),
  f_body(Vector3d::Zero()), t_body(Vector3d::Zero()), ncontact(0.0), elastic(0.0), work_body(0.0),
  work_body_mine(0.0), work_nodes_mine(0.0), work_nodes_all(0.0), f_mean(Vector3d::Zero()), reduced_at(-1),
  hist(NULL), hist_rows(0), contacts_pending(false), candidates_pos(Vector3d::Zero()),
  candidates_valid(false), margin(0.0), f_floor(Vector3d::Zero()), t_floor(Vector3d::Zero()),
  fd_floor(Vector3d::Zero()), td_floor(Vector3d::Zero()), floor_points(0.0), floor_elastic(0.0),
  work_floor(0.0), dissipated_floor(0.0), impulse_floor(Vector3d::Zero())
{
  for (double &v : sums_mine) v = 0.0;
  windows.reset(1, 3);
  law.kn = law.kt = law.mu = law.gamma_n = 0.0;
  try {
    parse(narg, arg);
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, (std::string("fix wirenet/body: ") + e.what()).c_str());
  }
  if (!atom->radius_flag)
    error->all(FLERR, "fix wirenet/body: needs atoms with a radius (atom_style granular, sphere or hybrid with one)");
  update_pose();
  q_defined = q_shape;
  law_defined = law;

  vector_flag = 1;
  size_vector = NVECTOR;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  restart_peratom = 1;
  time_integrate = 0;

  grow_arrays(atom->nmax);
  atom->add_callback(0);
  atom->add_callback(1);
}

FixWirenetBody::~FixWirenetBody()
{
  atom->delete_callback(id, 0);
  atom->delete_callback(id, 1);
  memory->destroy(hist);
}

void FixWirenetBody::parse(int narg, char **arg)
{
  if (narg < 4) throw std::invalid_argument("missing shape (sphere, spheroid, cone, plane, box, truncated-cube, polyhedron)");
  const std::string kind = arg[3];
  int k = 4;
  // shape parameters: all numbers up to the first keyword
  auto shape_values = [&](int n, const char *usage) {
    std::vector<double> vals;
    for (int j = 0; j < n; j++) {
      if (k + j >= narg || !is_number(arg[k + j]))
        throw std::invalid_argument(std::string("'") + kind + "' needs " + usage +
                                    (k + j < narg ? std::string(" (got '") + arg[k + j] + "')" : std::string("")));
      vals.push_back(number(arg[k + j], kind + " parameter"));
    }
    k += n;
    return vals;
  };
  if (kind == "sphere") {
    std::vector<double> p = shape_values(1, "a radius R");
    shape.reset(new WireNet::SphereShape(p[0]));
  } else if (kind == "spheroid") {
    std::vector<double> p = shape_values(3, "3 semi-axes a b c");
    shape.reset(new WireNet::EllipsoidShape(p[0], p[1], p[2]));
  } else if (kind == "cone") {
    std::vector<double> p = shape_values(3, "base radius, height and tip radius R h a");
    bool round = false;
    if (k < narg && strcmp(arg[k], "tip") == 0) {
      if (k + 1 >= narg) throw std::invalid_argument("'tip' needs 'flat' or 'round'");
      const std::string t = arg[k + 1];
      if (t != "flat" && t != "round") throw std::invalid_argument("tip must be 'flat' or 'round' (got '" + t + "')");
      round = t == "round";
      k += 2;
    }
    shape.reset(new WireNet::ConeShape(p[0], p[1], p[2], round));
  } else if (kind == "plane") {
    shape.reset(new WireNet::PlaneShape());
  } else if (kind == "box") {
    std::vector<double> p = shape_values(3, "3 side lengths lx ly lz");
    shape.reset(new WireNet::PolyhedronShape(WireNet::PolyhedronShape::box(p[0], p[1], p[2])));
  } else if (kind == "truncated-cube") {
    std::vector<double> p = shape_values(2, "side and corner cut s c");
    shape.reset(new WireNet::PolyhedronShape(WireNet::PolyhedronShape::truncated_cube(p[0], p[1])));
  } else if (kind == "polyhedron") {
    if (k >= narg) throw std::invalid_argument("'polyhedron' needs an OBJ file name");
    shape.reset(new WireNet::PolyhedronShape(read_obj(arg[k])));
    k++;
  } else {
    throw std::invalid_argument("unknown shape '" + kind + "' (use sphere, spheroid, cone, plane, box, truncated-cube, polyhedron)");
  }

  double mass = -1.0;
  bool have_inertia = false, have_kn = false, have_ramp = false, have_gravity = false;
  Matrix3d inertia = Matrix3d::Zero();
  Vector3d v0 = Vector3d::Zero(), w0 = Vector3d::Zero();
  while (k < narg) {
    const std::string key = arg[k];
    if (key == "centre") {
      x0 = vector3(narg, arg, k, key);
    } else if (key == "axis") {
      const Vector3d a = vector3(narg, arg, k, key);
      if (!(a.norm() > 0.0)) throw std::invalid_argument("axis must not be 0 0 0");
      q0 = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), a.normalized());
      // FromTwoVectors is ill-conditioned for the antiparallel case; make -z exact
      if (a.normalized().dot(Vector3d::UnitZ()) < -1.0 + 1e-15) q0 = Quaterniond(0.0, 1.0, 0.0, 0.0);
      q0.normalize();
    } else if (key == "quat") {
      if (k + 4 >= narg) throw std::invalid_argument("'quat' needs 4 values: w x y z");
      double c[4];
      for (int d = 0; d < 4; d++) c[d] = number(arg[k + 1 + d], "quat value");
      const Quaterniond q(c[0], c[1], c[2], c[3]);
      if (!(q.norm() > 0.0)) throw std::invalid_argument("quat must not be 0 0 0 0");
      q0 = q.normalized();
      k += 5;
    } else if (key == "kn") {
      law.kn = value(narg, arg, k, key, 0.0, true);
      have_kn = true;
    } else if (key == "kt") {
      law.kt = value(narg, arg, k, key, 0.0, false);
    } else if (key == "mu") {
      law.mu = value(narg, arg, k, key, 0.0, false);
    } else if (key == "gamma_n") {
      law.gamma_n = value(narg, arg, k, key, 0.0, false);
    } else if (key == "vel") {
      v0 = vector3(narg, arg, k, key);
    } else if (key == "omega") {
      w0 = vector3(narg, arg, k, key);
    } else if (key == "ramp") {
      ramp = value(narg, arg, k, key, 0.0, false);
      have_ramp = true;
    } else if (key == "mass") {
      mass = value(narg, arg, k, key, 0.0, true);
    } else if (key == "inertia") {
      inertia = FixArgs::inertia(narg, arg, k);
      have_inertia = true;
    } else if (key == "gravity") {
      gravity = vector3(narg, arg, k, key);
      have_gravity = true;
    } else if (key == "mean") {
      windows.reset(FixArgs::steps(narg, arg, k, key), 3);
    } else if (key == "damping") {
      damping = damping_value(narg, arg, k);
    } else if (key == "floor") {
      floors.push_back(floor_value(narg, arg, k));
    } else {
      throw std::invalid_argument("unknown keyword '" + key + "'");
    }
  }
  if (!have_kn) throw std::invalid_argument("missing 'kn K' (normal contact stiffness, N/m)");
  if (law.mu > 0.0 && law.kt == 0.0) throw std::invalid_argument("mu " + text(law.mu) + " needs a tangential stiffness 'kt' > 0");
  free_body = mass > 0.0;
  if (!free_body) {
    if (have_inertia) throw std::invalid_argument("'inertia' needs a free body: give 'mass M'");
    if (have_gravity) throw std::invalid_argument("'gravity' acts on a free body only: give 'mass M'");
    if (damping > 0.0) throw std::invalid_argument("'damping' acts on a free body only: give 'mass M'");
    if (!floors.empty()) throw std::invalid_argument("'floor' needs a free body: give 'mass M' (a kinematic body goes where it is driven)");
    vel_kin = v0;
    omega_kin = w0;
    return;
  }
  if (have_ramp) throw std::invalid_argument("'ramp' is for a kinematic body (no 'mass')");
  if (!shape->centred())
    throw std::invalid_argument("a " + shape->name() + " cannot be a free body (its reference point is not its centre of "
                                "mass); use sphere, spheroid, box, truncated-cube or a polyhedron centred on its centroid");
  if (!have_inertia) {
    Matrix3d unit;
    if (!shape->unit_inertia(unit)) throw std::invalid_argument("missing 'inertia Ixx Iyy Izz Ixy Ixz Iyz'");
    const Matrix3d R = q0.toRotationMatrix();
    inertia = mass * R * unit * R.transpose();
    inertia = 0.5 * (inertia + inertia.transpose());
  }
  body.reset(new WireNet::RigidBody(mass, inertia));
  body->x = x0;
  body->v = v0;
  body->set_omega(w0);
  q_shape_in_body = (body->q.conjugate() * q0).normalized();
  define_floors();
}

// The body's points that can touch the floors, and a spring at rest for each floor and point
void FixWirenetBody::define_floors()
{
  if (floors.empty()) return;
  Vector3d p;
  if (shape->corners()) corners = *shape->corners();
  else if (!shape->support(Vector3d::UnitZ(), p)) throw std::invalid_argument("a " + shape->name() + " cannot touch a floor");
  floor_springs.assign(floors.size() * floor_npoints(), Vector3d::Zero());
}

int FixWirenetBody::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | FINAL_INTEGRATE | END_OF_STEP | PRE_NEIGHBOR;
}

void FixWirenetBody::init()
{
  const std::string pre = "fix wirenet/body: ";
  if (domain->xperiodic || domain->yperiodic || domain->zperiodic)
    error->all(FLERR, (pre + "periodic boundaries are not supported").c_str());
  if (strstr(update->integrate_style, "respa")) error->all(FLERR, (pre + "run_style respa is not supported").c_str());
  if (!atom->rmass_flag && !atom->mass)
    error->all(FLERR, (pre + "atoms need a mass").c_str());
  // the candidate list relies on LIGGGHTS re-neighbouring before an atom moves half the skin
  margin = (neighbor->every == 1 && neighbor->delay == 0 && neighbor->dist_check) ? neighbor->skin : 0.0;
  candidates_valid = false;
}

void FixWirenetBody::update_pose()
{
  if (free_body) {
    pos = body->x;
    vel = body->v;
    omega = body->omega();
    q_shape = (body->q * q_shape_in_body).normalized();
    return;
  }
  const double t = elapsed;
  // (vel_from is zero unless fix_modify vel changed the motion: the terms in it then add
  // exact zeros, and a run without fix_modify moves as before to the last bit)
  if (ramp > 0.0 && t < ramp) {
    pos = x0 + (t * t / (2.0 * ramp)) * (vel_kin - vel_from) + t * vel_from;
    vel = (t / ramp) * (vel_kin - vel_from) + vel_from;
  } else {
    pos = x0 + (t - 0.5 * ramp) * vel_kin + (0.5 * ramp) * vel_from;
    vel = vel_kin;
  }
  omega = omega_kin;
  const double w = omega_kin.norm();
  q_shape = w > 0.0 ? Quaterniond(AngleAxisd(w * t, omega_kin / w) * q0).normalized() : q0;
}

// Forces at the setup of a run: the history is read but not advanced (a run continues where the
// last one, or the restart file, left it).
void FixWirenetBody::setup(int)
{
  update_pose();
  compute_contacts(false);
  if (!floors.empty()) compute_floors(false);
}

void FixWirenetBody::initial_integrate(int)
{
  const double dt = update->dt;
  if (free_body) {
    kick(0.5 * dt);
    body->drift(dt);
  } else {
    elapsed += dt;
  }
  update_pose();
}

void FixWirenetBody::post_force(int)
{
  compute_contacts(true);
  if (!floors.empty()) compute_floors(true);
}

void FixWirenetBody::compute_contacts(bool advance)
{
  const double dt = update->dt;
  const Matrix3d R = q_shape.toRotationMatrix();
  const double bound = shape->bounding_radius();
  const bool bounded = std::isfinite(bound);
  double **x = atom->x, **v = atom->v, **f = atom->f;
  double **w = atom->omega_flag ? atom->omega : NULL, **tq = atom->torque_flag ? atom->torque : NULL;
  const double *radius = atom->radius, *rmass = atom->rmass_flag ? atom->rmass : NULL, *mass = atom->mass;
  const int *mask = atom->mask, *type = atom->type;
  const int nlocal = atom->nlocal;
  double sums[8] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
  contacts.clear();
  if (!candidates_valid || (pos - candidates_pos).norm() > 0.5 * margin) {
    candidates.clear();
    const double reach = bounded ? bound + margin : std::numeric_limits<double>::infinity();
    // an unbounded body that does not turn (a ground plane): the shape's distance bound, which
    // changes by at most the body's travel, skips the atoms far from its surface
    const bool far_test = !bounded && omega.squaredNorm() == 0.0;
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit)) continue;
      const Vector3d rel(x[i][0] - pos[0], x[i][1] - pos[1], x[i][2] - pos[2]);
      if (far_test) {
        if (!(shape->distance_bound(R.transpose() * rel) > margin + radius[i])) candidates.push_back(i);
      } else if (!(rel.norm() > reach + radius[i])) candidates.push_back(i);
    }
    candidates_pos = pos;
    candidates_valid = margin > 0.0;
  }
  WireNet::SurfacePoint sp;
  for (const int i : candidates) {
    const Vector3d xi(x[i][0], x[i][1], x[i][2]);
    const Vector3d rel = xi - pos;
    const double r = radius[i];
    if (bounded && rel.squaredNorm() > (bound + r) * (bound + r)) {
      if (advance) hist[i][3] = hist[i][0] = hist[i][1] = hist[i][2] = 0.0;
      continue;
    }
    const Vector3d local = R.transpose() * rel;
    if (shape->distance_bound(local) >= r) {
      if (advance) hist[i][3] = hist[i][0] = hist[i][1] = hist[i][2] = 0.0;
      continue;
    }
    shape->query(local, sp);
    const double delta = r - sp.dist;
    if (!(delta > 0.0)) {
      if (advance) hist[i][3] = hist[i][0] = hist[i][1] = hist[i][2] = 0.0;
      continue;
    }
    const Vector3d n = R * sp.normal;
    const Vector3d vi(v[i][0], v[i][1], v[i][2]);
    const Vector3d wi = w ? Vector3d(w[i][0], w[i][1], w[i][2]) : Vector3d::Zero();
    const double m = rmass ? rmass[i] : mass[type[i]];
    NodeContact nc;
    nc.i = i;
    Vector3d c;
    const double e = node_contact(law, delta, n, r, m, xi, vi, wi, pos, vel, omega, dt, advance, hist[i], nc.f, nc.t, c);
    for (int d = 0; d < 3; d++) {
      f[i][d] += nc.f[d];
      if (tq) tq[i][d] += nc.t[d];
    }
    const Vector3d tb = (c - pos).cross(-nc.f);
    for (int d = 0; d < 3; d++) {
      sums[d] -= nc.f[d];
      sums[3 + d] += tb[d];
    }
    sums[6] += 1.0;
    sums[7] += e;
    contacts.push_back(nc);
  }
  for (int k = 0; k < 8; k++) sums_mine[k] = sums[k];
  double *win = windows.add_step(update->ntimestep);
  if (win)
    for (int d = 0; d < 3; d++) win[d] += sums[d];
  reduced_at = -1;
  if (free_body) {
    double all[8];
    MPI_Allreduce(sums, all, 8, MPI_DOUBLE, MPI_SUM, world);
    f_body = Vector3d(all[0], all[1], all[2]);
    t_body = Vector3d(all[3], all[4], all[5]);
    ncontact = all[6];
    elastic = all[7];
  }
  contacts_pending = advance;
}

// Every point of the body below a floor is a contact (a polyhedron's corners, a smooth shape's
// deepest point); a point off the floor forgets its spring. The body's state is the same on every
// rank, and so are these forces: no reduction.
void FixWirenetBody::compute_floors(bool advance)
{
  const double dt = update->dt, m = body->mass();
  const Matrix3d R = q_shape.toRotationMatrix();
  const int np = floor_npoints();
  f_floor = t_floor = fd_floor = td_floor = Vector3d::Zero();
  floor_points = floor_elastic = 0.0;
  double slip = 0.0;
  for (size_t j = 0; j < floors.size(); j++) {
    const Floor &fl = floors[j];
    for (int k = 0; k < np; k++) {
      Vector3d local;
      if (corners.empty()) shape->support(R.transpose() * -fl.normal, local);
      else local = corners[k];
      const Vector3d arm = R * local;
      const double depth = (fl.point - pos - arm).dot(fl.normal);
      Vector3d &s = floor_springs[j * np + k];
      if (!(depth > 0.0)) {
        if (advance) {
          slip += 0.5 * fl.law.kt * s.squaredNorm();  // the point left: its spring's energy is lost
          s.setZero();
        }
        continue;
      }
      Vector3d F, Fd;
      floor_elastic += floor_contact(fl.law, depth, fl.normal, vel + omega.cross(arm), m, dt, advance, s, F, Fd, slip);
      f_floor += F;
      t_floor += arm.cross(F);
      fd_floor += Fd;
      td_floor += arm.cross(Fd);
      floor_points += 1.0;
    }
  }
  if (advance) dissipated_floor += slip;
}

// The outputs' sums over the ranks, in one reduction per step asked: a kinematic body's force,
// torque, contacts, elastic energy and work; the work on the nodes; the window mean force.
void FixWirenetBody::reduce()
{
  if (reduced_at == update->ntimestep) return;
  int count = 0;
  const double *win = windows.complete(update->ntimestep, count);
  double buf[13];
  for (int k = 0; k < 8; k++) buf[k] = sums_mine[k];
  buf[8] = work_body_mine;
  buf[9] = work_nodes_mine;
  for (int d = 0; d < 3; d++) buf[10 + d] = count ? win[d] / count : 0.0;
  MPI_Allreduce(MPI_IN_PLACE, buf, 13, MPI_DOUBLE, MPI_SUM, world);
  if (!free_body) {
    f_body = Vector3d(buf[0], buf[1], buf[2]);
    t_body = Vector3d(buf[3], buf[4], buf[5]);
    ncontact = buf[6];
    elastic = buf[7];
    work_body = buf[8];
  }
  work_nodes_all = buf[9];
  f_mean = Vector3d(buf[10], buf[11], buf[12]);
  reduced_at = update->ntimestep;
}

void FixWirenetBody::final_integrate()
{
  const double dt = update->dt;
  if (free_body) {
    kick(0.5 * dt);
    update_pose();
  }
  // F(t+dt) . v(t+dt) dt, the convention of fix wirenet/damping and wirenet/contactwork; a
  // kinematic body's work is linear in the contacts' forces, so each rank sums its own
  if (free_body) {
    work_body += dt * (f_body.dot(vel) + t_body.dot(omega));
    // the floors' work, and the damping's power at the same velocities: its share is dissipated
    work_floor += dt * (f_floor.dot(vel) + t_floor.dot(omega));
    dissipated_floor -= dt * (fd_floor.dot(vel) + td_floor.dot(omega));
  } else {
    const Vector3d f_mine(sums_mine[0], sums_mine[1], sums_mine[2]), t_mine(sums_mine[3], sums_mine[4], sums_mine[5]);
    work_body_mine += dt * (f_mine.dot(vel) + t_mine.dot(omega));
  }
  reduced_at = -1;
}

// Half kick of the free body by its contacts, the floors and its weight, less the local damping
// at the current velocity; the damping's work is its impulse times the mean velocity over the kick
void FixWirenetBody::kick(double h)
{
  const Vector3d f = f_body + f_floor + body->mass() * gravity, t = t_body + t_floor;
  impulse_floor += h * f_floor;
  if (damping == 0.0) {
    body->kick(f, t, h);
    return;
  }
  const Vector3d v_before = body->v, w_before = body->omega();
  const Vector3d fd = locally_damped(f, v_before, damping) - f;
  const Vector3d td = locally_damped(t, w_before, damping) - t;
  body->kick(f + fd, t + td, h);
  work_damping += 0.5 * h * (fd.dot(v_before + body->v) + td.dot(w_before + body->omega()));
}

// fix_modify ID vel vx vy vz [ramp T]: a kinematic body goes on from where it is, its velocity
// changing linearly from the current one to the new one over T seconds (0: at once). The clock
// restarts at the current pose, so the closed-form motion stays exact.
void FixWirenetBody::modify_velocity(int narg, char **arg)
{
  if (free_body) throw std::invalid_argument("'vel' sets the motion of a kinematic body; a free body (with 'mass') moves by its forces");
  int k = 0;
  const Vector3d v = vector3(narg, arg, k, "vel");
  double t_ramp = 0.0;
  if (k < narg) {
    if (strcmp(arg[k], "ramp") != 0) throw std::invalid_argument(std::string("unknown keyword '") + arg[k] + "' after 'vel vx vy vz' (only 'ramp T')");
    t_ramp = value(narg, arg, k, "ramp", 0.0, false);
  }
  if (k < narg) throw std::invalid_argument(std::string("unexpected '") + arg[k] + "' after 'ramp T'");
  update_pose();
  x0 = pos;
  vel_from = vel;
  q0 = q_shape;
  vel_kin = v;
  ramp = t_ramp;
  elapsed = 0.0;
  motion_modified = true;
  update_pose();
}

// fix_modify ID soften S: the nodes' contacts S times softer than defined (kn, kt / S; gamma_n
// / sqrt(S), so the same damping ratio and restitution), for a static search whose step the
// contact limits (a mesh settling on the ground: the equilibrium moves by weight / kn, nm). Each
// contact's force stays what it was: its tangential spring is stretched by S_new / S_old, and
// its node moved along the normal to the overlap that gives the same spring force. (With the
// overlap kept, a node pressed S times harder would be thrown off the ground, its friction
// spring lost: a resting net would slip.)
void FixWirenetBody::soften_contacts(int narg, char **arg)
{
  int k = 0;
  const double s = value(narg, arg, k, "soften", 1.0, false);
  if (k < narg) throw std::invalid_argument(std::string("unexpected '") + arg[k] + "' after 'soften S'");
  const double stretch = s / soften;
  update_pose();
  const Matrix3d R = q_shape.toRotationMatrix();
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  WireNet::SurfacePoint sp;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit) || hist[i][3] == 0.0) continue;
    for (int d = 0; d < 3; d++) hist[i][d] *= stretch;
    const Vector3d xi(x[i][0], x[i][1], x[i][2]);
    shape->query(R.transpose() * (xi - pos), sp);
    const double delta = radius[i] - sp.dist;
    if (!(delta > 0.0)) continue;
    const Vector3d moved = xi + (delta - delta * stretch) * (R * sp.normal);
    for (int d = 0; d < 3; d++) x[i][d] = moved[d];
  }
  soften = s;
  law = law_defined;
  law.kn /= s;
  law.kt /= s;
  law.gamma_n /= std::sqrt(s);
}

int FixWirenetBody::modify_param(int narg, char **arg)
{
  const bool vel = strcmp(arg[0], "vel") == 0, soft = strcmp(arg[0], "soften") == 0;
  if (vel || soft) {
    try {
      if (vel) modify_velocity(narg, arg);
      else soften_contacts(narg, arg);
    } catch (const std::invalid_argument &e) {
      error->all(FLERR, (std::string("fix_modify wirenet/body: ") + e.what()).c_str());
    }
    return narg;
  }
  if (strcmp(arg[0], "damping") != 0) return 0;
  try {
    int k = 0;
    const double a = damping_value(narg, arg, k);
    if (a > 0.0 && !free_body) throw std::invalid_argument("'damping' acts on a free body only: give 'mass M'");
    damping = a;
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, (std::string("fix_modify wirenet/body: ") + e.what()).c_str());
  }
  return 2;
}

void FixWirenetBody::end_of_step()
{
  if (!contacts_pending) return;
  const double dt = update->dt;
  double **v = atom->v, **w = atom->omega_flag ? atom->omega : NULL;
  for (size_t k = 0; k < contacts.size(); k++) {
    const NodeContact &c = contacts[k];
    const int i = c.i;
    double p = c.f[0] * v[i][0] + c.f[1] * v[i][1] + c.f[2] * v[i][2];
    if (w) p += c.t[0] * w[i][0] + c.t[1] * w[i][1] + c.t[2] * w[i][2];
    work_nodes_mine += dt * p;
  }
  contacts_pending = false;
  reduced_at = -1;
}

double FixWirenetBody::compute_vector(int n)
{
  // a free body's force, torque, contacts and energy are reduced already (its motion needs them)
  const bool summed = n == 13 || (n > 24 && n < 28) || (!free_body && (n < 6 || n == 12 || n == 14 || n == 24));
  if (summed) reduce();
  if (n < 3) return f_body[n];
  if (n < 6) return t_body[n - 3];
  if (n < 9) return pos[n - 6];
  if (n < 12) return vel[n - 9];
  if (n > 28) {
    if (n == 29) return work_floor;
    if (n == 30) return floor_elastic;
    if (n < 34) return impulse_floor[n - 31];
    if (n == 34) return floor_points;
    return dissipated_floor;
  }
  if (n == 12) return ncontact;
  if (n == 13) return work_nodes_all;
  if (n == 14) return work_body;
  if (n == 28) return work_damping;
  if (n < 18) return omega[n - 15];
  if (n == 18) return free_body ? body->kinetic_energy() : 0.0;
  if (n == 19) return free_body ? -body->mass() * gravity.dot(pos) : 0.0;
  if (n == 24) return elastic;
  if (n > 24) return f_mean[n - 25];
  Quaterniond r = (q_shape * q_defined.conjugate()).normalized();
  if (r.w() < 0.0) r.coeffs() *= -1.0;
  const double c[4] = { r.w(), r.x(), r.y(), r.z() };
  return c[n - 20];
}

// ---- restart ------------------------------------------------------------------------------

void FixWirenetBody::write_restart(FILE *fp)
{
  reduced_at = -1;
  reduce();
  if (comm->me != 0) return;
  std::vector<double> record(1 + NSTATE + NFLOOR_SUMS + 3 * floor_springs.size(), 0.0);
  record[0] = RECORD_VERSION;
  double *list = &record[1];
  list[0] = free_body ? 1.0 : 0.0;
  list[1] = elapsed;
  list[2] = work_body;
  list[3] = work_nodes_all;
  list[36] = work_damping;
  to_array(q_defined, &list[21]);
  for (int d = 0; d < 3; d++) list[29 + d] = x0[d];
  to_array(q0, &list[32]);
  list[37] = motion_modified ? 1.0 : 0.0;
  for (int d = 0; d < 3; d++) {
    list[38 + d] = vel_from[d];
    list[41 + d] = vel_kin[d];
  }
  list[44] = ramp;
  if (free_body) {
    for (int d = 0; d < 3; d++) {
      list[4 + d] = body->x[d];
      list[7 + d] = body->v[d];
      list[10 + d] = body->L[d];
      list[26 + d] = body->principal_moments()[d];
    }
    to_array(body->q, &list[13]);
    to_array(q_shape_in_body, &list[17]);
    list[25] = body->mass();
  }
  double *fl = list + NSTATE;
  fl[0] = work_floor;
  fl[1] = dissipated_floor;
  for (int d = 0; d < 3; d++) fl[2 + d] = impulse_floor[d];
  fl[5] = floors.size();
  fl[6] = floors.empty() ? 0 : floor_npoints();
  for (size_t k = 0; k < floor_springs.size(); k++)
    for (int d = 0; d < 3; d++) fl[NFLOOR_SUMS + 3 * k + d] = floor_springs[k][d];
  int size = record.size() * sizeof(double);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(record.data(), sizeof(double), record.size(), fp);
}

void FixWirenetBody::restart(char *buf)
{
  const double *record = (const double *)buf;
  if (record[0] != RECORD_VERSION) {
    const std::string old = record[0] == 0.0 || record[0] == 1.0 ? "1 or 2 (WireNet before the floors)" : text(record[0]);
    error->all(FLERR, ("fix wirenet/body: the restart file's record is of version " + old + ", this build reads version " +
                       std::to_string(RECORD_VERSION) + " only: write the restart file again with this build").c_str());
  }
  const double *list = record + 1;
  if ((list[0] != 0.0) != free_body)
    error->all(FLERR, free_body ? "fix wirenet/body: the restart file holds a kinematic body, this fix defines a free one"
                                : "fix wirenet/body: the restart file holds a free body, this fix defines a kinematic one");
  elapsed = list[1];
  work_body = list[2];
  work_body_mine = comm->me == 0 && !free_body ? list[2] : 0.0;
  work_nodes_mine = comm->me == 0 ? list[3] : 0.0;
  work_damping = list[36];
  reduced_at = -1;
  q_defined = from_array(&list[21]);
  x0 = Vector3d(list[29], list[30], list[31]);
  q0 = from_array(&list[32]);
  // a motion changed by fix_modify vel continues as stored; otherwise the new definition's
  // vel and ramp apply (from the stored clock and start pose)
  motion_modified = list[37] != 0.0;
  if (motion_modified && !free_body) {
    vel_from = Vector3d(list[38], list[39], list[40]);
    vel_kin = Vector3d(list[41], list[42], list[43]);
    ramp = list[44];
  }
  if (free_body) {
    const Vector3d moments(list[26], list[27], list[28]);
    if ((moments - body->principal_moments()).norm() > 1e-12 * moments.norm() ||
        std::fabs(list[25] - body->mass()) > 1e-12 * list[25])
      error->all(FLERR, "fix wirenet/body: mass or inertia differ from the restart file's");
    body->x = Vector3d(list[4], list[5], list[6]);
    body->v = Vector3d(list[7], list[8], list[9]);
    body->L = Vector3d(list[10], list[11], list[12]);
    body->q = from_array(&list[13]);
    q_shape_in_body = from_array(&list[17]);
  }
  restart_floors(list + NSTATE);
  update_pose();
}

// The floors' sums and springs; a file without floors lets this definition add them
void FixWirenetBody::restart_floors(const double *fl)
{
  work_floor = fl[0];
  dissipated_floor = fl[1];
  impulse_floor = Vector3d(fl[2], fl[3], fl[4]);
  const int nfloors = static_cast<int>(fl[5]), npoints = static_cast<int>(fl[6]);
  if (nfloors == 0) return;
  if (nfloors != (int)floors.size() || npoints != floor_npoints())
    error->all(FLERR, ("fix wirenet/body: the restart file holds " + std::to_string(nfloors) + " floor(s) of " +
                       std::to_string(npoints) + " contact point(s) each, this fix defines " + std::to_string(floors.size()) +
                       (floors.empty() ? "" : " of " + std::to_string(floor_npoints())) +
                       ": define the same floors, in the same order").c_str());
  for (size_t k = 0; k < floor_springs.size(); k++)
    floor_springs[k] = Vector3d(fl[NFLOOR_SUMS + 3 * k], fl[NFLOOR_SUMS + 3 * k + 1], fl[NFLOOR_SUMS + 3 * k + 2]);
}

// ---- per-atom tangential history ----------------------------------------------------------

void FixWirenetBody::grow_arrays(int nmax)
{
  memory->grow(hist, nmax, NHIST, "wirenet/body:hist");
  for (int i = hist_rows; i < nmax; i++)
    for (int k = 0; k < NHIST; k++) hist[i][k] = 0.0;
  if (nmax > hist_rows) hist_rows = nmax;
}

void FixWirenetBody::copy_arrays(int i, int j, int)
{
  for (int k = 0; k < NHIST; k++) hist[j][k] = hist[i][k];
}

void FixWirenetBody::set_arrays(int i)
{
  for (int k = 0; k < NHIST; k++) hist[i][k] = 0.0;
}

int FixWirenetBody::pack_exchange(int i, double *buf)
{
  for (int k = 0; k < NHIST; k++) buf[k] = hist[i][k];
  return NHIST;
}

int FixWirenetBody::unpack_exchange(int nlocal, double *buf)
{
  for (int k = 0; k < NHIST; k++) hist[nlocal][k] = buf[k];
  return NHIST;
}

int FixWirenetBody::pack_restart(int i, double *buf)
{
  buf[0] = NHIST + 1;
  for (int k = 0; k < NHIST; k++) buf[1 + k] = hist[i][k];
  return NHIST + 1;
}

void FixWirenetBody::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  for (int k = 0; k < NHIST; k++) hist[nlocal][k] = extra[nlocal][m++];
}

int FixWirenetBody::size_restart(int) { return NHIST + 1; }

int FixWirenetBody::maxsize_restart() { return NHIST + 1; }

double FixWirenetBody::memory_usage()
{
  return (double)atom->nmax * NHIST * sizeof(double) + contacts.capacity() * sizeof(NodeContact) +
         candidates.capacity() * sizeof(int) + floor_springs.capacity() * sizeof(Vector3d);
}
