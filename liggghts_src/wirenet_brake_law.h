/* WireNet: brake law, the energy-dissipating device in a support rope of a rockfall fence
   (an idealised friction or ring brake; Volkwein 2004, Escallon et al. 2014).
   No LIGGGHTS dependency. The law is a force-elongation envelope of the wire law (WireLaw with
   a = 1, b = 0, c = 1: the table is elongation [m] and force [N]), so the force loop, the
   history record, the plastic-work and rupture tallies, damping, output and restarts are the
   wire law's. See doc/bond_wirenet.md, "The brake law". */

#ifndef WIRENET_BRAKE_LAW_H
#define WIRENET_BRAKE_LAW_H

#include <optional>

#include "wirenet_wire_law.h"

namespace WireNet {

// The parameters of `bond_coeff T brake ...`, one member per keyword.
struct BrakeLawParams {
  double force = 0.0;               // `force F_ACT` [N]: activation force, the plateau's; > 0
  double stroke = 0.0;              // `stroke S` [m]: elongation of the sliding plateau; > 0
  double stiffness = 0.0;           // `stiffness K` [N/m]: elastic loading, unloading, reloading; > 0
  std::optional<double> lock;       // `lock K_LOCK` [N/m]: after the stroke; 0 < K_LOCK <= K; default K
  std::optional<double> breaking;   // `break F_BREAK` [N]: rupture force > F_ACT; default: never breaks
  double damping = 0.0;             // `damping ZETA`: bond damping, fraction of critical; >= 0
};

class BrakeLaw {
 public:
  // Throws std::invalid_argument with a one-line message naming the item and its value.
  explicit BrakeLaw(const BrakeLawParams &p);

  const BrakeLawParams &params() const { return p_; }
  double lock_stiffness() const { return k_lock_; }
  bool breakable() const { return p_.breaking.has_value(); }
  double activation_elongation() const { return u_act_; }  // F_ACT / K
  double stroke_end() const { return u_end_; }             // F_ACT / K + S
  double rupture_elongation() const { return u_break_; }   // infinite without `break`

  // The wire-law parameters of the same envelope: points (F/K, F), (F/K + S, F) and a point on
  // the lock-up line (at F_BREAK, or one stroke further when the brake never breaks).
  WireLawParams envelope() const;

 private:
  BrakeLawParams p_;
  double k_lock_ = 0.0, u_act_ = 0.0, u_end_ = 0.0, u_break_ = 0.0;
};

}  // namespace WireNet

#endif
