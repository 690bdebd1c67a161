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

// atan2(y, x), by its series when the angle is small
__attribute__((always_inline)) inline double angle(double y, double x)
{
  if (x > 0.0 && std::fabs(y) < SMALL_TAN * x) {
    const double r = y / x, r2 = r * r;
    return r * (1.0 - r2 * (1.0 / 3 - r2 * (1.0 / 5 - r2 * (1.0 / 7 - r2 * (1.0 / 9)))));
  }
  return std::atan2(y, x);
}

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

namespace {

struct V3 { double x, y, z; };
__attribute__((always_inline)) inline V3 mul(const double *r, const double *v)
{
  return { r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
           r[6] * v[0] + r[7] * v[1] + r[8] * v[2] };
}
__attribute__((always_inline)) inline V3 cross(const V3 &a, const V3 &b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
__attribute__((always_inline)) inline double dot(const V3 &a, const V3 &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
__attribute__((always_inline)) inline V3 axpy(double a, const V3 &x, const V3 &y)
{
  return { a * x.x + y.x, a * x.y + y.y, a * x.z + y.z };
}
// Rotation vector of the smallest rotation taking unit vector a onto unit vector b:
// angle / sin(angle) = asin(s) / s by its series at small angles, atan2 otherwise.
__attribute__((always_inline)) inline V3 bend(const V3 &a, const V3 &b)
{
  const V3 c = cross(a, b);
  const double s2 = dot(c, c), co = dot(a, b);
  double f;
  if (co > 0.0 && s2 < SMALL_SIN2) {
    f = 1.0 + s2 * (1.0 / 6 + s2 * (3.0 / 40 + s2 * (5.0 / 112 + s2 * (35.0 / 1152))));
  } else {
    const double s = std::sqrt(s2);
    f = s < 1e-300 ? 0.0 : std::atan2(s, co) / s;
  }
  return { f * c.x, f * c.y, f * c.z };
}

}  // namespace

void BeamLaw::evaluate(const double *h, const double *xi, const double *xj, const double *ri,
                       const double *rj, BeamResult &out, bool report) const
{
  const double l0 = h[B_L0];
  const V3 d = { xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2] };
  const double L = std::sqrt(dot(d, d)), inv_L = 1.0 / L;
  const V3 e = { d.x * inv_L, d.y * inv_L, d.z * inv_L };
  const double inv_l0 = 1.0 / l0;
  const double ka = EA_ * inv_l0, kb = fEI_ * inv_l0, kt = ftGJ_ * inv_l0;
  const double cs = p_.shear == ShearModel::EULER_BERNOULLI ? 3.0 * kb : 0.25 * GA_ * l0;

  // end rotations relative to the chord
  const V3 th_i = bend(e, mul(ri, h + B_DI)), th_j = bend(e, mul(rj, h + B_DJ));
  // twist: the ends' reference normals projected on the chord's normal plane
  V3 ni = mul(ri, h + B_PI), nj = mul(rj, h + B_PJ);
  ni = axpy(-dot(e, ni), e, ni);
  nj = axpy(-dot(e, nj), e, nj);
  const double phi = angle(dot(e, cross(ni, nj)), dot(ni, nj));

  const V3 sum = { th_i.x + th_j.x, th_i.y + th_j.y, th_i.z + th_j.z };
  const V3 diff = { th_i.x - th_j.x, th_i.y - th_j.y, th_i.z - th_j.z };
  const V3 bend_i = { kb * diff.x + cs * sum.x, kb * diff.y + cs * sum.y, kb * diff.z + cs * sum.z };
  const V3 bend_j = { cs * sum.x - kb * diff.x, cs * sum.y - kb * diff.y, cs * sum.z - kb * diff.z };
  const V3 sc = cross(sum, e);
  const double fs = 2.0 * cs * inv_L;
  const double axial = ka * (L - l0), tw = kt * phi;

  out.force_i = Eigen::Vector3d(axial * e.x - fs * sc.x, axial * e.y - fs * sc.y, axial * e.z - fs * sc.z);
  out.torque_i = Eigen::Vector3d(tw * e.x - bend_i.x, tw * e.y - bend_i.y, tw * e.z - bend_i.z);
  out.torque_j = Eigen::Vector3d(-tw * e.x - bend_j.x, -tw * e.y - bend_j.y, -tw * e.z - bend_j.z);
  out.axial = axial;
  if (!report) return;
  out.shear = fs * std::sqrt(dot(sc, sc));
  out.moment = std::sqrt(std::max(dot(bend_i, bend_i), dot(bend_j, bend_j)));
  out.energy = 0.5 * (axial * (L - l0) + kb * dot(diff, diff) + cs * dot(sum, sum) + kt * phi * phi);
}

}  // namespace WireNet
