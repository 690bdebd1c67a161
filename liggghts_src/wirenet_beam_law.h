/* WireNet: parallel-bond beam law (Potyondy & Cundall 2004) for strand ropes, in a corotational
   form that is exact for rigid rotations. No LIGGGHTS dependency. */

#ifndef WIRENET_BEAM_LAW_H
#define WIRENET_BEAM_LAW_H

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace WireNet {

enum class ShearModel { EULER_BERNOULLI = 0, PARALLEL_BOND = 1 };

struct BeamLawParams {
  double diameter = 0.0;
  double young = 0.0;
  double nu = 0.0;
  double bending = 1.0;  // fraction of E I
  double twist = -1.0;   // fraction of G J; < 0 means "same as bending"
  ShearModel shear = ShearModel::EULER_BERNOULLI;
};

// Per-bond history record of a beam bond. The chord direction and a perpendicular reference are
// stored in each node's body frame at the first run; the current material directions of the two
// ends follow from the node orientations.
enum BeamSlot {
  B_L0 = 0,
  B_DI = 1,   // initial chord direction in node i's frame (3)
  B_DJ = 4,   // initial chord direction in node j's frame (3)
  B_PI = 7,   // reference normal in node i's frame (3)
  B_PJ = 10,  // reference normal in node j's frame (3)
  B_NSLOTS = 13
};

struct BeamResult {
  double force_i[3];           // force on node i (node j gets the opposite)
  double torque_i[3], torque_j[3];
  double axial;                // axial force, positive in tension
  // for output and energy tallies only (not filled in the bond loop)
  double shear;                // shear force magnitude
  double moment;               // largest end bending moment magnitude
  double energy;               // strain energy
};

// The two ends of a bond side by side, lane 0 node i and lane 1 node j: the kernel treats both
// ends in one instruction (SSE2 on x86-64; GCC/Clang vector extension).
typedef double Ends __attribute__((vector_size(16)));

// One beam bond as the bond loop reads it: its nodes and the constant part of its history
// record, with the stiffnesses divided by l0 once (a beam record never changes after its first
// run), packed so that a bond is one contiguous read.
struct BeamBond {
  int i, j;             // node indices (local or ghost), set by the bond style
  double l0;
  double ka;            // axial stiffness E A / l0
  double kp, km;        // end moment per own / other end rotation: Kb + Cs, Cs - Kb
  double kf;            // 2 Cs: shear force = kf |theta_i + theta_j| / L
  double kt;            // twist stiffness
  Ends d[3], p[3];      // chord direction and reference normal in each node's frame (x, y, z)
};

class BeamLaw {
 public:
  // Throws std::invalid_argument with a one-line message naming the problem.
  explicit BeamLaw(const BeamLawParams &p);
  const BeamLawParams &params() const { return p_; }

  double area() const { return area_; }
  double EI() const { return young_ * inertia_; }
  double GJ() const { return shear_modulus_ * polar_; }

  // Node orientations are rotation matrices (row-major, body to space).
  using Rotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
  void init_bond(double *h, const Eigen::Vector3d &xi, const Eigen::Vector3d &xj,
                 const Rotation &ri, const Rotation &rj) const;
  // The bond-loop form of an initialised record (b.i and b.j are left to the caller).
  void prepare(const double *h, BeamBond &b) const;

  // Forces and moments of one bond from raw pointers: positions (3) and row-major rotation
  // matrices (9) straight from the atom and history arrays. With REPORT false only forces,
  // torques and the axial force are filled. Inline and written out in scalars: it is the body
  // of the bond loop.
  template <bool REPORT>
  static void load(const BeamBond &b, const double *xi, const double *xj, const double *ri,
                   const double *rj, BeamResult &out);
  // The same from a history record (output, tests).
  void evaluate(const double *h, const double *xi, const double *xj, const double *ri,
                const double *rj, BeamResult &out, bool report = true) const;

  // Stiffnesses of a bond of initial length l0 (for the time-step estimate).
  struct Stiffness { double axial, bending, shear_coupling, twist; };
  Stiffness stiffness(double l0) const;

 private:
  BeamLawParams p_;
  double area_, inertia_, polar_, young_, shear_modulus_, twist_fraction_;
  double EA_, fEI_, ftGJ_, GA_;  // stiffness numerators, divided by l0 per bond
};

namespace beam_kernel {

// Bonds bend little: below these sizes the series are exact to round-off and skip the
// transcendental calls that would otherwise dominate the bond's cost.
const double SMALL_SIN2 = 0.05 * 0.05;
const double SMALL_TAN = 0.05;

struct V3 { double x, y, z; };
struct E3 { Ends x, y, z; };  // a vector at each end

inline E3 mul(const Ends *r, const Ends *v)
{
  return { r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
           r[6] * v[0] + r[7] * v[1] + r[8] * v[2] };
}
inline E3 cross(const E3 &a, const E3 &b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
inline Ends dot(const E3 &a, const E3 &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(const V3 &a, const V3 &b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
inline double dot(const V3 &a, const V3 &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Ends swap(Ends a) { return Ends{ a[1], a[0] }; }
inline V3 lane(const E3 &a, int k) { return { a.x[k], a.y[k], a.z[k] }; }

// atan2(y, x), by its series when the angle is small
inline double angle(double y, double x)
{
  if (x > 0.0 && std::fabs(y) < SMALL_TAN * x) {
    const double r = y / x, r2 = r * r;
    return r * (1.0 - r2 * (1.0 / 3 - r2 * (1.0 / 5 - r2 * (1.0 / 7 - r2 * (1.0 / 9)))));
  }
  return std::atan2(y, x);
}

// Rotation vectors of the smallest rotations taking unit vector a onto the unit vectors b of
// both ends: angle / sin(angle) = asin(s) / s by its series at small angles, atan2 otherwise.
inline E3 bend(const E3 &a, const E3 &b)
{
  const E3 c = cross(a, b);
  const Ends s2 = dot(c, c), co = dot(a, b);
  Ends f;
  if (co[0] > 0.0 && co[1] > 0.0 && s2[0] < SMALL_SIN2 && s2[1] < SMALL_SIN2) {
    f = 1.0 + s2 * (1.0 / 6 + s2 * (3.0 / 40 + s2 * (5.0 / 112 + s2 * (35.0 / 1152))));
  } else {
    for (int k = 0; k < 2; k++) {
      const double s = std::sqrt(s2[k]);
      f[k] = s < 1e-300 ? 0.0 : std::atan2(s, co[k]) / s;
    }
  }
  return { f * c.x, f * c.y, f * c.z };
}

}  // namespace beam_kernel

// always_inline: GCC would call it, and the loop pays for the call and the result's round trip
template <bool REPORT>
inline __attribute__((always_inline)) void BeamLaw::load(const BeamBond &b, const double *xi, const double *xj, const double *ri,
                          const double *rj, BeamResult &out)
{
  using namespace beam_kernel;
  const V3 d = { xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2] };
  const double L = std::sqrt(dot(d, d)), inv_L = 1.0 / L;
  const V3 e = { d.x * inv_L, d.y * inv_L, d.z * inv_L };
  const E3 ee = { Ends{ e.x, e.x }, Ends{ e.y, e.y }, Ends{ e.z, e.z } };
  Ends r[9];
  for (int k = 0; k < 9; k++) r[k] = Ends{ ri[k], rj[k] };

  // end rotations relative to the chord
  const E3 th = bend(ee, mul(r, b.d));
  // twist: angle about e between the ends' reference normals projected on the plane normal to
  // e; the projection leaves their triple product with e unchanged and turns their dot product
  // into ni.nj - (e.ni)(e.nj), so the projected vectors are never formed
  const E3 n = mul(r, b.p);
  const Ends en = dot(ee, n);
  const V3 ni = lane(n, 0), nj = lane(n, 1);
  const double phi = angle(dot(e, cross(ni, nj)), dot(ni, nj) - en[0] * en[1]);

  // bending moments Kb (th_i - th_j) + Cs (th_i + th_j) at both ends, the shear of their balance
  const E3 th_other = { swap(th.x), swap(th.y), swap(th.z) };
  const E3 m = { b.kp * th.x + b.km * th_other.x, b.kp * th.y + b.km * th_other.y,
                 b.kp * th.z + b.km * th_other.z };
  const V3 sum = { th.x[0] + th.x[1], th.y[0] + th.y[1], th.z[0] + th.z[1] };
  const V3 sc = cross(sum, e);
  const double fs = b.kf * inv_L;
  const double axial = b.ka * (L - b.l0), tw = b.kt * phi;

  out.force_i[0] = axial * e.x - fs * sc.x;
  out.force_i[1] = axial * e.y - fs * sc.y;
  out.force_i[2] = axial * e.z - fs * sc.z;
  // twisting moments +tw e on node i, -tw e on node j
  const Ends tws = { tw, -tw };
  const E3 torque = { tws * ee.x - m.x, tws * ee.y - m.y, tws * ee.z - m.z };
  for (int k = 0; k < 3; k++) {
    const Ends &c = k == 0 ? torque.x : k == 1 ? torque.y : torque.z;
    out.torque_i[k] = c[0];
    out.torque_j[k] = c[1];
  }
  out.axial = axial;
  if (!REPORT) return;
  out.shear = fs * std::sqrt(dot(sc, sc));
  const Ends mm = dot(m, m), work = dot(m, th);
  out.moment = std::sqrt(std::max(mm[0], mm[1]));
  // half the generalised forces times their displacements
  out.energy = 0.5 * (axial * (L - b.l0) + work[0] + work[1] + tw * phi);
}

}  // namespace WireNet

#endif
