/* WireNet: parallel-bond beam law (Potyondy & Cundall 2004) for strand ropes, in a corotational
   form that is exact for rigid rotations. No LIGGGHTS dependency. */

#ifndef WIRENET_BEAM_LAW_H
#define WIRENET_BEAM_LAW_H

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
  Eigen::Vector3d force_i;     // force on node i (node j gets the opposite)
  Eigen::Vector3d torque_i, torque_j;
  double axial;                // axial force, positive in tension
  double shear;                // shear force magnitude
  double moment;               // largest end bending moment magnitude
  double energy;               // strain energy
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
  // With report == false only forces, torques and the axial force are filled (the bond loop);
  // shear, moment and energy are for output and energy tallies.
  // Raw pointers: positions (3) and row-major rotation matrices (9) straight from the atom and
  // history arrays; the kernel is written out in scalars (the bond loop's hot spot).
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

}  // namespace WireNet

#endif
