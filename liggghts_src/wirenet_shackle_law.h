/* WireNet: shackle law, a node held on a rope by a shackle (clip, post-head saddle) that slides
   along the rope with Coulomb friction (issue #18, the fence's net-to-rope connection).
   No LIGGGHTS dependency: the fix wirenet/shackle gathers the atoms, this class finds the point
   of the rope polyline the shackle sits at and returns the force; see doc/fix_wirenet_shackle.md.

   Geometry: the rope is the polyline R_0 .. R_{n-1} (n >= 2 atoms, n - 1 segments). A shackle S
   keeps the index k of its segment (R_k, R_k+1) as history; each step locate() walks from k to the
   segment of the closest point P = R_k + s (R_k+1 - R_k), s in [0, 1]:
     - s > 1 moves on to segment k+1 (s < 0 back to k-1) while the closest point lies there; a
       convex vertex (s > 1 on k and s < 0 on k+1) clamps P to the vertex, on segment k;
     - at the rope's ends P is clamped to the end atom: the shackle stops there.
   Force on S (the rope atoms get -(1-s) F on R_k and -s F on R_k+1):
     normal   F_n = -kn d, d = S - P (perpendicular to the segment inside it; at a clamped vertex
              or end the whole offset, whose component along the rope is the end stop)
              - c v_perp with c = 2 zeta sqrt(kn m_S) (optional viscous damping of the relative
              velocity across the rope)
     tangent  xi += (v_S - v_P).t dt, F_t = -kt xi t, |kt xi| <= mu kn |d| (Coulomb, on the elastic
              normal force); when capped xi is set back to the cap and the slip work
              mu kn |d| |dxi| is dissipated. */

#ifndef WIRENET_SHACKLE_LAW_H
#define WIRENET_SHACKLE_LAW_H

#include <Eigen/Dense>

namespace WireNet {

struct ShackleLawParams {
  double kn = 0.0;       // `kn` [N/m]: holding stiffness across the rope; > 0
  double kt = 0.0;       // `kt` [N/m]: tangential (stick) stiffness; > 0
  double mu = 0.0;       // `mu`: Coulomb friction coefficient; >= 0
  double damping = 0.0;  // `damping ZETA`: viscous damping across the rope, fraction of critical; >= 0
};

// Where a shackle sits on its rope.
struct ShackleLocation {
  int seg = 0;           // segment index k: between rope atoms k and k+1
  double s = 0.0;        // P = R_k + s (R_k+1 - R_k), s in [0, 1]
  int missing = -1;      // >= 0: the rope atom (index along the rope) that was needed and absent
};

// What one step of the law gives.
struct ShackleResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // on S; -(1-s) F on R_k, -s F on R_k+1
  double xi = 0.0;            // tangential elastic displacement after the step [m]
  double slip_work = 0.0;     // friction work dissipated this step [J]
  double damping_work = 0.0;  // work dissipated by the normal damping this step [J]
  double elastic = 0.0;       // 0.5 kn |d|^2 + 0.5 kt xi^2 [J]
  bool sliding = false;       // the friction cap was reached
};

class ShackleLaw {
 public:
  // Throws std::invalid_argument with a one-line message naming the item and its value.
  explicit ShackleLaw(const ShackleLawParams &p);
  const ShackleLawParams &params() const { return p_; }

  // Parameter s of the point of segment (a, b) closest to x, unclamped (0 for a zero-length segment).
  static double param(const Eigen::Vector3d &x, const Eigen::Vector3d &a, const Eigen::Vector3d &b)
  {
    const Eigen::Vector3d e = b - a;
    const double ee = e.squaredNorm();
    return ee > 0.0 ? (x - a).dot(e) / ee : 0.0;
  }

  // Walks from segment seg (0 <= seg < n - 1) to the closest point of the rope to x. POS(m) gives a
  // pointer to rope atom m's 3 coordinates, or NULL if that atom is not available (then
  // .missing = m and the walk stops). At most n - 2 moves; the walk never turns back.
  template <class Pos>
  static ShackleLocation locate(const Eigen::Vector3d &x, int seg, int n, Pos pos)
  {
    ShackleLocation L;
    L.seg = seg;
    auto at = [&](int m, Eigen::Vector3d &r) -> bool {
      const double *p = pos(m);
      if (!p) { L.missing = m; return false; }
      r = Eigen::Vector3d(p[0], p[1], p[2]);
      return true;
    };
    Eigen::Vector3d a, b, c;
    if (!at(seg, a) || !at(seg + 1, b)) return L;
    double s = param(x, a, b);
    if (s > 1.0) {
      while (L.seg < n - 2) {
        if (!at(L.seg + 2, c)) return L;
        const double s2 = param(x, b, c);
        if (s2 < 0.0) break;            // convex vertex: stays at R_k+1
        L.seg++;
        s = s2;
        a = b;
        b = c;
        if (s2 <= 1.0) break;
      }
    } else if (s < 0.0) {
      while (L.seg > 0) {
        if (!at(L.seg - 1, c)) return L;
        const double s2 = param(x, c, a);
        if (s2 > 1.0) break;            // convex vertex: stays at R_k
        L.seg--;
        s = s2;
        b = a;
        a = c;
        if (s2 >= 0.0) break;
      }
    }
    L.s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
    return L;
  }

  // One step. x/v/m: the shackle's position, velocity, mass; a, b, va, vb: the segment's ends and
  // their velocities; s: the location on it; xi: the tangential history; dt: the time step, or 0 to
  // evaluate the force without moving the history (LIGGGHTS' setup pass): then the force is capped
  // but neither xi nor the slip work changes.
  ShackleResult step(const Eigen::Vector3d &x, const Eigen::Vector3d &v, double m,
                     const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                     const Eigen::Vector3d &va, const Eigen::Vector3d &vb,
                     double s, double xi, double dt) const;

 private:
  ShackleLawParams p_;
};

}  // namespace WireNet

#endif
