/* WireNet: shackle law. See wirenet_shackle_law.h and doc/fix_wirenet_shackle.md. */

#include "wirenet_shackle_law.h"

#include <cmath>

#include "wirenet_checks.h"

namespace WireNet {

ShackleLaw::ShackleLaw(const ShackleLawParams &p) : p_(p)
{
  require(std::isfinite(p.kn) && p.kn > 0.0, "kn must be a finite number > 0 (got " + fmt(p.kn) + ")");
  require(std::isfinite(p.kt) && p.kt > 0.0, "kt must be a finite number > 0 (got " + fmt(p.kt) + ")");
  require(std::isfinite(p.mu) && p.mu >= 0.0, "mu must be a finite number >= 0 (got " + fmt(p.mu) + ")");
  require(std::isfinite(p.damping) && p.damping >= 0.0,
          "damping must be a finite number >= 0 (got " + fmt(p.damping) + ")");
}

ShackleResult ShackleLaw::step(const Eigen::Vector3d &x, const Eigen::Vector3d &v, double m,
                               const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                               const Eigen::Vector3d &va, const Eigen::Vector3d &vb,
                               double s, double xi, double dt) const
{
  ShackleResult r;
  const Eigen::Vector3d e = b - a;
  const double len = e.norm();
  const Eigen::Vector3d t = len > 0.0 ? Eigen::Vector3d(e / len) : Eigen::Vector3d::Zero();

  // offset from the closest point; inside the segment only its part across the rope (the
  // projection removes the round-off of s), at a clamped vertex or end all of it
  Eigen::Vector3d d = x - (a + s * e);
  if (s > 0.0 && s < 1.0) d -= d.dot(t) * t;
  const double dn = d.norm();
  const double fn = p_.kn * dn;  // elastic holding force: the friction's normal force

  const Eigen::Vector3d vrel = v - ((1.0 - s) * va + s * vb);
  const double vt = vrel.dot(t);

  r.force = -p_.kn * d;
  if (p_.damping > 0.0) {
    const double c = 2.0 * p_.damping * std::sqrt(p_.kn * m);
    const Eigen::Vector3d vperp = vrel - vt * t;
    r.force -= c * vperp;
    r.damping_work = c * vperp.squaredNorm() * dt;
  }

  // Coulomb friction with an elastic stick spring
  const double trial = xi + vt * dt;
  const double cap = p_.mu * fn;
  double xi_new = trial;
  if (p_.kt * std::fabs(trial) > cap) {
    xi_new = std::copysign(cap / p_.kt, trial);
    r.sliding = true;
    r.slip_work = cap * std::fabs(trial - xi_new);
  }
  r.force -= p_.kt * xi_new * t;
  r.elastic = 0.5 * p_.kn * dn * dn + 0.5 * p_.kt * xi_new * xi_new;
  if (dt > 0.0) {
    r.xi = xi_new;
  } else {  // setup pass: the history stays as it is
    r.xi = xi;
    r.slip_work = 0.0;
  }
  return r;
}

}  // namespace WireNet
