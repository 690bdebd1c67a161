/* WireNet: two doubles side by side, one per lane (GCC/Clang vector extension: SSE2 on x86-64,
   NEON on aarch64). Lane arithmetic is plain IEEE arithmetic, so a value gets the same bits in
   a lane as alone: the beam loop evaluates two bonds per instruction, the damping pass two force
   components. */

#ifndef WIRENET_LANES_H
#define WIRENET_LANES_H

namespace WireNet {

typedef double Lanes __attribute__((vector_size(16)));
typedef long long LaneBits __attribute__((vector_size(16)));  // a Lanes' bits; comparison masks

}  // namespace WireNet

#endif
