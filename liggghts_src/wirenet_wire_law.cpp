/* WireNet: tension-only elasto-plastic wire law. See wirenet_wire_law.h and doc/bond_wirenet.md. */

#include "wirenet_wire_law.h"
#include "wirenet_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

namespace WireNet {

namespace {

// splitmix64: a well-mixed 64-bit hash, so the slack of a bond depends only on (seed, tags).
uint64_t mix(uint64_t z)
{
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double unit(uint64_t z) { return (double)(z >> 11) * (1.0 / 9007199254740992.0); }

}  // namespace

WireLaw::WireLaw(const WireLawParams &p) : p_(p)
{
  // every check is written so that nan fails it; isfinite refuses inf
  if (!p.force_elongation) {
    require(std::isfinite(p.diameter) && p.diameter > 0.0,
            "wire diameter must be a finite number > 0 (got " + fmt(p.diameter) + ")");
    require(std::isfinite(p.area_factor) && p.area_factor > 0.0,
            "wire area_factor must be a finite number > 0 (got " + fmt(p.area_factor) + ")");
  } else {
    require(!p.derived && !p.slack, "a force-elongation table takes neither derived nor slack");
  }
  require(std::isfinite(p.damping) && p.damping >= 0.0,
          "wire damping must be a finite number >= 0 (got " + fmt(p.damping) + ")");
  require(!p.strain.empty(), "wire law needs a curve (strain stress pairs)");
  require(p.strain.size() == p.stress.size(), "wire curve needs an even number of values (strain stress pairs)");
  for (size_t i = 0; i < p.strain.size(); ++i) {
    const std::string at = "wire curve point " + std::to_string(i + 1);
    require(std::isfinite(p.strain[i]) && p.strain[i] > 0.0,
            at + ": strain must be a finite number > 0 (got " + fmt(p.strain[i]) + ")");
    require(std::isfinite(p.stress[i]) && p.stress[i] >= 0.0,
            at + ": stress must be a finite number >= 0 (got " + fmt(p.stress[i]) + ")");
    if (i > 0)
      require(p.strain[i] > p.strain[i - 1], at + ": strains must increase (" + fmt(p.strain[i - 1]) +
                                             " then " + fmt(p.strain[i]) + ")");
  }
  require(p.stress[0] > 0.0, "wire curve point 1: stress must be > 0 (it sets the elastic stiffness)");
  area_ = p.force_elongation ? 0.0 : p.area_factor * M_PI * p.diameter * p.diameter / 4.0;

  strain_ = p.strain;
  stress_ = p.stress;
  if (p.derived) {
    require(std::isfinite(p.lambda_eps) && p.lambda_eps > 0.0,
            "derived lambda_eps must be a finite number > 0 (got " + fmt(p.lambda_eps) + ")");
    require(p.lambda_k >= 0.0 && p.lambda_k <= 1.0, "derived lambda_k must be in [0,1] (got " + fmt(p.lambda_k) + ")");
    require(p.nu > -1.0 && p.nu < 0.5, "derived nu must be in (-1,0.5) (got " + fmt(p.nu) + ")");
    for (size_t i = 1; i < strain_.size(); ++i) strain_[i] *= p.lambda_eps;
    for (size_t i = 1; i < strain_.size(); ++i)
      require(strain_[i] > strain_[i - 1], "derived lambda_eps " + fmt(p.lambda_eps) +
                                           " makes the double-twist strains non-increasing at point " +
                                           std::to_string(i + 1));
  }
  if (p.slack) {
    require(std::isfinite(p.lambda_u) && p.lambda_u >= 0.0,
            "slack lambda_u must be a finite number >= 0 (got " + fmt(p.lambda_u) + ")");
    require(p.lambda_f > 0.0 && p.lambda_f <= 1.0, "slack lambda_f must be in (0,1] (got " + fmt(p.lambda_f) + ")");
    if (p.lambda_f < 1.0) {
      // Softer first loading branch through the slack: an extra point below the elastic one.
      strain_.insert(strain_.begin(), p.lambda_f * strain_[0]);
      stress_.insert(stress_.begin(), p.lambda_f * stress_[0]);
      elastic_point_ = 1;
    }
  }
  rupture_strain_ = p.breakable ? strain_.back() : INFINITY;
  slope_.assign(strain_.size(), 0.0);
  for (size_t k = 0; k + 1 < strain_.size(); ++k)
    slope_[k] = (stress_[k + 1] - stress_[k]) / (strain_[k + 1] - strain_[k]);
  work_.assign(strain_.size(), 0.0);
  for (size_t k = 0; k + 1 < strain_.size(); ++k)
    work_[k + 1] = work_[k] + 0.5 * (stress_[k] + stress_[k + 1]) * (strain_[k + 1] - strain_[k]);
}

double WireLaw::slack_draw(long seed, long tag1, long tag2)
{
  if (seed == -1) return 1.0;  // deterministic worst case, used by the reference traces
  const uint64_t lo = (uint64_t)std::min(tag1, tag2), hi = (uint64_t)std::max(tag1, tag2);
  const uint64_t h1 = mix(mix((uint64_t)seed) ^ lo);
  const uint64_t h2 = mix(h1 ^ hi);
  const uint64_t h3 = mix(h2);
  // The mean of two uniforms is triangular on [0,1] with mode 1/2.
  return 0.5 * (unit(h2) + unit(h3));
}

void WireLaw::init_bond(double *h, double l0, long tag1, long tag2) const
{
  const double dl = p_.slack ? p_.lambda_u * l0 * slack_draw(p_.seed, tag1, tag2) : 0.0;
  double scale = 1.0;
  if (p_.derived) {
    // Bertrand et al. (2008): double-twist stiffness k_D from the wire's axial stiffness k and the
    // helix stiffness k_h of the twisted pair; stresses scale by k_D / k.
    const double d = p_.diameter;
    const double alpha = std::atan(l0 / (3.0 * M_PI * d));
    const double t = std::tan(alpha);
    const double kh_over_k = (l0 * d / area_) /
        (48.0 * std::cos(alpha) * (41.0 / 9.0 * (1.0 + p_.nu) + 17.0 / 4.0 * t * t));
    scale = 2.0 * (p_.lambda_k * kh_over_k + (1.0 - p_.lambda_k));
  }
  h[W_L0] = l0;
  if (p_.force_elongation) {
    h[W_A] = 1.0;
    h[W_B] = 0.0;
    h[W_C] = 1.0;
  } else {
    h[W_A] = l0 + dl;
    h[W_B] = dl;
    h[W_C] = area_ * scale;
  }
  h[W_KU] = h[W_C] * stress_[elastic_point_] / (h[W_A] * strain_[elastic_point_]);
  h[W_UMAX] = 0.0;
  h[W_FMAX] = 0.0;
}

// At scale s the map u = a e + b, F = c s(e) becomes u = (s a) e + s b, F = (s c) s(e): the
// breakpoints s times, the slopes (k1, ku and the table's) unchanged.
void WireLaw::prepare(const double *h, WireConst &k, double scale) const
{
  k.u_rupture = scale * (h[W_A] * rupture_strain_ + h[W_B]);
  k.u1 = scale * (h[W_A] * strain_[0] + h[W_B]);
  k.k1 = scale * h[W_C] * stress_[0] / k.u1;
  k.inv_a = 1.0 / (scale * h[W_A]);
  k.b = scale * h[W_B];
  k.c = scale * h[W_C];
  k.ku = h[W_KU];
}

double WireLaw::tension_const(double u, const double *h, double scale) const
{
  WireConst k;
  prepare(h, k, scale);
  if (u >= h[W_UMAX]) return envelope(k, u);
  const double f = h[W_FMAX] - k.ku * (h[W_UMAX] - u);
  return f > 0.0 ? f : 0.0;
}

// The envelope is F = k1 u up to u1, then F = c s(e) with u = a e + b: its integral is the
// first triangle plus c a times the integral of the stress table from strain_[0] to e (linear
// beyond the last point when the bond cannot break, as envelope() is).
double WireLaw::envelope_work(const WireConst &k, double a, double u) const
{
  if (u <= k.u1) return 0.5 * k.k1 * u * u;
  const double e = (u - k.b) * k.inv_a;
  const int j = segment(e);
  const double de = e - strain_[j];
  return 0.5 * k.k1 * k.u1 * k.u1 + k.c * a * (work_[j] + de * (stress_[j] + 0.5 * slope_[j] * de));
}

double WireLaw::plastic_work(const WireConst &k, const double *h, double scale) const
{
  if (h[W_UMAX] <= 0.0) return 0.0;
  return envelope_work(k, scale * h[W_A], h[W_UMAX]) - 0.5 * h[W_FMAX] * h[W_FMAX] / k.ku;
}

}  // namespace WireNet
