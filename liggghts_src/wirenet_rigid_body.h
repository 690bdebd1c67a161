/* WireNet: rigid-body state and its time integrator (no LIGGGHTS dependence).

   Velocity Verlet for the translation; for the rotation the kick-drift-kick splitting of the
   Hamiltonian H = |L|^2/(2 I_r) + sum_k (1/I_k - 1/I_r) L_k^2/2 (body components L_k, I_r the middle
   principal moment): every part has an exact flow, so the scheme is symplectic and time-reversible,
   keeps the space-frame angular momentum to round-off between torque kicks, and is exact for
   spherical and axisymmetric bodies (one correction term vanishes and the other commutes with
   |L|^2). See doc/fix_wirenet_rigidmesh.md. */

#ifndef WIRENET_RIGID_BODY_H
#define WIRENET_RIGID_BODY_H

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace WireNet {

class RigidBody {
 public:
  // inertia: about the centre of mass, in the space axes of the current orientation
  RigidBody(double mass, const Eigen::Matrix3d &inertia);

  double mass() const { return m_; }
  const Eigen::Vector3d &principal_moments() const { return moments_; }

  // state; q maps the principal body frame to space
  Eigen::Vector3d x, v, L;
  Eigen::Quaterniond q;

  void set_omega(const Eigen::Vector3d &omega);
  Eigen::Vector3d omega() const;
  double kinetic_energy() const { return translational_energy() + rotational_energy(); }
  double translational_energy() const { return 0.5 * m_ * v.squaredNorm(); }
  double rotational_energy() const;

  // v += h F/m, L += h T (T about the centre of mass)
  void kick(const Eigen::Vector3d &force, const Eigen::Vector3d &torque, double h);
  // force-free motion over h: x += h v, free-rotor rotation
  void drift(double h);

 private:
  double m_;
  Eigen::Vector3d moments_;  // principal moments
  int ref_;                  // index of the middle moment
  void rotate_in_space(double h);
  void rotate_about_body_axis(int k, double h);
};

}

#endif
