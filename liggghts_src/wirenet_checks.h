/* WireNet: the two helpers of the laws' parameter checks (wire, brake, bond_coeff): a number as
   the message shows it, and a check that throws the one-line message a style turns into an
   error. No LIGGGHTS dependency. */

#ifndef WIRENET_CHECKS_H
#define WIRENET_CHECKS_H

#include <sstream>
#include <stdexcept>
#include <string>

namespace WireNet {

// a value as the user's messages show it (6 significant digits, as C's %g)
inline std::string fmt(double v)
{
  std::ostringstream s;
  s << v;
  return s.str();
}

// throws std::invalid_argument(msg) unless ok
inline void require(bool ok, const std::string &msg)
{
  if (!ok) throw std::invalid_argument(msg);
}

}  // namespace WireNet

#endif
