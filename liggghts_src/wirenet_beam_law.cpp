/* WireNet: corotational parallel-bond beam. Derivation in doc/bond_wirenet.md ("beam law").

   The chord e = (xj - xi)/L carries the rigid motion of the bond. Each end's material tangent
   t = R q d0 is compared with the chord: theta = rotation vector taking e to t (bending of that
   end relative to the chord). A rigid rotation of the pair rotates e and t alike, so theta's
   magnitude and every force and moment are unchanged: the law is objective for any rotation.
   The twist phi is the angle about e between the two ends' reference normals projected on the
   plane normal to e (objective as well; exact in pure twist).
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

using Eigen::Vector3d;

namespace {

void require(bool ok, const std::string &what, double got)
{
  if (ok) return;
  std::ostringstream s;
  s << what << " (got " << got << ")";
  throw std::invalid_argument(s.str());
}

// Bonds bend little: below these sizes the series are exact to round-off and skip the
// transcendental calls that would otherwise dominate the bond's cost.
const double SMALL_SIN2 = 0.05 * 0.05;
const double SMALL_TAN = 0.05;

// Rotation vector of the smallest rotation taking unit vector a onto unit vector b.
__attribute__((always_inline)) inline Vector3d rotation_between(const Vector3d &a, const Vector3d &b)
{
  const Vector3d c = a.cross(b);
  const double s2 = c.squaredNorm(), co = a.dot(b);
  if (co > 0.0 && s2 < SMALL_SIN2)  // angle / sin(angle) = asin(s) / s
    return c * (1.0 + s2 * (1.0 / 6 + s2 * (3.0 / 40 + s2 * (5.0 / 112 + s2 * (35.0 / 1152)))));
  const double s = std::sqrt(s2);
  if (s < 1e-300) return Vector3d::Zero();
  return c * (std::atan2(s, co) / s);
}

// atan2(y, x), by its series when the angle is small
__attribute__((always_inline)) inline double angle(double y, double x)
{
  if (x > 0.0 && std::fabs(y) < SMALL_TAN * x) {
    const double r = y / x, r2 = r * r;
    return r * (1.0 - r2 * (1.0 / 3 - r2 * (1.0 / 5 - r2 * (1.0 / 7 - r2 * (1.0 / 9)))));
  }
  return std::atan2(y, x);
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
  EA_ = young_ * area_;
  fEI_ = p.bending * young_ * inertia_;
  ftGJ_ = twist_fraction_ * shear_modulus_ * polar_;
  GA_ = shear_modulus_ * area_;
}

BeamLaw::Stiffness BeamLaw::stiffness(double l0) const
{
  const double inv = 1.0 / l0;
  Stiffness k;
  k.axial = EA_ * inv;
  k.bending = fEI_ * inv;
  k.shear_coupling = p_.shear == ShearModel::EULER_BERNOULLI ? 3.0 * k.bending : 0.25 * GA_ * l0;
  k.twist = ftGJ_ * inv;
  return k;
}

void BeamLaw::init_bond(double *h, const Vector3d &xi, const Vector3d &xj, const Rotation &ri,
                        const Rotation &rj) const
{
  const Vector3d d = xj - xi;
  const double l0 = d.norm();
  const Vector3d e = d / l0;
  // any unit normal of the chord; fixed from the chord so it is the same on every rank
  Vector3d n = e.cross(Vector3d::UnitZ());
  if (n.norm() < 0.1) n = e.cross(Vector3d::UnitX());
  n.normalize();
  h[B_L0] = l0;
  store3(h + B_DI, ri.transpose() * e);
  store3(h + B_DJ, rj.transpose() * e);
  store3(h + B_PI, ri.transpose() * n);
  store3(h + B_PJ, rj.transpose() * n);
}

void BeamLaw::evaluate(const double *h, const Vector3d &xi, const Vector3d &xj, const Rotation &ri,
                       const Rotation &rj, BeamResult &out, bool report) const
{
  const double l0 = h[B_L0];
  const Vector3d d = xj - xi;
  const double L = d.norm();
  const double inv_L = 1.0 / L;
  const Vector3d e = d * inv_L;
  const Stiffness k = stiffness(l0);

  // end rotations relative to the chord
  const Vector3d ti = ri * load3(h + B_DI), tj = rj * load3(h + B_DJ);
  const Vector3d th_i = rotation_between(e, ti), th_j = rotation_between(e, tj);
  // twist: the ends' reference normals projected on the chord's normal plane
  Vector3d ni = ri * load3(h + B_PI), nj = rj * load3(h + B_PJ);
  ni -= e.dot(ni) * e;
  nj -= e.dot(nj) * e;
  const double phi = angle(e.dot(ni.cross(nj)), ni.dot(nj));

  const Vector3d sum = th_i + th_j, diff = th_i - th_j;
  const Vector3d bend_i = k.bending * diff + k.shear_coupling * sum;
  const Vector3d bend_j = -k.bending * diff + k.shear_coupling * sum;
  const Vector3d shear_j = (2.0 * k.shear_coupling * inv_L) * sum.cross(e);
  const double axial = k.axial * (L - l0);

  out.force_i = axial * e - shear_j;
  out.torque_i = -bend_i + (k.twist * phi) * e;
  out.torque_j = -bend_j - (k.twist * phi) * e;
  out.axial = axial;
  if (!report) return;
  out.shear = shear_j.norm();
  out.moment = std::max(bend_i.norm(), bend_j.norm());
  out.energy = 0.5 * (axial * (L - l0) + k.bending * diff.squaredNorm() +
                      k.shear_coupling * sum.squaredNorm() + k.twist * phi * phi);
}

}  // namespace WireNet
