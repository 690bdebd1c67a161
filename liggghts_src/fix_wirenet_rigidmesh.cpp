/* WireNet: fix wirenet/rigidmesh. See doc/fix_wirenet_rigidmesh.md.

   Each step: half kick with the force and torque of the last evaluation, drift (translation and
   free-rotor rotation, WireNet::RigidBody), then the mesh nodes are placed from the reference
   positions the mesh stored at the run's setup (rotation about the anchor pose, then translation)
   and the node velocities set to v + omega x r, so that the contact models see the right wall
   velocity; after the forces, the second half kick. Every rank holds the whole body state and
   moves its own and ghost triangles identically; only the contact sums are reduced. */

#include "fix_wirenet_rigidmesh.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_mesh_surface.h"
#include "mesh_module_stress.h"
#include "modify.h"
#include "tri_mesh.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

const int NRESTART = 22;

double number(const char *s, const std::string &what)
{
  char *end = NULL;
  errno = 0;
  const double v = strtod(s, &end);
  if (errno || end == s || *end != '\0' || !std::isfinite(v))
    throw std::invalid_argument(what + " must be a number (got '" + s + "')");
  return v;
}

Vector3d vector3(int narg, char **arg, int &k, const std::string &key)
{
  if (k + 3 >= narg) throw std::invalid_argument("'" + key + "' needs 3 values");
  Vector3d r;
  for (int d = 0; d < 3; d++) r[d] = number(arg[k + 1 + d], key + " value");
  k += 4;
  return r;
}

std::string fmt(double v)
{
  char buf[32];
  snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string fmt(const Vector3d &v) { return fmt(v[0]) + " " + fmt(v[1]) + " " + fmt(v[2]); }

void to_array(const Quaterniond &q, double *a) { a[0] = q.w(); a[1] = q.x(); a[2] = q.y(); a[3] = q.z(); }

}

FixWirenetRigidMesh::FixWirenetRigidMesh(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), fix_mesh(NULL), stress(NULL), gravity(Vector3d::Zero()),
  f_contact(Vector3d::Zero()), t_contact(Vector3d::Zero()), setup_forces_pending(false),
  x_anchor(Vector3d::Zero()), x_last(Vector3d::Zero()), registered(false), contact_work(0.0)
{
  Vector3d com, vel, omega;
  bool have_com = false;
  try {
    parse(narg, arg, com, have_com, vel, omega);
  } catch (const std::invalid_argument &e) {
    error->all(FLERR, (std::string("fix wirenet/rigidmesh: ") + e.what()).c_str());
  }
  find_mesh();
  if (!have_com) com = mesh_centroid();
  body->x = com;
  body->v = vel;
  body->set_omega(omega);
  q_defined = body->q;
  q_anchor = q_last = body->q;
  x_anchor = x_last = com;

  vector_flag = 1;
  size_vector = NVECTOR;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
}

FixWirenetRigidMesh::~FixWirenetRigidMesh() {}

void FixWirenetRigidMesh::parse(int narg, char **arg, Vector3d &com, bool &have_com, Vector3d &vel,
                                Vector3d &omega)
{
  double mass = -1.0;
  bool have_inertia = false;
  Matrix3d inertia = Matrix3d::Zero();
  vel.setZero();
  omega.setZero();
  int k = 3;
  while (k < narg) {
    const std::string key = arg[k];
    if (key == "mesh") {
      if (k + 1 >= narg) throw std::invalid_argument("'mesh' needs the ID of a fix mesh/surface/stress");
      mesh_id = arg[k + 1];
      k += 2;
    } else if (key == "mass") {
      if (k + 1 >= narg) throw std::invalid_argument("'mass' needs a value");
      mass = number(arg[k + 1], "mass");
      if (!(mass > 0.0)) throw std::invalid_argument(std::string("mass must be > 0 (got ") + arg[k + 1] + ")");
      k += 2;
    } else if (key == "inertia") {
      if (k + 6 >= narg) throw std::invalid_argument("'inertia' needs 6 values: Ixx Iyy Izz Ixy Ixz Iyz");
      double c[6];
      for (int d = 0; d < 6; d++) c[d] = number(arg[k + 1 + d], "inertia value");
      inertia << c[0], c[3], c[4],
                 c[3], c[1], c[5],
                 c[4], c[5], c[2];
      have_inertia = true;
      k += 7;
    } else if (key == "com") {
      com = vector3(narg, arg, k, key);
      have_com = true;
    } else if (key == "vel") {
      vel = vector3(narg, arg, k, key);
    } else if (key == "omega") {
      omega = vector3(narg, arg, k, key);
    } else if (key == "gravity") {
      gravity = vector3(narg, arg, k, key);
    } else {
      throw std::invalid_argument("unknown keyword '" + key + "'");
    }
  }
  if (mesh_id.empty()) throw std::invalid_argument("missing 'mesh ID'");
  if (mass < 0.0) throw std::invalid_argument("missing 'mass M'");
  if (!have_inertia) throw std::invalid_argument("missing 'inertia Ixx Iyy Izz Ixy Ixz Iyz'");
  body.reset(new WireNet::RigidBody(mass, inertia));
  // Finite inputs can still overflow in what the integrator computes first: momentum, weight,
  // angular momentum and kinetic energy must be finite (e.g. 'vel 1e200 0 0').
  auto finite = [&](double v, const std::string &what, const std::string &keys) {
    if (!std::isfinite(v))
      throw std::invalid_argument(keys + " give a non-finite " + what + " (mass " + fmt(mass) + ")");
  };
  finite(0.5 * mass * vel.squaredNorm(), "kinetic energy", "'vel " + fmt(vel) + "'");
  finite(mass * gravity.norm(), "weight", "'gravity " + fmt(gravity) + "'");
  finite(0.5 * omega.dot(inertia * omega), "rotational kinetic energy",
         "'omega " + fmt(omega) + "' and the inertia");
}

void FixWirenetRigidMesh::find_mesh()
{
  const std::string pre = "fix wirenet/rigidmesh: mesh '" + mesh_id + "' ";
  fix_mesh = dynamic_cast<FixMeshSurface *>(modify->find_fix_id(mesh_id.c_str()));
  if (!fix_mesh) error->all(FLERR, (pre + "is not a fix mesh/surface (define the mesh first)").c_str());
  stress = dynamic_cast<MeshModuleStress *>(fix_mesh->get_module("stress"));
  if (!stress || !stress->trackStress())
    error->all(FLERR, (pre + "needs the stress module: use fix mesh/surface/stress with stress on").c_str());
  if (fix_mesh->surfaceVel())
    error->all(FLERR, (pre + "has surface_vel / surface_ang_vel; a rigid block cannot have them").c_str());
}

// Volume centroid of the closed surface (divergence theorem, tetrahedra from the origin). Before
// the mesh is first distributed every rank holds all triangles, later each its own: the ratio
// of the sums is right in both cases.
Vector3d FixWirenetRigidMesh::mesh_centroid()
{
  TriMesh *mesh = fix_mesh->triMesh();
  double sums[4] = { 0.0, 0.0, 0.0, 0.0 }, all[4];
  for (int i = 0; i < mesh->sizeLocal(); i++) {
    Vector3d p[3];
    for (int j = 0; j < 3; j++) mesh->node(i, j, p[j].data());
    const double vol = p[0].dot(p[1].cross(p[2])) / 6.0;
    const Vector3d c = vol * (p[0] + p[1] + p[2]) / 4.0;
    sums[0] += vol; sums[1] += c[0]; sums[2] += c[1]; sums[3] += c[2];
  }
  MPI_Allreduce(sums, all, 4, MPI_DOUBLE, MPI_SUM, world);
  if (!(all[0] > 0.0))
    error->all(FLERR, ("fix wirenet/rigidmesh: mesh '" + mesh_id + "' encloses no volume with outward "
                       "normals; give the centre of mass with 'com x y z'").c_str());
  return Vector3d(all[1], all[2], all[3]) / all[0];
}

int FixWirenetRigidMesh::setmask()
{
  return INITIAL_INTEGRATE | PRE_FORCE | FINAL_INTEGRATE;
}

void FixWirenetRigidMesh::post_create()
{
  AbstractMesh *mesh = fix_mesh->mesh();
  mesh->registerMove(false, true, true);
  registered = true;
  if (!mesh->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v"))
    mesh->prop().addElementProperty<MultiVectorContainer<double, 3, 3> >("v", "comm_exchange_borders",
                                                                        "frame_invariant", "restart_no");
  mesh->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v")->setAll(0.0);
}

void FixWirenetRigidMesh::pre_delete(bool)
{
  if (!registered) return;
  // the mesh fix may be gone already
  FixMeshSurface *fm = dynamic_cast<FixMeshSurface *>(modify->find_fix_id(mesh_id.c_str()));
  if (fm == fix_mesh && fm) {
    fm->mesh()->unregisterMove(false, true, true);
    MultiVectorContainer<double, 3, 3> *v = fm->mesh()->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v");
    if (v) v->setAll(0.0);
  }
  registered = false;
}

void FixWirenetRigidMesh::init()
{
  find_mesh();
  const std::string pre = "fix wirenet/rigidmesh: ";
  if (fix_mesh->mesh()->nMove() > 1)
    error->all(FLERR, (pre + "mesh '" + mesh_id + "' is also moved by another fix; one mover per mesh").c_str());
  // The mesh fix must finish its final_integrate (the force reduction) before this fix's.
  if (modify->find_fix(mesh_id.c_str()) > modify->find_fix(id))
    error->all(FLERR, (pre + "define the mesh '" + mesh_id + "' before this fix").c_str());
  if (domain->xperiodic || domain->yperiodic || domain->zperiodic)
    error->all(FLERR, (pre + "periodic boundaries are not supported").c_str());
  if (strstr(update->integrate_style, "respa")) error->all(FLERR, (pre + "run_style respa is not supported").c_str());
}

// The mesh has just stored its reference node positions (FixMesh::setup_pre_force, an earlier
// fix): they belong to the current pose. The setup force pass then adds this rank's contacts to
// the stress module's totals, which nobody reduces at setup: start them from zero here.
void FixWirenetRigidMesh::setup_pre_force(int)
{
  x_anchor = x_last = body->x;
  q_anchor = q_last = body->q;
  set_reference_point();
  set_wall_velocity();
  for (int d = 0; d < 3; d++) stress->f_total_ptr()[d] = stress->torque_total_ptr()[d] = 0.0;
  setup_forces_pending = true;
}

void FixWirenetRigidMesh::gather_setup_forces()
{
  if (!setup_forces_pending) return;
  MPI_Allreduce(stress->f_total_ptr(), f_contact.data(), 3, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(stress->torque_total_ptr(), t_contact.data(), 3, MPI_DOUBLE, MPI_SUM, world);
  setup_forces_pending = false;
}

// After the mesh fix's final_integrate the totals are summed over ranks.
void FixWirenetRigidMesh::take_contact_forces()
{
  for (int d = 0; d < 3; d++) {
    f_contact[d] = stress->f_total(d);
    t_contact[d] = stress->torque_total(d);
  }
  setup_forces_pending = false;
}

void FixWirenetRigidMesh::initial_integrate(int)
{
  gather_setup_forces();
  const double dt = update->dt;
  body->kick(total_force(), t_contact, 0.5 * dt);
  body->drift(dt);
  place_mesh();
  set_reference_point();
  set_wall_velocity();
}

void FixWirenetRigidMesh::final_integrate()
{
  take_contact_forces();
  body->kick(total_force(), t_contact, 0.5 * update->dt);
  // F(t+dt) . v(t+dt) dt, the convention of fix wirenet/damping: summed over all forces it is the
  // change of the half-step kinetic energy
  contact_work += update->dt * (f_contact.dot(body->v) + t_contact.dot(body->omega()));
}

// nodes = x + R (orig - x_anchor), R = q q_anchor^-1: the mesh rotates its reference nodes
// about the anchor, then translates them by x - x_anchor.
void FixWirenetRigidMesh::place_mesh()
{
  AbstractMesh *mesh = fix_mesh->mesh();
  double total[4], incr[4], origin[3], shift[3], dshift[3];
  to_array((body->q * q_anchor.conjugate()).normalized(), total);
  to_array((body->q * q_last.conjugate()).normalized(), incr);
  for (int d = 0; d < 3; d++) {
    origin[d] = x_anchor[d];
    shift[d] = body->x[d] - x_anchor[d];
    dshift[d] = body->x[d] - x_last[d];
  }
  mesh->rotate(total, incr, origin);
  mesh->move(shift, dshift);
  x_last = body->x;
  q_last = body->q;
}

void FixWirenetRigidMesh::set_wall_velocity()
{
  TriMesh *mesh = fix_mesh->triMesh();
  double ***v = mesh->prop().getElementProperty<MultiVectorContainer<double, 3, 3> >("v")->begin();
  const Vector3d w = body->omega();
  const int n = mesh->size();
  for (int i = 0; i < n; i++)
    for (int j = 0; j < 3; j++) {
      Vector3d p;
      mesh->node(i, j, p.data());
      const Vector3d vn = body->v + w.cross(p - body->x);
      for (int d = 0; d < 3; d++) v[i][j][d] = vn[d];
    }
}

// The stress module reports the torque about this point.
void FixWirenetRigidMesh::set_reference_point()
{
  double p[3] = { body->x[0], body->x[1], body->x[2] };
  stress->set_p_ref(p);
}

double FixWirenetRigidMesh::compute_vector(int n)
{
  gather_setup_forces();
  if (n < 3) return body->x[n];
  if (n < 6) return body->v[n - 3];
  if (n < 9) return body->omega()[n - 6];
  if (n < 12) return f_contact[n - 9];
  if (n == 12) return f_contact.norm();
  if (n < 16) return t_contact[n - 13];
  if (n == 16) return body->kinetic_energy();
  if (n == 17) return body->rotational_energy();
  if (n == 18) return -body->mass() * gravity.dot(body->x);
  if (n < 22) return body->L[n - 19];
  if (n == 26) return contact_work;
  Quaterniond r = (body->q * q_defined.conjugate()).normalized();
  if (r.w() < 0.0) r.coeffs() *= -1.0;
  const double c[4] = { r.w(), r.x(), r.y(), r.z() };
  return c[n - 22];
}

void FixWirenetRigidMesh::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  double list[NRESTART];
  int k = 0;
  for (int d = 0; d < 3; d++) list[k++] = body->x[d];
  for (int d = 0; d < 3; d++) list[k++] = body->v[d];
  for (int d = 0; d < 3; d++) list[k++] = body->L[d];
  to_array(body->q, &list[k]); k += 4;
  to_array(q_defined, &list[k]); k += 4;
  for (int d = 0; d < 3; d++) list[k++] = body->principal_moments()[d];
  list[k++] = body->mass();
  list[k++] = contact_work;
  int size = NRESTART * sizeof(double);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(list, sizeof(double), NRESTART, fp);
}

// The pose and momenta come from the restart file; mass and inertia must be the same as before.
void FixWirenetRigidMesh::restart(char *buf)
{
  const double *list = (const double *)buf;
  const Vector3d moments(list[17], list[18], list[19]);
  if ((moments - body->principal_moments()).norm() > 1e-12 * moments.norm() ||
      fabs(list[20] - body->mass()) > 1e-12 * list[20])
    error->all(FLERR, "fix wirenet/rigidmesh: mass or inertia differ from the restart file's");
  body->x = Vector3d(list[0], list[1], list[2]);
  body->v = Vector3d(list[3], list[4], list[5]);
  body->L = Vector3d(list[6], list[7], list[8]);
  body->q = Quaterniond(list[9], list[10], list[11], list[12]).normalized();
  q_defined = Quaterniond(list[13], list[14], list[15], list[16]).normalized();
  contact_work = list[21];
  x_anchor = x_last = body->x;
  q_anchor = q_last = body->q;
}
