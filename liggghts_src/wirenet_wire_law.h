/* WireNet: tension-only elasto-plastic wire law (Thoeni et al. 2013, Bertrand et al. 2008).
   No LIGGGHTS dependency: the kernel is plain arithmetic on a bond's history record. */

#ifndef WIRENET_WIRE_LAW_H
#define WIRENET_WIRE_LAW_H

#include <string>
#include <vector>

namespace WireNet {

// Per-bond history record of a wire bond (doubles in the history fix's slot).
// The bond's force-elongation envelope is the type's (strain, stress) table mapped by
//   u = a * strain + b,  F = c * stress,
// preceded by the segment from (0,0) to the first mapped point. This one transform covers the
// plain law (a = l0, b = 0, c = A), the derived double-twist law (c scaled by k_D/k), the
// random initial slack (a = l0 + dl, b = dl) and a table of elongations and forces (a = 1,
// b = 0, c = 1: the brake law, wirenet_brake_law.h).
enum WireSlot {
  W_L0 = 0,     // initial length; 0 until the bond is initialised at the first run
  W_A,          // strain -> elongation scale
  W_B,          // elongation offset (slack)
  W_C,          // stress -> force scale
  W_KU,         // unloading / reloading stiffness
  W_UMAX,       // largest elongation reached
  W_FMAX,       // envelope force at W_UMAX
  W_NSLOTS
};

// The constants of one bond's envelope, derived from its record (which never changes after the
// bond's first run except for W_UMAX and W_FMAX): the kernel then needs no division, no table
// below the first point and no look-up of its type's law.
struct WireConst {
  double u_rupture;  // elongation at rupture
  double u1;         // elongation of the first table point
  double k1;         // force per elongation below it (the first segment)
  double inv_a;      // 1 / W_A: elongation -> strain
  double b, c;       // W_B, W_C
  double ku;         // W_KU
};

struct WireLawParams {
  double diameter = 0.0;
  double area_factor = 1.0;
  std::vector<double> strain, stress;  // table without the implied (0,0)
  bool derived = false;
  double lambda_eps = 0.0, lambda_k = 0.0, nu = 0.0;
  bool slack = false;
  double lambda_u = 0.0, lambda_f = 1.0;
  long seed = 0;
  double damping = 0.0;  // fraction of critical damping of the bond's two-node oscillator
  // The table holds elongations [m] and forces [N], used as they are (a = 1, b = 0, c = 1):
  // diameter, area_factor, derived and slack do not apply.
  bool force_elongation = false;
  // false: no rupture, the last segment of the table continues without end
  bool breakable = true;
};

class WireLaw {
 public:
  // Throws std::invalid_argument with a one-line message naming the problem.
  explicit WireLaw(const WireLawParams &p);

  const WireLawParams &params() const { return p_; }
  double area() const { return area_; }

  // Fill a bond's record from its initial length and the two atom tags (slack draw).
  void init_bond(double *h, double l0, long tag1, long tag2) const;

  // The envelope constants of a bond's record (after init_bond), for the law at `scale` s: the
  // envelope F_s(u) = s F(u / s), every force and elongation of it s times, its stiffnesses
  // as they are (fix_modify wirenet_bonds scale; the record's state is kept at that scale).
  void prepare(const double *h, WireConst &k, double scale = 1.0) const;
  // Tension [N] at elongation u; updates the plastic state (W_UMAX, W_FMAX of h). Returns false
  // on rupture. k: prepare(h).
  inline bool tension(const WireConst &k, double u, double *h, double &force) const;
  // Tension without touching the state (output), for the law at `scale` (prepare()).
  double tension_const(double u, const double *h, double scale = 1.0) const;
  // Plastic work of a bond so far: the work along the envelope up to the largest elongation
  // reached (W_UMAX) less the elastic energy unloading from there gives back. A function of the
  // state (unloading and reloading follow one elastic line), exact for the piecewise-linear
  // envelope, so the tally is summed when it is read, not in the force loop. k: prepare(h, k,
  // scale); the work of the law at that scale (scale^2 times the work at scale 1).
  double plastic_work(const WireConst &k, const double *h, double scale = 1.0) const;

  // Slack fraction r in [0,1] (triangular, mode 1/2) drawn from the seed and the two tags.
  static double slack_draw(long seed, long tag1, long tag2);

 private:
  inline double envelope(const WireConst &k, double u) const;
  inline int segment(double e) const;  // table segment of strain e (the last one beyond it)
  double envelope_work(const WireConst &k, double a, double u) const;  // integral of the envelope, 0 to u

  WireLawParams p_;
  double area_ = 0.0;
  std::vector<double> strain_, stress_, slope_;  // effective table (derived / slack applied)
  std::vector<double> work_;  // [j]: integral of stress over strain from strain_[0] to strain_[j]
  int elastic_point_ = 0;  // table index of the point that defines the unloading stiffness
  double rupture_strain_ = 0.0;  // last table strain, or infinity (not breakable)
};

// ----------------------------------------------------------------------------------------------

inline int WireLaw::segment(double e) const
{
  const int n = (int)strain_.size();
  int j = 0;
  while (j < n - 2 && e > strain_[j + 1]) ++j;
  return j;
}

inline double WireLaw::envelope(const WireConst &k, double u) const
{
  if (u <= k.u1) return k.k1 * u;
  const double e = (u - k.b) * k.inv_a;
  const int j = segment(e);
  return k.c * (stress_[j] + slope_[j] * (e - strain_[j]));
}

inline bool WireLaw::tension(const WireConst &k, double u, double *h, double &force) const
{
  if (u > k.u_rupture) { force = 0.0; return false; }
  if (u >= h[W_UMAX]) {
    h[W_UMAX] = u;
    h[W_FMAX] = envelope(k, u);
    force = h[W_FMAX];
  } else {
    const double f = h[W_FMAX] - k.ku * (h[W_UMAX] - u);
    force = f > 0.0 ? f : 0.0;
  }
  return true;
}

}  // namespace WireNet

#endif
