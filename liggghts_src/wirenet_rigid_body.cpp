/* WireNet: rigid-body integrator. The splitting is explained in wirenet_rigid_body.h. */

#include "wirenet_rigid_body.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace WireNet {

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

RigidBody::RigidBody(double mass, const Matrix3d &inertia) :
  x(Vector3d::Zero()), v(Vector3d::Zero()), L(Vector3d::Zero()), q(Quaterniond::Identity()),
  m_(mass), ref_(1)
{
  if (!(mass > 0.0) || !std::isfinite(mass))
    throw std::invalid_argument("mass must be > 0 (got " + std::to_string(mass) + ")");
  if (!inertia.allFinite() || (inertia - inertia.transpose()).norm() > 1e-12 * inertia.norm())
    throw std::invalid_argument("inertia tensor must be finite and symmetric");
  Eigen::SelfAdjointEigenSolver<Matrix3d> eig(inertia);
  moments_ = eig.eigenvalues();  // ascending
  if (!(moments_[0] > 0.0))
    throw std::invalid_argument("inertia tensor must be positive definite (smallest principal moment " +
                                std::to_string(moments_[0]) + ")");
  // A real mass distribution has I1 + I2 >= I3 for its principal moments.
  if (moments_[0] + moments_[1] < moments_[2] * (1.0 - 1e-9))
    throw std::invalid_argument("inertia tensor violates I1 + I2 >= I3 (principal moments " +
                                std::to_string(moments_[0]) + ", " + std::to_string(moments_[1]) + ", " +
                                std::to_string(moments_[2]) + ")");
  Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
  q = Quaterniond(axes);
  q.normalize();
}

void RigidBody::set_omega(const Vector3d &omega)
{
  const Vector3d wb = q.conjugate() * omega;
  L = q * Vector3d(moments_.cwiseProduct(wb));
}

Vector3d RigidBody::omega() const
{
  const Vector3d lb = q.conjugate() * L;
  return q * Vector3d(lb.cwiseQuotient(moments_));
}

double RigidBody::rotational_energy() const
{
  const Vector3d lb = q.conjugate() * L;
  return 0.5 * lb.cwiseProduct(lb).cwiseQuotient(moments_).sum();
}

void RigidBody::kick(const Vector3d &force, const Vector3d &torque, double h)
{
  v += (h / m_) * force;
  L += h * torque;
}

// Strang splitting of the two correction terms; the |L|^2 term commutes with both and goes last.
void RigidBody::drift(double h)
{
  x += h * v;
  const int a = (ref_ + 1) % 3, b = (ref_ + 2) % 3;
  rotate_about_body_axis(a, 0.5 * h);
  rotate_about_body_axis(b, h);
  rotate_about_body_axis(a, 0.5 * h);
  rotate_in_space(h);
}

// Exact flow of |L|^2/(2 I_r): rotation about the fixed L at the rate |L|/I_r.
void RigidBody::rotate_in_space(double h)
{
  const double l = L.norm();
  if (l == 0.0) return;
  q = Quaterniond(AngleAxisd(h * l / moments_[ref_], L / l)) * q;
  q.normalize();
}

// Exact flow of c L_k^2/2, c = 1/I_k - 1/I_r: rotation about body axis k at the rate c L_k.
void RigidBody::rotate_about_body_axis(int k, double h)
{
  const double c = 1.0 / moments_[k] - 1.0 / moments_[ref_];
  if (c == 0.0) return;
  const Vector3d lb = q.conjugate() * L;
  q = q * Quaterniond(AngleAxisd(h * c * lb[k], Vector3d::Unit(k)));
  q.normalize();
}

}
