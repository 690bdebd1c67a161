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
   Ks = GA/L0 is the classical parallel bond.
   A general section (`section A IY IZ J orient ...`) has a Kb and a Cs per principal axis: the
   rotation vectors, normal to e, are split into their parts along the current axes y and z,
   each with its own stiffness (written as the mean of the two axes plus D = y y^T - z z^T times
   half their difference; the circle has no difference and runs the kernel without D).
   The force kernel, BeamLaw::load, is inline in the header: it is the body of the bond loop. */

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

inline void store3(double *h, const Vector3d &v) { h[0] = v[0]; h[1] = v[1]; h[2] = v[2]; }

}  // namespace

BeamLaw::BeamLaw(const BeamLawParams &p) : p_(p)
{
  // isfinite refuses inf and nan (which would pass a negated comparison)
  if (p.section) {
    require(std::isfinite(p.area) && p.area > 0.0, "beam section A must be a finite number > 0", p.area);
    require(std::isfinite(p.iy) && p.iy > 0.0, "beam section IY must be a finite number > 0", p.iy);
    require(std::isfinite(p.iz) && p.iz > 0.0, "beam section IZ must be a finite number > 0", p.iz);
    require(std::isfinite(p.torsion) && p.torsion > 0.0, "beam section J must be a finite number > 0", p.torsion);
    for (int c = 0; c < 3; c++)
      require(std::isfinite(p.orient[c]), std::string("beam orient ") + "XYZ"[c] + " must be a finite number",
              p.orient[c]);
    const double o2 = p.orient[0] * p.orient[0] + p.orient[1] * p.orient[1] + p.orient[2] * p.orient[2];
    if (!(o2 > 0.0 && std::isfinite(o2))) {
      std::ostringstream m;
      m << "beam orient must be a non-zero vector of finite length (got " << p.orient[0] << " " << p.orient[1] << " "
        << p.orient[2] << ")";
      throw std::invalid_argument(m.str());
    }
    // the parallel-bond stresses need the radius of a circle; bond damping's modes an isotropic
    // bending stiffness
    if (p.strength) throw std::invalid_argument("beam strength needs a circular section (diameter), not section");
    if (p.damping != 0.0) throw std::invalid_argument("beam damping is not available with section (use a circular section or no damping)");
  } else {
    require(std::isfinite(p.diameter) && p.diameter > 0.0, "beam diameter must be a finite number > 0", p.diameter);
  }
  require(std::isfinite(p.young) && p.young > 0.0, "beam E must be a finite number > 0", p.young);
  require(p.nu > -1.0 && p.nu < 0.5, "beam nu must be in (-1,0.5)", p.nu);
  require(std::isfinite(p.bending) && p.bending >= 0.0, "beam bending fraction must be a finite number >= 0", p.bending);
  // twist < 0 is the "not given" sentinel (the parser refuses an explicit negative value)
  twist_fraction_ = p.twist < 0.0 ? p.bending : p.twist;
  require(std::isfinite(twist_fraction_), "beam twist fraction must be a finite number >= 0", p.twist);
  if (p.strength) {
    require(std::isfinite(p.sigma_t) && p.sigma_t > 0.0, "beam strength SIGMA_T must be a finite number > 0", p.sigma_t);
    require(std::isfinite(p.tau_c) && p.tau_c > 0.0, "beam strength TAU_C must be a finite number > 0", p.tau_c);
  }
  require(std::isfinite(p.damping) && p.damping >= 0.0, "beam damping must be a finite number >= 0", p.damping);
  if (p.section) {
    area_ = p.area;
    inertia_ = 0.5 * (p.iy + p.iz);
    polar_ = p.torsion;
  } else {
    const double r = 0.5 * p.diameter;
    area_ = M_PI * r * r;
    inertia_ = M_PI * r * r * r * r / 4.0;
    polar_ = 2.0 * inertia_;
  }
  young_ = p.young;
  shear_modulus_ = p.young / (2.0 * (1.0 + p.nu));
  EA_ = young_ * area_;
  fEI_ = p.bending * young_ * inertia_;
  if (p.section) fEId_ = p.bending * young_ * 0.5 * (p.iy - p.iz);
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
  Vector3d n;
  if (p_.section) {
    // the principal axis y: `orient` without its part along the bond
    const Vector3d o(p_.orient[0], p_.orient[1], p_.orient[2]);
    n = o - o.dot(e) * e;
    if (!(n.norm() >= 1e-3 * o.norm())) {
      std::ostringstream m;
      m << "beam orient (" << o[0] << ", " << o[1] << ", " << o[2] << ") is parallel to the bond (direction ("
        << e[0] << ", " << e[1] << ", " << e[2] << ")); give a vector across it";
      throw std::invalid_argument(m.str());
    }
  } else {
    // any unit normal of the chord; fixed from the chord so it is the same on every rank
    n = e.cross(Vector3d::UnitZ());
    if (n.norm() < 0.1) n = e.cross(Vector3d::UnitX());
  }
  n.normalize();
  h[B_L0] = l0;
  store3(h + B_DI, ri.transpose() * e);
  store3(h + B_DJ, rj.transpose() * e);
  store3(h + B_PI, ri.transpose() * n);
  store3(h + B_PJ, rj.transpose() * n);
}

void BeamLaw::prepare(const double *h, BeamConst<double> &b, double scale) const
{
  const double l0 = h[B_L0];
  const Stiffness k = stiffness(l0);
  b.l0 = l0;
  b.ka = k.axial;
  b.kp = k.bending + k.shear_coupling;
  b.km = k.shear_coupling - k.bending;
  b.kf = 2.0 * k.shear_coupling;
  b.kt = k.twist;
  // strength of the geometric section of diameter D, whatever the stiffness fractions, S times
  const double R = 0.5 * p_.diameter;
  const double sigma = scale * p_.sigma_t, tau = scale * p_.tau_c;
  b.sa = p_.strength ? 1.0 / (area_ * sigma) : 0.0;
  b.sm = p_.strength ? R / (inertia_ * sigma) : 0.0;
  b.ss = p_.strength ? 1.0 / (area_ * tau) : 0.0;
  b.st = p_.strength ? R / (polar_ * tau) : 0.0;
  b.ca = b.cs = b.cb = b.ct = 0.0;  // set_damping() with the node masses
  for (int c = 0; c < 3; c++) {
    b.di[c] = h[B_DI + c];
    b.dj[c] = h[B_DJ + c];
    b.pi[c] = h[B_PI + c];
    b.pj[c] = h[B_PJ + c];
  }
}

void BeamLaw::prepare_section(const double *h, BeamSection<double> &s) const
{
  // the halves of the differences between the axes y and z of Kb, Cs and 2 Cs (prepare())
  const double l0 = h[B_L0];
  const double kbd = fEId_ / l0;
  const double csd = p_.shear == ShearModel::EULER_BERNOULLI ? 3.0 * kbd : 0.0;  // pb: G A L0 / 4, isotropic
  s.kpd = kbd + csd;
  s.kmd = csd - kbd;
  s.kfd = 2.0 * csd;
}

void BeamLaw::set_damping(double l0, double mi, double mj, double ii, double ij, BeamConst<double> &b) const
{
  // each mode of the two-node bond is an oscillator of stiffness k and effective mass (or moment
  // of inertia) m1 m2 / (m1 + m2): c = 2 zeta sqrt(k m_eff)
  const double z = p_.damping;
  if (z == 0.0) { b.ca = b.cs = b.cb = b.ct = 0.0; return; }
  const Stiffness k = stiffness(l0);
  const double m_eff = mi * mj / (mi + mj), i_eff = ii * ij / (ii + ij);
  const double ks = 4.0 * k.shear_coupling / (l0 * l0);  // Ks = 4 Cs / l0^2
  // the shear damper acts on one coordinate, the slip at the bond's centre, which both nodes'
  // translations and (lever l0/2) rotations move: its oscillator's mass is 1 / (1/m_eff +
  // (l0/2)^2 / i_eff). With m_eff alone a rope node small beside l0 had its rotation damped at
  // zeta (l0/2) sqrt(m/I), near critical, where the explicit step overshoots and gains energy.
  const double half = 0.5 * l0;
  const double m_slip = 1.0 / (1.0 / m_eff + half * half / i_eff);
  b.ca = 2.0 * z * std::sqrt(k.axial * m_eff);
  b.cs = 2.0 * z * std::sqrt(ks * m_slip);
  b.cb = 2.0 * z * std::sqrt(k.bending * i_eff);
  b.ct = 2.0 * z * std::sqrt(k.twist * i_eff);
}

BeamConst<double> lane(const BeamConst<Lanes> &p, int k)
{
  BeamConst<double> b;
  b.l0 = p.l0[k];
  b.ka = p.ka[k];
  b.kp = p.kp[k];
  b.km = p.km[k];
  b.kf = p.kf[k];
  b.kt = p.kt[k];
  b.sa = p.sa[k]; b.sm = p.sm[k]; b.ss = p.ss[k]; b.st = p.st[k];
  b.ca = p.ca[k]; b.cs = p.cs[k]; b.cb = p.cb[k]; b.ct = p.ct[k];
  for (int c = 0; c < 3; c++) {
    b.di[c] = p.di[c][k];
    b.dj[c] = p.dj[c][k];
    b.pi[c] = p.pi[c][k];
    b.pj[c] = p.pj[c][k];
  }
  return b;
}

void set_lane(BeamConst<Lanes> &p, int k, const BeamConst<double> &b)
{
  p.l0[k] = b.l0;
  p.ka[k] = b.ka;
  p.kp[k] = b.kp;
  p.km[k] = b.km;
  p.kf[k] = b.kf;
  p.kt[k] = b.kt;
  p.sa[k] = b.sa; p.sm[k] = b.sm; p.ss[k] = b.ss; p.st[k] = b.st;
  p.ca[k] = b.ca; p.cs[k] = b.cs; p.cb[k] = b.cb; p.ct[k] = b.ct;
  for (int c = 0; c < 3; c++) {
    p.di[c][k] = b.di[c];
    p.dj[c][k] = b.dj[c];
    p.pi[c][k] = b.pi[c];
    p.pj[c][k] = b.pj[c];
  }
}

BeamSection<double> lane(const BeamSection<Lanes> &p, int k)
{
  return { p.kpd[k], p.kmd[k], p.kfd[k] };
}

void set_lane(BeamSection<Lanes> &p, int k, const BeamSection<double> &s)
{
  p.kpd[k] = s.kpd;
  p.kmd[k] = s.kmd;
  p.kfd[k] = s.kfd;
}

void BeamLaw::evaluate(const double *h, const double *xi, const double *xj, const double *ri,
                       const double *rj, BeamResult &out, bool report) const
{
  BeamConst<double> b;
  prepare(h, b);
  BeamNodes<double> n;
  for (int c = 0; c < 3; c++) {
    n.xi[c] = xi[c];
    n.xj[c] = xj[c];
  }
  for (int c = 0; c < 9; c++) {
    n.ri[c] = ri[c];
    n.rj[c] = rj[c];
  }
  if (p_.section) {
    BeamSection<double> s;
    prepare_section(h, s);
    if (report) load_section<true>(b, s, n, out);
    else load_section<false>(b, s, n, out);
    return;
  }
  if (report) load<true>(b, n, out);
  else load<false>(b, n, out);
}

}  // namespace WireNet
