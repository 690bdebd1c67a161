/* WireNet: corotational parallel-bond beam. Derivation in doc/bond_wirenet.md ("beam law").

   The chord e = (xj - xi)/L carries the rigid motion of the bond. Each end's material tangent
   t = R q d0 is compared with the chord: theta = rotation vector taking e to t (bending of that
   end relative to the chord). A rigid rotation of the pair rotates e and t alike, so theta's
   magnitude and every force and moment are unchanged: the law is objective for any rotation.
   With Kb = f E I / L0 and the shear coupling Cs (= Ks L0^2 / 4):
     moments  M_i = -(Kb (th_i - th_j) + Cs (th_i + th_j)) + Kt phi e,
              M_j = -(Kb (th_j - th_i) + Cs (th_i + th_j)) - Kt phi e,
     shear    F_j = 2 Cs (th_i + th_j) x e / L   (moment balance of the bond, F_i = -F_j).
   Kb = EI/L0 with Ks = 12 EI/L0^3 (Cs = 3 EI/L0) is the exact Euler-Bernoulli element;
   Ks = GA/L0 is the classical parallel bond. */

#include "wirenet_beam_law.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace WireNet {

using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

void require(bool ok, const std::string &what, double got)
{
  if (ok) return;
  std::ostringstream s;
  s << what << " (got " << got << ")";
  throw std::invalid_argument(s.str());
}

// Rotation vector of the smallest rotation taking unit vector a onto unit vector b.
inline Vector3d rotation_between(const Vector3d &a, const Vector3d &b)
{
  const Vector3d c = a.cross(b);
  const double s = c.norm(), co = a.dot(b);
  if (s < 1e-300) return Vector3d::Zero();
  return c * (std::atan2(s, co) / s);
}

// v rotated by rotation vector th (Rodrigues).
inline Vector3d rotate(const Vector3d &v, const Vector3d &th)
{
  const double a = th.norm();
  if (a < 1e-300) return v;
  const Vector3d k = th / a;
  const double c = std::cos(a), s = std::sin(a);
  return v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c));
}

inline Vector3d load3(const double *h) { return Vector3d(h[0], h[1], h[2]); }
inline void store3(double *h, const Vector3d &v) { h[0] = v[0]; h[1] = v[1]; h[2] = v[2]; }

}  // namespace

BeamLaw::BeamLaw(const BeamLawParams &p) : p_(p)
{
  require(p.diameter > 0.0, "beam diameter must be > 0", p.diameter);
  require(p.young > 0.0, "beam E must be > 0", p.young);
  require(p.nu > -1.0 && p.nu < 0.5, "beam nu must be in (-1,0.5)", p.nu);
  require(p.bending >= 0.0, "beam bending fraction must be >= 0", p.bending);
  twist_fraction_ = p.twist < 0.0 ? p.bending : p.twist;
  require(twist_fraction_ >= 0.0, "beam twist fraction must be >= 0", p.twist);
  const double r = 0.5 * p.diameter;
  area_ = M_PI * r * r;
  inertia_ = M_PI * r * r * r * r / 4.0;
  polar_ = 2.0 * inertia_;
  young_ = p.young;
  shear_modulus_ = p.young / (2.0 * (1.0 + p.nu));
}

BeamLaw::Stiffness BeamLaw::stiffness(double l0) const
{
  Stiffness k;
  k.axial = young_ * area_ / l0;
  k.bending = p_.bending * young_ * inertia_ / l0;
  k.shear_coupling = p_.shear == ShearModel::EULER_BERNOULLI ? 3.0 * k.bending
                                                             : 0.25 * shear_modulus_ * area_ * l0;
  k.twist = twist_fraction_ * shear_modulus_ * polar_ / l0;
  return k;
}

void BeamLaw::init_bond(double *h, const Vector3d &xi, const Vector3d &xj, const Quaterniond &qi,
                        const Quaterniond &qj) const
{
  const Vector3d d = xj - xi;
  const double l0 = d.norm();
  const Vector3d e = d / l0;
  // any unit normal of the chord; fixed from the chord so it is the same on every rank
  Vector3d n = e.cross(Vector3d::UnitZ());
  if (n.norm() < 0.1) n = e.cross(Vector3d::UnitX());
  n.normalize();
  h[B_L0] = l0;
  store3(h + B_DI, qi.conjugate() * e);
  store3(h + B_DJ, qj.conjugate() * e);
  store3(h + B_PI, qi.conjugate() * n);
  store3(h + B_PJ, qj.conjugate() * n);
}

void BeamLaw::evaluate(const double *h, const Vector3d &xi, const Vector3d &xj, const Quaterniond &qi,
                       const Quaterniond &qj, BeamResult &out) const
{
  const double l0 = h[B_L0];
  const Vector3d d = xj - xi;
  const double L = d.norm();
  const Vector3d e = d / L;
  const Stiffness k = stiffness(l0);

  // end rotations relative to the chord
  const Vector3d ti = qi * load3(h + B_DI), tj = qj * load3(h + B_DJ);
  const Vector3d th_i = rotation_between(e, ti), th_j = rotation_between(e, tj);
  // twist: carry each end's reference normal back onto the chord's normal plane and compare
  const Vector3d ni = rotate(qi * load3(h + B_PI), -th_i);
  const Vector3d nj = rotate(qj * load3(h + B_PJ), -th_j);
  const double phi = std::atan2(e.dot(ni.cross(nj)), ni.dot(nj));

  const Vector3d sum = th_i + th_j, diff = th_i - th_j;
  const Vector3d bend_i = k.bending * diff + k.shear_coupling * sum;
  const Vector3d bend_j = -k.bending * diff + k.shear_coupling * sum;
  const Vector3d shear_j = (2.0 * k.shear_coupling / L) * sum.cross(e);
  const double axial = k.axial * (L - l0);

  out.force_i = axial * e - shear_j;
  out.torque_i = -bend_i + (k.twist * phi) * e;
  out.torque_j = -bend_j - (k.twist * phi) * e;
  out.axial = axial;
  out.shear = shear_j.norm();
  out.moment = std::max(bend_i.norm(), bend_j.norm());
  out.energy = 0.5 * (axial * (L - l0) + k.bending * diff.squaredNorm() +
                      k.shear_coupling * sum.squaredNorm() + k.twist * phi * phi);
}

}  // namespace WireNet
