/* WireNet: parallel-bond beam law (Potyondy & Cundall 2004) for strand ropes, in a corotational
   form that is exact for rigid rotations and conservative at any bending (forces and moments are
   the exact gradient of the strain energy, kept smooth through a half turn: beyond()). No
   LIGGGHTS dependency. */

#ifndef WIRENET_BEAM_LAW_H
#define WIRENET_BEAM_LAW_H

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include "wirenet_lanes.h"

namespace WireNet {

enum class ShearModel { EULER_BERNOULLI = 0, PARALLEL_BOND = 1 };

struct BeamLawParams {
  double diameter = 0.0;  // solid circular section (`diameter D`); 0 with `section`
  // `section A IY IZ J orient X Y Z`: a general section instead of the circle: area, second
  // moments about the section's principal axes y and z, torsion constant; y is the space vector
  // `orient` at the first run, projected normal to the bond, and z = e x y (e along the bond)
  bool section = false;
  double area = 0.0, iy = 0.0, iz = 0.0, torsion = 0.0;
  double orient[3] = { 0.0, 0.0, 0.0 };
  double young = 0.0;
  double nu = 0.0;
  double bending = 1.0;  // fraction of E I
  double twist = -1.0;   // fraction of G J; < 0 means "same as bending"
  ShearModel shear = ShearModel::EULER_BERNOULLI;
  bool strength = false;  // parallel-bond rupture (Potyondy & Cundall 2004); false: unbreakable
  double sigma_t = 0.0;   // tensile strength [Pa]
  double tau_c = 0.0;     // shear strength [Pa]
  double damping = 0.0;   // fraction of critical damping of each of the bond's two-node modes
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

// Two bonds side by side, one per lane (wirenet_lanes.h): the bond loop evaluates two bonds per
// instruction, and a bond gets the same bits alone (T = double) or in a pair (T = Lanes).

// The constant part of a beam bond's history record, stiffnesses divided by l0 once (a beam
// record never changes after its first run): one bond (T = double) or two (T = Lanes).
template <typename T> struct BeamConst {
  T l0;
  T ka;                          // axial stiffness E A / l0
  T kp, km;                      // end moment per own / other end rotation: Kb + Cs, Cs - Kb
  T kf;                          // 2 Cs = kp + km: shear force kf |theta_i + theta_j| / L at small angles (time step)
  T kt;                          // twist stiffness
  T di[3], dj[3], pi[3], pj[3];  // B_DI, B_DJ, B_PI, B_PJ of the record
  // strength: failure index = max(F_n sa + |M_b| sm, |F_s| ss + |M_t| st), the bond breaks at 1;
  // sa = 1/(A SIGMA_T), sm = R/(I SIGMA_T), ss = 1/(A TAU_C), st = R/(J TAU_C); 0 = no strength
  T sa, sm, ss, st;
  // damping coefficients of the axial, shear, bending and twist modes (set by the bond style,
  // which knows the node masses; not read by load())
  T ca, cs, cb, ct;
};

// The anisotropic part of a general section's bending (`section` with IY != IZ), the halves of
// the differences between the principal axes y and z: with D v = y (y.v) - z (z.v) the end
// moments get kpd D th_i + kmd D th_j (and the symmetric term), the shear kfd D (th_i + th_j)
// at small angles (kfd sets the time step; the kernel's shear is the energy's gradient).
// A circular section has none and its bonds never read this.
template <typename T> struct BeamSection { T kpd, kmd, kfd; };

// What the kernel reads of the nodes: positions and row-major rotation matrices (body to space).
template <typename T> struct BeamNodes { T xi[3], xj[3], ri[9], rj[9]; };

template <typename T> struct BeamLoad {
  T force_i[3];  // force on node i (node j gets the opposite)
  T torque_i[3], torque_j[3];
  T axial;       // axial force, positive in tension
  T fail;        // failure index (REPORT or STRESS only): the bond breaks when it is >= 1
  // for output and energy tallies only (REPORT)
  T shear;       // shear force magnitude
  T moment;      // largest end bending moment magnitude
  T energy;      // strain energy
};
using BeamResult = BeamLoad<double>;

// lane k of a pair of bonds, and back
BeamConst<double> lane(const BeamConst<Lanes> &p, int k);
void set_lane(BeamConst<Lanes> &p, int k, const BeamConst<double> &b);
BeamSection<double> lane(const BeamSection<Lanes> &p, int k);
void set_lane(BeamSection<Lanes> &p, int k, const BeamSection<double> &s);

class BeamLaw {
 public:
  // Throws std::invalid_argument with a one-line message naming the problem.
  explicit BeamLaw(const BeamLawParams &p);
  const BeamLawParams &params() const { return p_; }

  double area() const { return area_; }
  double EI() const { return young_ * inertia_; }  // a general section: the mean of the two axes
  double GJ() const { return shear_modulus_ * polar_; }

  // Node orientations are rotation matrices (row-major, body to space). With `section` the
  // record's reference normal is the principal axis y (`orient` projected normal to the bond);
  // throws std::invalid_argument when `orient` is (nearly) parallel to the bond.
  using Rotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
  void init_bond(double *h, const Eigen::Vector3d &xi, const Eigen::Vector3d &xj,
                 const Rotation &ri, const Rotation &rj) const;
  // the constants of an initialised record, for the law at `scale` S (fix_modify wirenet_bonds
  // scale): a linear law is its own magnification S F(u / S), so S scales the strengths alone
  void prepare(const double *h, BeamConst<double> &b, double scale = 1.0) const;
  // a general section (has_section()): the anisotropic constants of an initialised record
  void prepare_section(const double *h, BeamSection<double> &s) const;
  bool has_section() const { return p_.section; }

  // Forces and moments of one bond or a pair; with REPORT false only forces, torques and the
  // axial force are filled (REPORT needs T = double), STRESS adds the failure index. A pair
  // returns false, untouched, when one of its bonds bends or twists beyond the series (about 3
  // degrees): evaluate those one at a time (T = double always succeeds). Inline, component by
  // component: it is the bond loop.
  template <bool REPORT, bool STRESS = false, typename T>
  static bool load(const BeamConst<T> &b, const BeamNodes<T> &n, BeamLoad<T> &out);
  // The same for a bond of a general section (the isotropic part in b, the rest in s).
  template <bool REPORT, bool STRESS = false, typename T>
  static bool load_section(const BeamConst<T> &b, const BeamSection<T> &s, const BeamNodes<T> &n,
                           BeamLoad<T> &out);

  // Viscous damping of one bond (see doc/bond_wirenet.md, "Bond damping"): node velocities v and
  // angular velocities w. Sets the force f on i (j gets -f) and the torques ti, tj on i and j
  // (the bond style applies them and tallies their work at the end of the step). No allocation.
  // ca, cs, cb, ct: the coefficients of BeamConst.
  static inline void damp(double ca, double cs, double cb, double ct, const double *xi, const double *xj,
                          const double *vi, const double *vj, const double *wi, const double *wj,
                          double *f, double *ti, double *tj);
  // the damping coefficients of a bond of initial length l0 between nodes of masses mi, mj and
  // moments of inertia ii, ij
  void set_damping(double l0, double mi, double mj, double ii, double ij, BeamConst<double> &b) const;
  bool breakable() const { return p_.strength; }
  bool damped() const { return p_.damping > 0.0; }
  // The same from a history record and raw pointers (output, tests).
  void evaluate(const double *h, const double *xi, const double *xj, const double *ri,
                const double *rj, BeamResult &out, bool report = true) const;

  // Stiffnesses of a bond of initial length l0 (for the time-step estimate); bending and
  // shear_coupling of a general section are the means of its two axes.
  struct Stiffness { double axial, bending, shear_coupling, twist; };
  Stiffness stiffness(double l0) const;

 private:
  template <bool REPORT, bool STRESS, bool SECTION, typename T>
  static bool kernel(const BeamConst<T> &b, const BeamSection<T> *s, const BeamNodes<T> &n, BeamLoad<T> &out);

  BeamLawParams p_;
  double area_, inertia_, polar_, young_, shear_modulus_, twist_fraction_;
  double EA_, fEI_, ftGJ_, GA_;  // stiffness numerators, divided by l0 per bond
  double fEId_ = 0.0;            // a general section: f E (IY - IZ) / 2, per bond / l0
};

namespace beam_kernel {

// Bonds bend little: below these sizes the series are exact to round-off and skip the
// transcendental calls that would otherwise dominate the bond's cost.
const double SMALL_SIN2 = 0.05 * 0.05;
const double SMALL_TAN2 = 0.05 * 0.05;

template <typename T> struct V { T x, y, z; };

template <typename T> inline V<T> mul(const T *r, const T *v)
{
  return { r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[3] * v[0] + r[4] * v[1] + r[5] * v[2],
           r[6] * v[0] + r[7] * v[1] + r[8] * v[2] };
}
template <typename T> inline V<T> cross(const V<T> &a, const V<T> &b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
template <typename T> inline T dot(const V<T> &a, const V<T> &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename T> inline V<T> scale(T a, const V<T> &x) { return { a * x.x, a * x.y, a * x.z }; }
// a x + b y
template <typename T> inline V<T> lin(T a, const V<T> &x, T b, const V<T> &y)
{
  return { a * x.x + b * y.x, a * x.y + b * y.y, a * x.z + b * y.z };
}

inline double root(double a) { return std::sqrt(a); }
inline Lanes root(Lanes a) { return Lanes{ std::sqrt(a[0]), std::sqrt(a[1]) }; }
inline double larger(double a, double b) { return a > b ? a : b; }
inline Lanes larger(Lanes a, Lanes b) { return Lanes{ a[0] > b[0] ? a[0] : b[0], a[1] > b[1] ? a[1] : b[1] }; }
inline double magnitude(double a) { return std::fabs(a); }
inline Lanes magnitude(Lanes a) { return Lanes{ std::fabs(a[0]), std::fabs(a[1]) }; }
// a comparison is true in every lane (one bond: bool & bool is an int)
inline bool all(int m) { return m != 0; }
template <typename M> inline bool all(M m) { return m[0] && m[1]; }

// The exact forms, outside the series: one bond only (a pair falls back to single bonds).
// f = angle / sin(angle) and g = (cos(angle) - f) / sin^2(angle) from s2 = sin^2, co = cos.
inline bool exact_bend(double s2, double co, double &f, double &g)
{
  const double s = std::sqrt(s2);
  if (s < 1e-300) {  // a half turn (co < 0): the rotation axis is undefined; no moment
    f = g = 0.0;
    return true;
  }
  f = std::atan2(s, co) / s;
  g = (co - f) / s2;
  return true;
}
inline bool exact_bend(Lanes, Lanes, Lanes &, Lanes &) { return false; }
inline bool exact_angle(double y, double x, double &phi) { phi = std::atan2(y, x); return true; }
inline bool exact_angle(Lanes, Lanes, Lanes &) { return false; }

// phi = atan2(y, x), by its series when the angle is small
template <typename T> inline bool angle(T y, T x, T &phi)
{
  if (all((x > 0.0) & (y * y < SMALL_TAN2 * (x * x)))) {
    const T r = y / x, r2 = r * r;
    phi = r * (1.0 - r2 * (1.0 / 3 - r2 * (1.0 / 5 - r2 * (1.0 / 7 - r2 * (1.0 / 9)))));
    return true;
  }
  return exact_angle(y, x, phi);
}

// One end of a bond bent from the chord direction e to its material direction r (unit vectors):
// c = e x r, co = e.r, the rotation vector theta = f c of the smallest rotation taking e onto r,
// f = angle / sin(angle), and g = (co - f) / |c|^2, which the exact derivative of theta needs
// (series at small angles: asin(s)/s and sqrt(1 - s^2) expanded to s^8, exact otherwise).
template <typename T> struct Bend { V<T> c; T co, f, g; };
template <typename T> inline bool bend(const V<T> &e, const V<T> &r, Bend<T> &b)
{
  b.c = cross(e, r);
  b.co = dot(e, r);
  const T s2 = dot(b.c, b.c);
  if (all((b.co > 0.0) & (s2 < SMALL_SIN2))) {
    b.f = 1.0 + s2 * (1.0 / 6 + s2 * (3.0 / 40 + s2 * (5.0 / 112 + s2 * (35.0 / 1152))));
    b.g = -(2.0 / 3) - s2 * (1.0 / 5 + s2 * (3.0 / 28 + s2 * (5.0 / 72 + s2 * (35.0 / 704))));
    return true;
  }
  return exact_bend(s2, b.co, b.f, b.g);
}

// Beyond a quarter turn (one end bent more than 90 degrees from the chord, or twisted more than
// 90 degrees), which no element of a net carries in earnest but a torn rope's whipping free end
// reaches, the law is regularised so that its energy stays smooth through the half turn, where
// an end's theta (or phi) is undefined and flips as the end passes it. Before, theta_i.theta_j
// jumped there and the energy with it: an end spun through half turns gained 113 % of its
// energy in 0.2 s, whatever the step (the 500 kJ fences' open budgets, doc/fence.md).
//  - each end's own energy kp theta^2 / 2 becomes kp g(theta), g(a) = a^2 / 2 up to a quarter
//    turn, then the parabola with g' = pi - a: C1, its largest value pi^2 / 4 at the half turn
//    with zero slope (the moment fades to 0 there instead of flipping from kp pi to -kp pi);
//  - the ends' coupling X = th_i.(km th_j) is weighted by W = w_i w_j, w = 1 up to a quarter
//    turn and sin^4(angle) beyond it (C1, 0 with zero slope at the half turn).
// Below a quarter turn every end is exactly the law it was. h = g'(a) / a scales an end's own
// moment; a = (dW/d|th|) / |th|, so that dE/dth_i = kp h_i th_i + W km th_j + X a_i th_i;
// extra = the energy the quadratic form (m_i.th_i + m_j.th_j) / 2 misses, kp (g - h a^2 / 2).
// A pair of bonds exists only where both took the small-angle series (co > 0): nothing beyond.
template <typename T> struct Beyond { T W, ai, aj, hi, hj, extra; };

// g(a) and h = g'(a) / a of an angle a >= 0
inline void soften(double a, double &g, double &h)
{
  const double q = 0.5 * M_PI, u = a - q;
  if (u <= 0.0) { g = 0.5 * a * a; h = 1.0; return; }
  g = 0.5 * q * q + q * u - 0.5 * u * u;
  h = (M_PI - a) / a;
}
inline void beyond(const Bend<Lanes> &, const Bend<Lanes> &, Lanes, Beyond<Lanes> &z)
{
  z.W = z.hi = z.hj = Lanes{ 1.0, 1.0 };
  z.ai = z.aj = z.extra = Lanes{ 0.0, 0.0 };
}
inline void beyond(const Bend<double> &bi, const Bend<double> &bj, double kp, Beyond<double> &z)
{
  z.W = z.hi = z.hj = 1.0;
  z.ai = z.aj = z.extra = 0.0;
  if (bi.co >= 0.0 && bj.co >= 0.0) return;
  // w = sin^4 = (s^2)^2 and dw/dangle / angle = 4 s^3 co / (f s) = 4 s^2 co / f (theta = f c)
  const double si = dot(bi.c, bi.c), sj = dot(bj.c, bj.c);
  const double wi = bi.co >= 0.0 ? 1.0 : si * si, wj = bj.co >= 0.0 ? 1.0 : sj * sj;
  const double di = bi.co >= 0.0 || bi.f == 0.0 ? 0.0 : 4.0 * si * bi.co / bi.f;
  const double dj = bj.co >= 0.0 || bj.f == 0.0 ? 0.0 : 4.0 * sj * bj.co / bj.f;
  z.W = wi * wj;
  z.ai = di * wj;
  z.aj = dj * wi;
  // the ends' angles: |theta| = f s (f = 0 only at an exact half turn)
  const double ti = bi.f == 0.0 ? M_PI : bi.f * std::sqrt(si), tj = bj.f == 0.0 ? M_PI : bj.f * std::sqrt(sj);
  double gi, gj;
  soften(ti, gi, z.hi);
  soften(tj, gj, z.hj);
  z.extra = kp * (gi - 0.5 * z.hi * ti * ti + gj - 0.5 * z.hj * tj * tj);
}

// The twist's fade where an end's reference normal turns towards the chord: psi(rho) = 1 for
// rho >= 1/4, the smoothstep u^2 (3 - 2 u) of u = 4 rho below (C1, 0 with zero slope at rho = 0);
// dpsi = dpsi/drho. A pair of bonds bends less than the series' 3 degrees: rho is near 1 there.
inline void fade_twist(Lanes, Lanes &psi, Lanes &dpsi)
{
  psi = Lanes{ 1.0, 1.0 };
  dpsi = Lanes{ 0.0, 0.0 };
}
inline void fade_twist(double rho, double &psi, double &dpsi)
{
  const double u = 4.0 * rho;
  psi = u >= 1.0 ? 1.0 : u * u * (3.0 - 2.0 * u);
  dpsi = u >= 1.0 ? 0.0 : 24.0 * u * (1.0 - u);
}
// The twist's energy kt g(|phi|) (soften(); a pair twists little): g and the moment's factor h
inline void soften_twist(Lanes phi, Lanes &g, Lanes &h)
{
  g = 0.5 * phi * phi;
  h = Lanes{ 1.0, 1.0 };
}
inline void soften_twist(double phi, double &g, double &h) { soften(std::fabs(phi), g, h); }

// The bending energy's gradient through one end (moment m = dE/dtheta of that end): adds
// dE/de to ge and returns the torque -r x dE/dr on the end's node. With theta = f c:
// dE = G.dc + h d(co), G = f m + g (m.c) c, h = -(m.c), dc = de x r + e x dr, d(co) = r.de + e.dr.
template <typename T>
inline V<T> bend_gradient(const V<T> &e, const V<T> &r, const Bend<T> &b, const V<T> &m, V<T> &ge)
{
  const T mc = dot(m, b.c);
  const V<T> G = lin(b.f, m, b.g * mc, b.c);
  const V<T> rG = cross(r, G);
  ge = { ge.x + rG.x - mc * r.x, ge.y + rG.y - mc * r.y, ge.z + rG.z - mc * r.z };
  const T rg = dot(r, G);
  return { -b.co * G.x + rg * e.x - mc * b.c.x, -b.co * G.y + rg * e.y - mc * b.c.y,
           -b.co * G.z + rg * e.z - mc * b.c.z };
}

}  // namespace beam_kernel

template <bool REPORT, bool STRESS, typename T>
inline __attribute__((always_inline)) bool BeamLaw::load(const BeamConst<T> &b, const BeamNodes<T> &n,
                                                         BeamLoad<T> &out)
{
  return kernel<REPORT, STRESS, false>(b, static_cast<const BeamSection<T> *>(nullptr), n, out);
}

template <bool REPORT, bool STRESS, typename T>
inline __attribute__((always_inline)) bool BeamLaw::load_section(const BeamConst<T> &b, const BeamSection<T> &s,
                                                                 const BeamNodes<T> &n, BeamLoad<T> &out)
{
  return kernel<REPORT, STRESS, true>(b, &s, n, out);
}

// always_inline: GCC would call it, and the loop would pay for the call and the result's trip
// through memory. SECTION false is the circular section, exactly as before general sections.
template <bool REPORT, bool STRESS, bool SECTION, typename T>
inline __attribute__((always_inline)) bool BeamLaw::kernel(const BeamConst<T> &b, const BeamSection<T> *s,
                                                           const BeamNodes<T> &n, BeamLoad<T> &out)
{
  using namespace beam_kernel;
  const V<T> d = { n.xj[0] - n.xi[0], n.xj[1] - n.xi[1], n.xj[2] - n.xi[2] };
  const T L = root(dot(d, d)), inv_L = 1.0 / L;
  const V<T> e = { d.x * inv_L, d.y * inv_L, d.z * inv_L };

  // The law is the exact gradient of its energy E = ka (L - l0)^2 / 2 + (theta_i.m_i +
  // theta_j.m_j) / 2 + kt phi^2 / 2 (forces -dE/dx, torques -dE/dphi; m with the ends' coupling
  // faded beyond a quarter turn), so that it conserves energy at any bending and twist; at small
  // angles it is the linear corotational beam.
  // end rotations relative to the chord
  const V<T> ri = mul(n.ri, b.di), rj = mul(n.rj, b.dj);
  Bend<T> bi, bj;
  if (!bend(e, ri, bi) || !bend(e, rj, bj)) return false;
  const V<T> th_i = scale(bi.f, bi.c), th_j = scale(bj.f, bj.c);
  // twist: angle about e between the ends' reference normals projected on the plane normal to
  // e; the projection leaves their triple product with e unchanged and turns their dot product
  // into ni.nj - (e.ni)(e.nj), so the projected vectors are never formed
  const V<T> ni = mul(n.ri, b.pi), nj = mul(n.rj, b.pj);
  const V<T> nixnj = cross(ni, nj);
  const T eni = dot(e, ni), enj = dot(e, nj), ninj = dot(ni, nj);
  const T ty = dot(e, nixnj), tx = ninj - eni * enj;
  T phi;
  if (!angle(ty, tx, phi)) return false;

  // bending moments Kb (th_i - th_j) + Cs (th_i + th_j) at both ends, regularised beyond a
  // quarter turn (beyond())
  Beyond<T> far;
  beyond(bi, bj, b.kp, far);
  const T kmW = b.km * far.W;
  V<T> m_i = lin(b.kp * far.hi, th_i, kmW, th_j), m_j = lin(b.kp * far.hj, th_j, kmW, th_i);
  T X = b.km * dot(th_i, th_j);  // the coupling energy before the fade
  V<T> ge = { T{}, T{}, T{} };  // dE/de
  V<T> tq_i = { T{}, T{}, T{} }, tq_j = tq_i;
  if constexpr (SECTION) {
    // principal axis y: the two ends' reference normals (the record's `orient`), averaged and
    // made normal to the chord; z = e x y. The rotation vectors are normal to e, so
    // D v = y (y.v) - z (z.v) splits them into the two axes' parts.
    const V<T> a = { ni.x + nj.x, ni.y + nj.y, ni.z + nj.z };
    const T ae = dot(a, e);
    const V<T> u = { a.x - ae * e.x, a.y - ae * e.y, a.z - ae * e.z };
    const T inv_u = 1.0 / root(dot(u, u));
    const V<T> y = { u.x * inv_u, u.y * inv_u, u.z * inv_u };
    const V<T> z = cross(e, y);
    const T yi = dot(y, th_i), yj = dot(y, th_j);
    const V<T> di = lin(yi, y, -dot(z, th_i), z);
    const V<T> dj = lin(yj, y, -dot(z, th_j), z);
    const T kmdW = s->kmd * far.W;
    X = X + s->kmd * dot(th_i, dj);
    const V<T> ci = lin(s->kpd, di, kmdW, dj), cj = lin(s->kpd, dj, kmdW, di);
    m_i = { m_i.x + ci.x, m_i.y + ci.y, m_i.z + ci.z };
    m_j = { m_j.x + cj.x, m_j.y + cj.y, m_j.z + cj.z };
    // the energy's dependence on y = P a / |P a|: dE/dy = q, its part normal to y over |P a| is
    // p; dE = p.(dni + dnj) - (e.a) p.de (p is normal to e)
    const T qi = 2.0 * (s->kpd * yi + kmdW * yj), qj = 2.0 * (s->kpd * yj + kmdW * yi);
    V<T> q = lin(qi, th_i, qj, th_j);
    const T qy = dot(q, y);
    const V<T> p = { (q.x - qy * y.x) * inv_u, (q.y - qy * y.y) * inv_u, (q.z - qy * y.z) * inv_u };
    ge = scale(-ae, p);
    tq_i = cross(p, ni);
    tq_j = cross(p, nj);
  }
  // the bending energy: half moments times rotations (a quadratic form below a quarter turn)
  const T e_bend = 0.5 * (dot(m_i, th_i) + dot(m_j, th_j)) + far.extra;
  // the fade's own gradient (zero below a quarter turn, and always in a pair of bonds)
  if constexpr (std::is_same<T, double>::value) {
    if (far.ai != 0.0 || far.aj != 0.0) {
      m_i = lin(1.0, m_i, X * far.ai, th_i);
      m_j = lin(1.0, m_j, X * far.aj, th_j);
    }
  }
  const V<T> bi_t = bend_gradient(e, ri, bi, m_i, ge), bj_t = bend_gradient(e, rj, bj, m_j, ge);
  // twist: dE = tw dphi, dphi = (tx dty - ty dtx) / (tx^2 + ty^2)
  // The twist fades where an end's reference normal turns towards the chord (rho = tx^2 + ty^2
  // = |P ni|^2 |P nj|^2 below 1/4, a bend beyond 60 degrees about an axis across the normal):
  // at rho = 0 phi is undefined and jumped, and the twist energy with it (fade_twist()); beyond
  // a quarter turn of twist its energy is softened as an end's bending (soften_twist()).
  T psi, dpsi, gt, ht;
  fade_twist(tx * tx + ty * ty, psi, dpsi);
  soften_twist(phi, gt, ht);
  const T tw = psi * b.kt * ht * phi;  // the twist moment: energy psi kt g(|phi|)
  {
    // dE = tw dphi + kt g psi' drho, dphi = (tx dty - ty dtx) / rho, drho = 2 (tx dtx
    // + ty dty): dE = wx dty - wy dtx (the floor keeps rho = 0 finite where psi is 0 anyway)
    const T w = tw / larger(tx * tx + ty * ty, T{} + 1e-24);
    T wx = w * tx, wy = w * ty;
    if constexpr (std::is_same<T, double>::value) {
      if (dpsi != 0.0) {  // the fade's own gradient (never in a pair of bonds)
        const double k = 2.0 * b.kt * gt * dpsi;
        wx += k * ty;
        wy -= k * tx;
      }
    }
    // dE/de, dE/dni, dE/dnj of the twist; torques -n x dE/dn
    ge = { ge.x + wx * nixnj.x + wy * (enj * ni.x + eni * nj.x), ge.y + wx * nixnj.y + wy * (enj * ni.y + eni * nj.y),
           ge.z + wx * nixnj.z + wy * (enj * ni.z + eni * nj.z) };
    const V<T> nixe = cross(ni, e), njxe = cross(nj, e);
    // ni x dE/dni = wx (nj (ni.e) - e (ni.nj)) - wy (ni x nj - (e.nj) ni x e)
    tq_i = { tq_i.x - (wx * (eni * nj.x - ninj * e.x) - wy * (nixnj.x - enj * nixe.x)),
             tq_i.y - (wx * (eni * nj.y - ninj * e.y) - wy * (nixnj.y - enj * nixe.y)),
             tq_i.z - (wx * (eni * nj.z - ninj * e.z) - wy * (nixnj.z - enj * nixe.z)) };
    // nj x dE/dnj = wx (e (ni.nj) - ni (e.nj)) - wy (nj x ni - (e.ni) nj x e)
    tq_j = { tq_j.x - (wx * (ninj * e.x - enj * ni.x) - wy * (-nixnj.x - eni * njxe.x)),
             tq_j.y - (wx * (ninj * e.y - enj * ni.y) - wy * (-nixnj.y - eni * njxe.y)),
             tq_j.z - (wx * (ninj * e.z - enj * ni.z) - wy * (-nixnj.z - eni * njxe.z)) };
  }
  const T axial = b.ka * (L - b.l0);
  // force on i: axial e + (dE/de normal to e) / L (de/dx_i = -(I - e e^T) / L)
  const T gee = dot(ge, e);
  const V<T> sh = { (ge.x - gee * e.x) * inv_L, (ge.y - gee * e.y) * inv_L, (ge.z - gee * e.z) * inv_L };

  out.force_i[0] = axial * e.x + sh.x;
  out.force_i[1] = axial * e.y + sh.y;
  out.force_i[2] = axial * e.z + sh.z;
  out.torque_i[0] = bi_t.x + tq_i.x;
  out.torque_i[1] = bi_t.y + tq_i.y;
  out.torque_i[2] = bi_t.z + tq_i.z;
  out.torque_j[0] = bj_t.x + tq_j.x;
  out.torque_j[1] = bj_t.y + tq_j.y;
  out.torque_j[2] = bj_t.z + tq_j.z;
  out.axial = axial;
  if constexpr (REPORT || STRESS) {
    // parallel-bond stresses: the largest tensile fibre stress F_n/A + |M_b| R/I (compression
    // lowers it) and the largest shear stress |F_s|/A + |M_t| R/J, each over its strength; the
    // bending moment is the larger of the two end moments
    const T shear = root(dot(sh, sh));
    const T moment = root(larger(dot(m_i, m_i), dot(m_j, m_j)));
    out.fail = larger(axial * b.sa + moment * b.sm, shear * b.ss + magnitude(tw) * b.st);
    if constexpr (REPORT) {
      out.shear = shear;
      out.moment = moment;
    }
  }
  if constexpr (REPORT) {
    // half the generalised forces times their displacements
    out.energy = 0.5 * axial * (L - b.l0) + psi * b.kt * gt + e_bend;
  }
  return true;
}

inline void BeamLaw::damp(double ca, double cs, double cb, double ct, const double *xi, const double *xj,
                          const double *vi, const double *vj, const double *wi, const double *wj,
                          double *f, double *ti, double *tj)
{
  double e[3] = { xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2] };
  const double L = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  for (int c = 0; c < 3; c++) f[c] = ti[c] = tj[c] = 0.0;
  if (!(L > 0.0)) return;
  for (int c = 0; c < 3; c++) e[c] /= L;
  // relative velocity of the two bond ends at the bond's centre: dv - (L/2) (wi + wj) x e
  const double h = 0.5 * L;
  const double ws[3] = { wi[0] + wj[0], wi[1] + wj[1], wi[2] + wj[2] };
  const double wxe[3] = { ws[1] * e[2] - ws[2] * e[1], ws[2] * e[0] - ws[0] * e[2], ws[0] * e[1] - ws[1] * e[0] };
  double vc[3];
  for (int c = 0; c < 3; c++) vc[c] = vj[c] - vi[c] - h * wxe[c];
  const double vn = vc[0] * e[0] + vc[1] * e[1] + vc[2] * e[2];  // = (vj - vi).e
  const double wr[3] = { wj[0] - wi[0], wj[1] - wi[1], wj[2] - wi[2] };
  const double wn = wr[0] * e[0] + wr[1] * e[1] + wr[2] * e[2];
  double m[3];
  for (int c = 0; c < 3; c++) {
    const double vs = vc[c] - vn * e[c];  // shear part of the end velocity
    const double wb = wr[c] - wn * e[c];  // bending part of the relative rotation rate
    f[c] = ca * vn * e[c] + cs * vs;      // on i, at the centre of the bond
    m[c] = cb * wb + ct * wn * e[c];      // relative rotation: +m on i, -m on j
  }
  // the shear force acts at the centre: the same couple (L/2) e x f on both nodes
  const double exf[3] = { h * (e[1] * f[2] - e[2] * f[1]), h * (e[2] * f[0] - e[0] * f[2]),
                          h * (e[0] * f[1] - e[1] * f[0]) };
  for (int c = 0; c < 3; c++) {
    ti[c] = m[c] + exf[c];
    tj[c] = exf[c] - m[c];
  }
}

}  // namespace WireNet

#endif
