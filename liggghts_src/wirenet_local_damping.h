/* WireNet: Cundall's local damping (PFC's "local damping"), the one rule fix wirenet/damping
   applies to every node and fix wirenet/body to a free body's resultant. */

#ifndef WIRENET_LOCAL_DAMPING_H
#define WIRENET_LOCAL_DAMPING_H

#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
// The same rule on two components at once, bit for bit the scalar one: the select is a mask
// (the compiler keeps the scalar select as a branch, which stops it vectorising a loop).
inline __m128d local_damping(__m128d f, __m128d v, __m128d alpha)
{
  const __m128d sign = _mm_set1_pd(-0.0);
  const __m128d mag = _mm_mul_pd(alpha, _mm_andnot_pd(sign, f));            // alpha |f|
  const __m128d d = _mm_xor_pd(_mm_or_pd(_mm_and_pd(sign, v), mag), sign);  // -copysign(mag, v)
  return _mm_and_pd(d, _mm_cmpneq_pd(v, _mm_setzero_pd()));                 // 0 where v = 0
}
#endif

}  // namespace WireNet

#endif
