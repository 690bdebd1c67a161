/* WireNet: fix wirenet/body, an analytic rigid body (sphere, spheroid, cone, plane, box,
   truncated cube, convex polyhedron) in contact with the node spheres of its group: linear
   normal spring with optional viscous damping, tangential spring with Coulomb friction (history
   per atom). The body moves kinematically (prescribed velocity, optional ramp, spin) or as a
   free 6-DOF body (WireNet::RigidBody); a free body may also touch fixed planes (floors: the
   ground, a slope) with the same law at its corners or support point. See
   doc/fix_wirenet_body.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/body,FixWirenetBody)

#else

#ifndef LMP_FIX_WIRENET_BODY_H
#define LMP_FIX_WIRENET_BODY_H

#include "fix.h"
#include "wirenet_body_shapes.h"
#include "wirenet_rigid_body.h"
#include "wirenet_window_mean.h"
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixWirenetBody : public Fix {
 public:
  // global vector: F(3) T(3) x(3) v(3) ncontact W_nodes W_body omega(3) KE PE q(4) E_elastic
  // F_mean(3) (the force's mean over the last window of `mean` steps) W_damping, then the
  // floors': W_floor E_floor J_floor(3) (impulse) npoints D_floor (friction and damping)
  static const int NVECTOR = 36;

  FixWirenetBody(class LAMMPS *, int, char **);
  ~FixWirenetBody();
  int setmask();
  void init();
  void setup(int);
  void initial_integrate(int);
  void post_force(int);
  void pre_neighbor() { candidates_valid = false; }
  void final_integrate();
  void end_of_step();
  void reset_dt() {}
  double compute_vector(int);
  int modify_param(int, char **);
  void write_restart(FILE *);
  void restart(char *);

  void grow_arrays(int);
  void copy_arrays(int, int, int);
  void set_arrays(int);
  int pack_exchange(int, double *);
  int unpack_exchange(int, double *);
  int pack_restart(int, double *);
  void unpack_restart(int, int);
  int size_restart(int);
  int maxsize_restart();
  double memory_usage();

  // contact law of one node with the body (no I/O, no allocation)
  struct Law {
    double kn, kt, mu, gamma_n;
  };
  struct NodeContact {
    int i;                    // local atom
    Eigen::Vector3d f, t;     // force and torque on the node
  };
  // a fixed plane that a free body touches (keyword floor): the half-space behind it is solid
  struct Floor {
    Eigen::Vector3d point, normal;   // unit normal, out of the ground
    Law law;                         // gamma_n per unit mass of the body
  };

 private:
  std::unique_ptr<WireNet::BodyShape> shape;
  Law law;
  // fix_modify soften S: the nodes' contact law is the defined one (law_defined) with kn and kt
  // divided by S and gamma_n by sqrt(S) (the same damping ratio); 1 as defined
  Law law_defined;
  double soften;
  bool free_body;
  std::unique_ptr<WireNet::RigidBody> body;
  Eigen::Quaterniond q_shape_in_body;  // free: shape frame in the principal frame
  Eigen::Vector3d gravity;
  // free: local damping of the body's resultant force and torque (the nodes' fix
  // wirenet/damping rule, for a body that comes to rest with the fence), and its work (<= 0)
  double damping;
  double work_damping;
  // kinematic motion: x(t) from x0, the velocity ramped from vel_from to vel_kin over `ramp`
  // seconds; orientation exp(omega t) q0. fix_modify vel restarts the clock at the current pose
  Eigen::Vector3d x0, vel_from, vel_kin, omega_kin;
  Eigen::Quaterniond q0;
  double ramp;
  double elapsed;                      // time since the fix was defined or its motion modified
  bool motion_modified;                // fix_modify vel: the restart file's motion wins
  // pose at the last update: reference point, its velocity, angular velocity, shape frame
  Eigen::Vector3d pos, vel, omega;
  Eigen::Quaterniond q_shape, q_defined;
  // results of the last force evaluation: this rank's contacts (force, torque, count, elastic
  // energy), and their sums over the ranks. A free body needs the sums at every step; a
  // kinematic one only for its outputs, so it reduces them when they are asked for.
  double sums_mine[8];
  Eigen::Vector3d f_body, t_body;
  double ncontact, elastic;
  double work_body;                    // work of the contact forces on the body (free: all ranks)
  double work_body_mine;               // kinematic: the same work of this rank's contacts
  double work_nodes_mine;              // work of the contact forces on this rank's nodes
  double work_nodes_all;
  WireNet::WindowSums windows;         // this rank's contact force on the body, per mean window
  Eigen::Vector3d f_mean;              // the last complete window's mean force, all ranks
  long long reduced_at;                // step of the reduced outputs; -1: stale
  double **hist;                       // per atom: tangential spring (3), in contact (1)
  int hist_rows;                       // rows of hist allocated (new rows start at zero)
  std::vector<NodeContact> contacts;   // this rank's contacts of the last post_force
  bool contacts_pending;               // contacts to account at end_of_step
  // Nodes that can touch the body before the list is built again: within bounding radius + node
  // radius + margin of the body's reference point when built. Built again after atoms moved
  // between ranks or were re-sorted (pre_neighbor) and when the body has moved by half the
  // margin; LIGGGHTS re-neighbours before any atom moves by half the skin (the margin), so no
  // node outside the list can reach the body in between.
  std::vector<int> candidates;
  Eigen::Vector3d candidates_pos;
  bool candidates_valid;
  double margin;                       // the neighbour skin when LIGGGHTS checks every step, else 0
  // Floors (free body only). The body's points that can touch them: a polyhedron's corners (shape
  // frame), or for a smooth shape (no corners) its support point. A tangential spring per floor
  // and point, [floor * npoints + point], zero while the point is off the floor.
  std::vector<Floor> floors;
  std::vector<Eigen::Vector3d> corners;
  std::vector<Eigen::Vector3d> floor_springs;
  // results of the last floor evaluation (identical on every rank): force and torque on the
  // body, their viscous part, contact points, elastic energy; sums since the fix was defined
  Eigen::Vector3d f_floor, t_floor, fd_floor, td_floor;
  double floor_points, floor_elastic;
  double work_floor, dissipated_floor;
  Eigen::Vector3d impulse_floor;

  void parse(int narg, char **arg);
  void modify_velocity(int narg, char **arg);
  void soften_contacts(int narg, char **arg);
  void update_pose();
  void compute_contacts(bool advance);
  int floor_npoints() const { return corners.empty() ? 1 : (int)corners.size(); }
  void define_floors();
  void compute_floors(bool advance);
  void restart_floors(const double *record);
  void reduce();
  void kick(double h);
};

}

#endif
#endif
