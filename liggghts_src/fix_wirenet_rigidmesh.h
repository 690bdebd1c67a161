/* WireNet: fix wirenet/rigidmesh, a rigid block bounded by a fix mesh/surface/stress mesh, moving
   with six degrees of freedom under the particle contact forces and gravity.
   See doc/fix_wirenet_rigidmesh.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/rigidmesh,FixWirenetRigidMesh)

#else

#ifndef LMP_FIX_WIRENET_RIGIDMESH_H
#define LMP_FIX_WIRENET_RIGIDMESH_H

#include "fix.h"
#include "wirenet_rigid_body.h"
#include <memory>
#include <string>

namespace LAMMPS_NS {

class FixWirenetRigidMesh : public Fix {
 public:
  // global vector: x(3) v(3) omega(3) F(3) |F| T(3) KE KE_rot PE_gravity L(3) q(4) W_contact
  static const int NVECTOR = 27;

  FixWirenetRigidMesh(class LAMMPS *, int, char **);
  ~FixWirenetRigidMesh();
  int setmask();
  void post_create();
  void pre_delete(bool);
  void init();
  void setup_pre_force(int);
  void initial_integrate(int);
  void pre_force(int) {}
  void final_integrate();
  void reset_dt() {}
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);

 private:
  std::string mesh_id;
  class FixMeshSurface *fix_mesh;
  class MeshModuleStress *stress;
  std::unique_ptr<WireNet::RigidBody> body;
  Eigen::Vector3d gravity;
  Eigen::Quaterniond q_defined;  // principal orientation when the fix was defined
  // contact force and torque (about the centre of mass) at the last force evaluation, all ranks
  Eigen::Vector3d f_contact, t_contact;
  bool setup_forces_pending;     // f_contact / t_contact still hold per-rank setup sums
  // body pose when the mesh stored its reference node positions (each run's setup)
  Eigen::Vector3d x_anchor, x_last;
  Eigen::Quaterniond q_anchor, q_last;
  bool registered;
  double contact_work;           // work of the contact force and torque on the block (all ranks)

  void parse(int narg, char **arg, Eigen::Vector3d &com, bool &have_com, Eigen::Vector3d &vel,
             Eigen::Vector3d &omega);
  Eigen::Vector3d mesh_centroid();
  void find_mesh();
  void gather_setup_forces();
  void take_contact_forces();
  Eigen::Vector3d total_force() const { return f_contact + body->mass() * gravity; }
  void place_mesh();
  void set_wall_velocity();
  void set_reference_point();
};

}

#endif
#endif
