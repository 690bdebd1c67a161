/* WireNet: analytic body shapes. See wirenet_body_shapes.h and doc/fix_wirenet_body.md. */

#include "wirenet_body_shapes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <stdexcept>

namespace WireNet {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

// shortest text that reads back as v
std::string num(double v)
{
  char buf[64];
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (strtod(buf, NULL) == v) break;
  }
  return buf;
}

void require_positive(double v, const std::string &what)
{
  if (!(v > 0.0) || !std::isfinite(v))
    throw std::invalid_argument(what + " must be a finite number > 0 (got " + num(v) + ")");
}

// Upper bound of Eberly's bisection: enough halvings to reach any double from any other.
const int MAX_BISECTION = std::numeric_limits<double>::digits - std::numeric_limits<double>::min_exponent;

double robust_length(double a, double b)
{
  const double m = std::max(std::fabs(a), std::fabs(b));
  if (m == 0.0) return 0.0;
  const double x = a / m, y = b / m;
  return m * std::sqrt(x * x + y * y);
}

double robust_length(double a, double b, double c)
{
  const double m = std::max(std::fabs(a), std::max(std::fabs(b), std::fabs(c)));
  if (m == 0.0) return 0.0;
  const double x = a / m, y = b / m, z = c / m;
  return m * std::sqrt(x * x + y * y + z * z);
}

// Root s of F(s) = sum_k (n_k / (s + r_k))^2 - 1 (k < m, r_{m-1} = 1) on Eberly's bracket.
// F is convex and decreasing for s > -1; every term alone bounds the root from below
// (s >= |n_k| - r_k), so Newton's method started at the largest of these bounds, where F >= 0,
// climbs monotonically to the root (quadratically near it) and stops when a step makes no
// progress. A step beyond the upper end of the bracket falls back to bisection; if Newton has
// not converged after 100 steps, Eberly's bisection finishes the job (it cannot fail).
template <int M>
double root(const double *r, const double *n, double s0, double s1)
{
  double lo = s0;
  for (int k = 0; k < M; k++) lo = std::max(lo, std::fabs(n[k]) - r[k]);
  double s = lo;
  for (int it = 0; it < 100; it++) {
    double f = -1.0, df = 0.0;
    for (int k = 0; k < M; k++) {
      const double q = n[k] / (s + r[k]);
      f += q * q;
      df -= 2.0 * q * q / (s + r[k]);
    }
    if (f == 0.0) return s;
    const double next = s - f / df;
    // converged: no progress beyond round-off (s + 1 > 0 is the scale of every s + r_k)
    if (!(next - s > 4.0 * std::numeric_limits<double>::epsilon() * (s + 1.0))) return next > s ? next : s;
    s = next < s1 ? next : 0.5 * (s + s1);
  }
  s0 = lo;
  for (int i = 0; i < MAX_BISECTION; i++) {
    s = 0.5 * (s0 + s1);
    if (s == s0 || s == s1) break;
    double g = -1.0;
    for (int k = 0; k < M; k++) {
      const double q = n[k] / (s + r[k]);
      g += q * q;
    }
    if (g > 0.0) s0 = s;
    else if (g < 0.0) s1 = s;
    else break;
  }
  return s;
}

// Eberly's GetRoot in 2-D: (r0 z0/(s + r0))^2 + (z1/(s + 1))^2 = 1.
double root2(double r0, double z0, double z1, double g)
{
  const double r[2] = { r0, 1.0 }, n[2] = { r0 * z0, z1 };
  return root<2>(r, n, z1 - 1.0, g < 0.0 ? 0.0 : robust_length(n[0], z1) - 1.0);
}

// The same in 3-D.
double root3(double r0, double r1, double z0, double z1, double z2, double g)
{
  const double r[3] = { r0, r1, 1.0 }, n[3] = { r0 * z0, r1 * z1, z2 };
  return root<3>(r, n, z2 - 1.0, g < 0.0 ? 0.0 : robust_length(n[0], n[1], z2) - 1.0);
}

// Nearest point of the segment [a, b] to p (2-D or 3-D).
template <class V>
V segment_point(const V &a, const V &b, const V &p)
{
  const V d = b - a;
  const double dd = d.squaredNorm();
  if (dd == 0.0) return a;
  const double t = std::min(1.0, std::max(0.0, d.dot(p - a) / dd));
  return a + t * d;
}

}

// ---- sphere -------------------------------------------------------------------------------

SphereShape::SphereShape(double radius) : r_(radius) { require_positive(radius, "sphere radius"); }

void SphereShape::query(const Vector3d &p, SurfacePoint &out) const
{
  const double d = p.norm();
  out.normal = d > 0.0 ? Vector3d(p / d) : Vector3d::UnitZ();
  out.point = r_ * out.normal;
  out.dist = d - r_;
}

bool SphereShape::unit_inertia(Matrix3d &I) const
{
  I = 0.4 * r_ * r_ * Matrix3d::Identity();
  return true;
}

// ---- ellipsoid ----------------------------------------------------------------------------

EllipsoidShape::EllipsoidShape(double a, double b, double c)
{
  require_positive(a, "spheroid semi-axis a");
  require_positive(b, "spheroid semi-axis b");
  require_positive(c, "spheroid semi-axis c");
  axes_[0] = a; axes_[1] = b; axes_[2] = c;
  perm_[0] = 0; perm_[1] = 1; perm_[2] = 2;
  std::stable_sort(perm_, perm_ + 3, [this](int i, int j) { return axes_[i] > axes_[j]; });
  for (int k = 0; k < 3; k++) e_[k] = axes_[perm_[k]];
  sphere_ = a == b && b == c;
}

bool EllipsoidShape::unit_inertia(Matrix3d &I) const
{
  const double a2 = axes_[0] * axes_[0], b2 = axes_[1] * axes_[1], c2 = axes_[2] * axes_[2];
  I = Matrix3d::Zero();
  I(0, 0) = 0.2 * (b2 + c2);
  I(1, 1) = 0.2 * (a2 + c2);
  I(2, 2) = 0.2 * (a2 + b2);
  return true;
}

// the maximum of u . x on x^T A^-2 x = 1 (A = diag(a, b, c)) is at x = A^2 u / |A u|
bool EllipsoidShape::support(const Vector3d &u, Vector3d &p) const
{
  const Vector3d a(axes_[0], axes_[1], axes_[2]);
  const Vector3d au = a.cwiseProduct(u);
  p = a.cwiseProduct(au) / au.norm();
  return true;
}

double EllipsoidShape::distance_sorted_2d(double e0, double e1, double y0, double y1, double &x0, double &x1)
{
  if (y1 > 0.0) {
    if (y0 > 0.0) {
      const double z0 = y0 / e0, z1 = y1 / e1, g = z0 * z0 + z1 * z1 - 1.0;
      if (g != 0.0) {
        const double r0 = (e0 / e1) * (e0 / e1);
        const double s = root2(r0, z0, z1, g);
        x0 = r0 * y0 / (s + r0);
        x1 = y1 / (s + 1.0);
        return robust_length(x0 - y0, x1 - y1);
      }
      x0 = y0; x1 = y1;
      return 0.0;
    }
    x0 = 0.0; x1 = e1;
    return std::fabs(y1 - e1);
  }
  const double numer0 = e0 * y0, denom0 = e0 * e0 - e1 * e1;
  if (numer0 < denom0) {
    const double xde0 = numer0 / denom0;
    x0 = e0 * xde0;
    x1 = e1 * std::sqrt(std::max(0.0, 1.0 - xde0 * xde0));
    return robust_length(x0 - y0, x1);
  }
  x0 = e0; x1 = 0.0;
  return std::fabs(y0 - e0);
}

double EllipsoidShape::distance_sorted(const double e[3], const double y[3], double x[3])
{
  if (y[2] > 0.0) {
    if (y[1] > 0.0) {
      if (y[0] > 0.0) {
        const double z0 = y[0] / e[0], z1 = y[1] / e[1], z2 = y[2] / e[2];
        const double g = z0 * z0 + z1 * z1 + z2 * z2 - 1.0;
        if (g != 0.0) {
          const double r0 = (e[0] / e[2]) * (e[0] / e[2]), r1 = (e[1] / e[2]) * (e[1] / e[2]);
          const double s = root3(r0, r1, z0, z1, z2, g);
          x[0] = r0 * y[0] / (s + r0);
          x[1] = r1 * y[1] / (s + r1);
          x[2] = y[2] / (s + 1.0);
          return robust_length(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
        }
        x[0] = y[0]; x[1] = y[1]; x[2] = y[2];
        return 0.0;
      }
      x[0] = 0.0;
      return distance_sorted_2d(e[1], e[2], y[1], y[2], x[1], x[2]);
    }
    if (y[0] > 0.0) {
      x[1] = 0.0;
      return distance_sorted_2d(e[0], e[2], y[0], y[2], x[0], x[2]);
    }
    x[0] = 0.0; x[1] = 0.0; x[2] = e[2];
    return std::fabs(y[2] - e[2]);
  }
  const double denom0 = e[0] * e[0] - e[2] * e[2], denom1 = e[1] * e[1] - e[2] * e[2];
  const double numer0 = e[0] * y[0], numer1 = e[1] * y[1];
  if (numer0 < denom0 && numer1 < denom1) {
    const double xde0 = numer0 / denom0, xde1 = numer1 / denom1;
    const double discr = 1.0 - xde0 * xde0 - xde1 * xde1;
    if (discr > 0.0) {
      x[0] = e[0] * xde0;
      x[1] = e[1] * xde1;
      x[2] = e[2] * std::sqrt(discr);
      return robust_length(x[0] - y[0], x[1] - y[1], x[2]);
    }
  }
  x[2] = 0.0;
  return distance_sorted_2d(e[0], e[1], y[0], y[1], x[0], x[1]);
}

double EllipsoidShape::distance_bound(const Vector3d &p) const
{
  double g = 0.0;
  for (int j = 0; j < 3; j++) g += (p[j] / axes_[j]) * (p[j] / axes_[j]);
  return g > 1.0 ? (std::sqrt(g) - 1.0) * e_[2] : -std::numeric_limits<double>::infinity();
}

void EllipsoidShape::query(const Vector3d &p, SurfacePoint &out) const
{
  if (sphere_) {   // YADE's punch sphere: the root search cost 7 % of that step
    const double d = p.norm();
    out.normal = d > 0.0 ? Vector3d(p / d) : Vector3d::UnitZ();
    out.point = e_[0] * out.normal;
    out.dist = d - e_[0];
    return;
  }
  double y[3], x[3];
  for (int k = 0; k < 3; k++) y[k] = std::fabs(p[perm_[k]]);
  const double d = distance_sorted(e_, y, x);
  double g = 0.0;
  for (int k = 0; k < 3; k++) {
    const int j = perm_[k];
    out.point[j] = std::copysign(x[k], p[j]);
    g += (p[j] / axes_[j]) * (p[j] / axes_[j]);
  }
  for (int j = 0; j < 3; j++) out.normal[j] = out.point[j] / (axes_[j] * axes_[j]);
  out.normal.normalize();
  out.dist = g < 1.0 ? -d : d;
}

// ---- cone ---------------------------------------------------------------------------------

ConeShape::ConeShape(double base_radius, double height, double tip_radius, bool round_tip) :
  R_(base_radius), h_(height), a_(tip_radius), round_(round_tip)
{
  require_positive(base_radius, "cone base radius");
  require_positive(height, "cone height");
  if (!(tip_radius >= 0.0 && tip_radius < base_radius) || !std::isfinite(tip_radius))
    throw std::invalid_argument("cone tip radius must be in [0, base radius) (got " + num(tip_radius) + ")");
  if (round_ && a_ > 0.0) {
    // flank normal n: n . (C - B) = -a with C = (0, h - a), B = (R, 0): R cos(phi) - (h - a) sin(phi) = a
    const double hh = h_ - a_, L = std::hypot(R_, hh), psi = std::atan2(hh, R_);
    if (!(hh > 0.0) || !(a_ < L)) throw std::invalid_argument("cone round tip radius must be < height (got " + num(a_) + ")");
    const double phi = std::acos(a_ / L) - psi;
    nf_ = Vector2d(std::cos(phi), std::sin(phi));
    T_ = Vector2d(0.0, hh) + a_ * nf_;
    if (!(T_[1] > 0.0) || !(nf_[1] > 0.0))
      throw std::invalid_argument("cone round tip radius " + num(a_) + " too large for base radius " + num(R_) +
                                  " and height " + num(h_) + " (the cap must meet the flank above the base)");
  } else {
    round_ = false;
    nf_ = Vector2d(h_, R_ - a_).normalized();
    T_ = Vector2d(a_, h_);
  }
  bound_ = std::max(R_, T_.norm());
  bound_ = std::max(bound_, h_);
}

// In the meridian half-plane (rho, z): base (0,0)-(R,0), flank (R,0)-T, then the flat tip
// T-(0,h) or the round cap (circle about C = (0, h - a) from T up to (0, h)).
void ConeShape::query(const Vector3d &p, SurfacePoint &out) const
{
  const double rho = std::hypot(p[0], p[1]);
  const Vector3d u = rho > 0.0 ? Vector3d(p[0] / rho, p[1] / rho, 0.0) : Vector3d::UnitX();
  const Vector2d q(rho, p[2]);
  const Vector2d B(R_, 0.0);
  // base and flank segments
  Vector2d c = segment_point(Vector2d(0.0, 0.0), B, q), n(0.0, -1.0);
  double d2 = (q - c).squaredNorm();
  {
    const Vector2d cs = segment_point(B, T_, q);
    const double ds = (q - cs).squaredNorm();
    if (ds < d2) { d2 = ds; c = cs; n = nf_; }
  }
  bool inside = q[1] >= 0.0 && nf_.dot(q - B) <= 0.0;
  if (!round_) {
    inside = inside && q[1] <= h_;
    if (a_ > 0.0) {
      const Vector2d cs = segment_point(T_, Vector2d(0.0, h_), q);
      const double ds = (q - cs).squaredNorm();
      if (ds < d2) { d2 = ds; c = cs; n = Vector2d(0.0, 1.0); }
    }
  } else {
    const Vector2d C(0.0, h_ - a_);
    const Vector2d r = q - C;
    const double rl = r.norm();
    if (q[1] > T_[1]) inside = inside && rl <= a_;
    // the cap: the arc from the direction of nf_ up to +z
    Vector2d dir = rl > 0.0 ? Vector2d(r / rl) : Vector2d(0.0, 1.0);
    if (dir.dot(Vector2d(1.0, 0.0)) < 0.0) dir = Vector2d(0.0, 1.0);          // behind the axis: the pole
    else if (nf_[0] * dir[1] - nf_[1] * dir[0] < 0.0) dir = nf_;              // below the tangent point
    const Vector2d cs = C + a_ * dir;
    const double ds = (q - cs).squaredNorm();
    if (ds < d2) { d2 = ds; c = cs; n = dir; }
  }
  const double d = std::sqrt(d2);
  if (!inside && d > 0.0) n = (q - c) / d;
  out.dist = inside ? -d : d;
  out.point = c[0] * u + Vector3d(0.0, 0.0, c[1]);
  out.normal = n[0] * u + Vector3d(0.0, 0.0, n[1]);
}

// ---- plane --------------------------------------------------------------------------------

void PlaneShape::query(const Vector3d &p, SurfacePoint &out) const
{
  out.dist = p[2];
  out.point = Vector3d(p[0], p[1], 0.0);
  out.normal = Vector3d::UnitZ();
}

double PlaneShape::bounding_radius() const { return std::numeric_limits<double>::infinity(); }

// ---- convex polyhedron --------------------------------------------------------------------

PolyhedronShape::PolyhedronShape(const std::vector<Vector3d> &vertices, const std::vector<std::vector<int> > &faces,
                                 const std::string &name) :
  v_(vertices), f_(faces), bound_(0.0), volume_(0.0), centroid_(Vector3d::Zero()),
  second_moment_(Matrix3d::Zero()), centred_(false), name_(name)
{
  const int nv = (int)v_.size();
  if (nv < 4 || f_.size() < 4)
    throw std::invalid_argument(name + ": a polyhedron needs at least 4 vertices and 4 faces (got " +
                                std::to_string(nv) + " and " + std::to_string(f_.size()) + ")");
  Vector3d mean = Vector3d::Zero();
  for (const Vector3d &v : v_) {
    if (!v.allFinite()) throw std::invalid_argument(name + ": vertex coordinates must be finite");
    mean += v;
    bound_ = std::max(bound_, v.norm());
  }
  mean /= nv;
  const double tol = 1e-9 * bound_;
  std::map<std::pair<int, int>, int> edge_use;
  for (size_t k = 0; k < f_.size(); k++) {
    std::vector<int> &loop = f_[k];
    if (loop.size() < 3) throw std::invalid_argument(name + ": face " + std::to_string(k + 1) + " has fewer than 3 vertices");
    for (int i : loop)
      if (i < 0 || i >= nv)
        throw std::invalid_argument(name + ": face " + std::to_string(k + 1) + " names vertex " + std::to_string(i + 1) +
                                    " of " + std::to_string(nv));
    Vector3d n = Vector3d::Zero();  // Newell
    for (size_t i = 0; i < loop.size(); i++) n += v_[loop[i]].cross(v_[loop[(i + 1) % loop.size()]]);
    if (!(n.norm() > tol * bound_))
      throw std::invalid_argument(name + ": face " + std::to_string(k + 1) + " has no area");
    n.normalize();
    if (n.dot(v_[loop[0]] - mean) < 0.0) {
      std::reverse(loop.begin(), loop.end());
      n = -n;
    }
    const double off = n.dot(v_[loop[0]]);
    for (int i : loop)
      if (std::fabs(n.dot(v_[i]) - off) > tol)
        throw std::invalid_argument(name + ": face " + std::to_string(k + 1) + " is not planar");
    for (int i = 0; i < nv; i++)
      if (n.dot(v_[i]) - off > tol)
        throw std::invalid_argument(name + ": not convex (vertex " + std::to_string(i + 1) + " lies outside the plane of face " +
                                    std::to_string(k + 1) + ")");
    normal_.push_back(n);
    offset_.push_back(off);
    for (size_t i = 0; i < loop.size(); i++) {
      int a = loop[i], b = loop[(i + 1) % loop.size()];
      if (a > b) std::swap(a, b);
      edge_use[std::make_pair(a, b)]++;
    }
    // tetrahedra (mean, fan triangle): volume, first and second moments
    for (size_t i = 1; i + 1 < loop.size(); i++) {
      const Vector3d p[4] = { mean, v_[loop[0]], v_[loop[i]], v_[loop[i + 1]] };
      const double vol = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6.0;
      const Vector3d s = p[0] + p[1] + p[2] + p[3];
      volume_ += vol;
      centroid_ += vol * s / 4.0;
      Matrix3d m = s * s.transpose();
      for (int j = 0; j < 4; j++) m += p[j] * p[j].transpose();
      second_moment_ += vol / 20.0 * m;
    }
  }
  for (const auto &e : edge_use)
    if (e.second != 2)
      throw std::invalid_argument(name + ": not closed (edge " + std::to_string(e.first.first + 1) + "-" +
                                  std::to_string(e.first.second + 1) + " belongs to " + std::to_string(e.second) + " face(s))");
  if (!(volume_ > 0.0)) throw std::invalid_argument(name + ": encloses no volume");
  // an OBJ file may repeat a vertex or list one on no face: neither may touch a floor
  std::vector<bool> used(nv, false);
  for (const std::vector<int> &loop : f_)
    for (int i : loop) used[i] = true;
  for (int i = 0; i < nv; i++)
    if (used[i] && std::find(corners_.begin(), corners_.end(), v_[i]) == corners_.end()) corners_.push_back(v_[i]);
  centroid_ /= volume_;
  second_moment_ /= volume_;
  centred_ = centroid_.norm() <= 1e-9 * bound_;
}

PolyhedronShape PolyhedronShape::box(double lx, double ly, double lz)
{
  require_positive(lx, "box lx");
  require_positive(ly, "box ly");
  require_positive(lz, "box lz");
  std::vector<Vector3d> v;
  for (int k = 0; k < 8; k++)
    v.push_back(Vector3d((k & 1 ? 0.5 : -0.5) * lx, (k & 2 ? 0.5 : -0.5) * ly, (k & 4 ? 0.5 : -0.5) * lz));
  const std::vector<std::vector<int> > f = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 },
                                             { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
  return PolyhedronShape(v, f, "box");
}

PolyhedronShape PolyhedronShape::truncated_cube(double side, double cut)
{
  require_positive(side, "truncated-cube side");
  if (!(cut > 0.0 && cut < 0.5 * side) || !std::isfinite(cut))
    throw std::invalid_argument("truncated-cube corner cut must be in (0, side/2) (got " + num(cut) + ")");
  const double h = 0.5 * side, k = h - cut;
  std::vector<Vector3d> v;
  std::vector<std::vector<int> > f;
  for (int sx : { -1, 1 })
    for (int sy : { -1, 1 })
      for (int sz : { -1, 1 }) {
        const int a = (int)v.size();
        v.push_back(Vector3d(sx * k, sy * h, sz * h));
        v.push_back(Vector3d(sx * h, sy * k, sz * h));
        v.push_back(Vector3d(sx * h, sy * h, sz * k));
        f.push_back({ a, a + 1, a + 2 });
      }
  for (int axis = 0; axis < 3; axis++)
    for (int s : { -1, 1 }) {
      std::vector<int> poly;
      for (int i = 0; i < (int)v.size(); i++)
        if (v[i][axis] == s * h) poly.push_back(i);
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      std::sort(poly.begin(), poly.end(), [&](int a, int b) {
        return std::atan2(v[a][w], v[a][u]) < std::atan2(v[b][w], v[b][u]);
      });
      f.push_back(poly);
    }
  return PolyhedronShape(v, f, "truncated-cube");
}

bool PolyhedronShape::unit_inertia(Matrix3d &I) const
{
  I = second_moment_.trace() * Matrix3d::Identity() - second_moment_;
  return true;
}

double PolyhedronShape::distance_bound(const Vector3d &p) const
{
  double smax = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < normal_.size(); k++) smax = std::max(smax, normal_[k].dot(p) - offset_[k]);
  return smax;
}

void PolyhedronShape::query(const Vector3d &p, SurfacePoint &out) const
{
  const int nf = (int)normal_.size();
  int kmax = 0;
  double smax = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < nf; k++) {
    const double s = normal_[k].dot(p) - offset_[k];
    if (s > smax) { smax = s; kmax = k; }
  }
  if (smax <= 0.0) {  // inside or on the surface: the nearest face plane
    out.dist = smax;
    out.normal = normal_[kmax];
    out.point = p - smax * normal_[kmax];
    return;
  }
  // Outside: the distance is at least the height above any face plane; a visible face whose
  // polygon holds the projection attains it. Otherwise the nearest point is on an edge or vertex.
  double best = std::numeric_limits<double>::infinity();
  Vector3d c = p;
  for (int k = 0; k < nf; k++) {
    const double s = normal_[k].dot(p) - offset_[k];
    if (s <= 0.0) continue;
    const Vector3d q = p - s * normal_[k];
    const std::vector<int> &loop = f_[k];
    const size_t m = loop.size();
    bool in = true;
    for (size_t i = 0; i < m && in; i++) {
      const Vector3d &a = v_[loop[i]], &b = v_[loop[(i + 1) % m]];
      if ((b - a).cross(q - a).dot(normal_[k]) < 0.0) in = false;
    }
    if (in) {
      out.dist = s;
      out.normal = normal_[k];
      out.point = q;
      return;
    }
    for (size_t i = 0; i < m; i++) {
      const Vector3d e = segment_point<Vector3d>(v_[loop[i]], v_[loop[(i + 1) % m]], p);
      const double d2 = (p - e).squaredNorm();
      if (d2 < best) { best = d2; c = e; }
    }
  }
  out.dist = std::sqrt(best);
  out.point = c;
  out.normal = out.dist > 0.0 ? Vector3d((p - c) / out.dist) : normal_[kmax];
}

}
