/* WireNet: Cundall's local damping (PFC's "local damping"), the one rule fix wirenet/damping
   applies to every node and fix wirenet/body to a free body's resultant. */

#ifndef WIRENET_LOCAL_DAMPING_H
#define WIRENET_LOCAL_DAMPING_H

#include <cmath>

#include "wirenet_lanes.h"

namespace WireNet {

// The damping force on one component: alpha |f| against the velocity component, none where the
// component is at rest (the rule acts on unbalanced forces only, never on a node at rest)
// (copysign and a select instead of sign(v) as a number: no int-to-double conversion, and
// the same bits: -alpha |f| sign(v) for v != 0, and f + 0 = f + (-0) = f where v = 0)
inline double local_damping(double f, double v, double alpha)
{
  const double d = -std::copysign(alpha * std::fabs(f), v);
  return v != 0.0 ? d : 0.0;
}

// The same rule on two components at once, bit for bit the scalar one, in bit operations: the
// compiler keeps the scalar select as a branch, which stops it pairing a loop's components.
inline Lanes local_damping(Lanes f, Lanes v, Lanes alpha)
{
  const LaneBits sign = (LaneBits)(Lanes{ -0.0, -0.0 });
  const Lanes mag = alpha * (Lanes)((LaneBits)f & ~sign);                 // alpha |f|
  const LaneBits d = (((LaneBits)v & sign) | (LaneBits)mag) ^ sign;       // -copysign(mag, v)
  return (Lanes)(d & (v != Lanes{ 0.0, 0.0 }));                           // 0 where v = 0
}

}  // namespace WireNet

#endif
