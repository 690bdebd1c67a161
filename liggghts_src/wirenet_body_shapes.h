/* WireNet: exact geometry of the analytic rigid bodies of fix wirenet/body (no LIGGGHTS
   dependence, no I/O, no allocation in the queries).

   Every shape lives in its own local frame. query(p) returns, for a point p in that frame, the
   nearest point of the surface, the outward unit normal there and the signed distance (> 0
   outside, < 0 inside). For a point outside a convex shape the normal is (p - point) / dist, so
   edges and vertices act as exact rounded features; inside, it is the outward normal of the
   nearest face. See doc/fix_wirenet_body.md. */

#ifndef WIRENET_BODY_SHAPES_H
#define WIRENET_BODY_SHAPES_H

#include <Eigen/Dense>
#include <limits>
#include <string>
#include <vector>

namespace WireNet {

struct SurfacePoint {
  double dist;              // signed distance of the query point (> 0 outside)
  Eigen::Vector3d point;    // nearest surface point
  Eigen::Vector3d normal;   // outward unit normal of the surface there
};

class BodyShape {
 public:
  virtual ~BodyShape() {}
  virtual void query(const Eigen::Vector3d &p, SurfacePoint &out) const = 0;
  // radius of a sphere about the local origin that contains the body (infinite for a plane)
  virtual double bounding_radius() const = 0;
  // a cheap lower bound of the signed distance of p (a pre-test before query)
  virtual double distance_bound(const Eigen::Vector3d &) const { return -std::numeric_limits<double>::infinity(); }
  // true if the local origin is the centroid (a free body rotates about it)
  virtual bool centred() const { return true; }
  // inertia tensor of the uniform solid per unit mass about the local origin, local axes;
  // false if the shape has none (plane) or it is not implemented
  virtual bool unit_inertia(Eigen::Matrix3d &) const { return false; }
  virtual std::string name() const = 0;
  // The body's points that can touch a fixed plane (fix wirenet/body floor): a polyhedron's
  // corners, each a contact point of its own (a block on a face rests on all of them); NULL for a
  // smooth shape, which touches a plane at its support point only.
  virtual const std::vector<Eigen::Vector3d> *corners() const { return NULL; }
  // Point of a smooth shape farthest along the unit vector u (its deepest point below a plane of
  // outward normal -u); false if the shape has none (a polyhedron: its corners, a plane, a cone)
  virtual bool support(const Eigen::Vector3d &, Eigen::Vector3d &) const { return false; }
};

class SphereShape : public BodyShape {
 public:
  explicit SphereShape(double radius);
  void query(const Eigen::Vector3d &p, SurfacePoint &out) const;
  double bounding_radius() const { return r_; }
  bool unit_inertia(Eigen::Matrix3d &I) const;
  bool support(const Eigen::Vector3d &u, Eigen::Vector3d &p) const { p = r_ * u; return true; }
  std::string name() const { return "sphere"; }
 private:
  double r_;
};

// Ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1; a spheroid when two semi-axes are equal. Nearest
// point by Eberly's robust bisection on the Lagrange-multiplier root (Eberly 2013, "Distance
// from a point to an ellipse, an ellipsoid, or a hyperellipsoid").
class EllipsoidShape : public BodyShape {
 public:
  EllipsoidShape(double a, double b, double c);
  void query(const Eigen::Vector3d &p, SurfacePoint &out) const;
  double bounding_radius() const { return e_[0]; }
  // p on the ellipsoid scaled by k = sqrt(sum (p_i/a_i)^2) > 1 is at least (k - 1) min(a) away,
  // since the ball of that radius fits in (k - 1) times the ellipsoid
  double distance_bound(const Eigen::Vector3d &p) const;
  bool unit_inertia(Eigen::Matrix3d &I) const;
  bool support(const Eigen::Vector3d &u, Eigen::Vector3d &p) const;
  std::string name() const { return "spheroid"; }
  // Eberly's algorithm in the sorted frame: e0 >= e1 >= e2 > 0, y >= 0 componentwise; returns
  // the unsigned distance and the nearest point x.
  static double distance_sorted(const double e[3], const double y[3], double x[3]);
  static double distance_sorted_2d(double e0, double e1, double y0, double y1, double &x0, double &x1);
 private:
  double axes_[3];   // a, b, c
  double e_[3];      // sorted, descending
  int perm_[3];      // e_[k] = axes_[perm_[k]]
  bool sphere_;      // a = b = c: the nearest point in closed form, not Eberly's root search
};

// Solid cone about local +z: base disc of radius R at z = 0, tip at z = h. Flat tip (default): a
// disc of radius a at z = h (a = 0: sharp apex), as wirenet-gen shape cone --tip-radius a (whose
// base is at z = 0 and apex at z = -h: use axis 0 0 -1 to point the tip down). Round tip: a
// spherical cap of radius a, centre on the axis at z = h - a, tangent to the flank from the
// base rim (same height h).
class ConeShape : public BodyShape {
 public:
  ConeShape(double base_radius, double height, double tip_radius, bool round_tip = false);
  void query(const Eigen::Vector3d &p, SurfacePoint &out) const;
  double bounding_radius() const { return bound_; }
  bool centred() const { return false; }
  std::string name() const { return "cone"; }
  // round tip: outward normal of the flank and tangent point, meridian (rho, z) coordinates
  Eigen::Vector2d flank_normal() const { return nf_; }
  Eigen::Vector2d tangent_point() const { return T_; }
 private:
  double R_, h_, a_, bound_;
  bool round_;
  Eigen::Vector2d nf_, T_;   // flank normal; end of the flank (tip rim or tangent point)
};

// Half-space z <= 0 of the local frame: the plane through the origin with outward normal +z.
class PlaneShape : public BodyShape {
 public:
  void query(const Eigen::Vector3d &p, SurfacePoint &out) const;
  double bounding_radius() const;
  double distance_bound(const Eigen::Vector3d &p) const { return p[2]; }  // exact
  bool centred() const { return false; }
  std::string name() const { return "plane"; }
};

// Convex polyhedron: vertices and faces (vertex loops, any orientation; reoriented outward).
// Inside: nearest face plane (exact for a convex solid). Outside: the nearest of the face
// interiors, edges and vertices, each tested exactly.
class PolyhedronShape : public BodyShape {
 public:
  // throws std::invalid_argument (non-planar or non-convex input, fewer than 4 faces, ...)
  PolyhedronShape(const std::vector<Eigen::Vector3d> &vertices, const std::vector<std::vector<int> > &faces,
                  const std::string &name);
  static PolyhedronShape box(double lx, double ly, double lz);
  // wirenet-gen shape truncated-cube --side s --corner-cut c: each cube corner cut by the plane
  // through the points at distance c from it along its three edges
  static PolyhedronShape truncated_cube(double side, double cut);
  void query(const Eigen::Vector3d &p, SurfacePoint &out) const;
  double bounding_radius() const { return bound_; }
  double distance_bound(const Eigen::Vector3d &p) const;  // the largest height above a face plane
  bool centred() const { return centred_; }
  bool unit_inertia(Eigen::Matrix3d &I) const;
  const std::vector<Eigen::Vector3d> *corners() const { return &corners_; }
  std::string name() const { return name_; }
  double volume() const { return volume_; }
  Eigen::Vector3d centroid() const { return centroid_; }
  int nfaces() const { return (int)normal_.size(); }
 private:
  std::vector<Eigen::Vector3d> v_;
  std::vector<std::vector<int> > f_;
  std::vector<Eigen::Vector3d> corners_;     // the vertices on faces, each once
  std::vector<Eigen::Vector3d> normal_;
  std::vector<double> offset_;               // face plane: normal . x = offset
  double bound_, volume_;
  Eigen::Vector3d centroid_;
  Eigen::Matrix3d second_moment_;            // integral of x x^T dV / V about the origin
  bool centred_;
  std::string name_;
};

}

#endif
