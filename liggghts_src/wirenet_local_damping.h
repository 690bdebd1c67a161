/* WireNet: Cundall's local damping (PFC's "local damping"), the one rule fix wirenet/damping
   applies to every node and fix wirenet/body to a free body's resultant. */

#ifndef WIRENET_LOCAL_DAMPING_H
#define WIRENET_LOCAL_DAMPING_H

#include <cmath>

namespace WireNet {

// The damping force on one component: alpha |f| against the velocity component, none where the
// component is at rest (the rule acts on unbalanced forces only, never on a node at rest)
inline double local_damping(double f, double v, double alpha)
{
  return -alpha * std::fabs(f) * static_cast<double>((v > 0.0) - (v < 0.0));
}

}  // namespace WireNet

#endif
