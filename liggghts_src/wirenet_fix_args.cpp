/* WireNet: argument readers shared by the fixes' parsers. */

#include "wirenet_fix_args.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace WireNet {
namespace FixArgs {

double number(const char *s, const std::string &what)
{
  char *end = NULL;
  errno = 0;
  const double v = strtod(s, &end);
  if (errno || end == s || *end != '\0' || !std::isfinite(v))
    throw std::invalid_argument(what + " must be a finite number (got '" + s + "')");
  return v;
}

double value(int narg, char **arg, int &k, const std::string &key, double lo, bool lo_open)
{
  if (k + 1 >= narg) throw std::invalid_argument("'" + key + "' needs a value");
  const double v = number(arg[k + 1], key);
  if (lo_open ? !(v > lo) : !(v >= lo))
    throw std::invalid_argument(key + " must be " + (lo_open ? "> " : ">= ") + text(lo) +
                                " (got " + arg[k + 1] + ")");
  k += 2;
  return v;
}

int steps(int narg, char **arg, int &k, const std::string &key)
{
  const std::string given = k + 1 < narg ? arg[k + 1] : "";
  const double v = value(narg, arg, k, key, 1.0, false);
  if (v != static_cast<double>(static_cast<int>(v)) || v > 1e9)
    throw std::invalid_argument("'" + key + "' must be a whole number of steps, 1 to 1e9 (got '" + given + "')");
  return static_cast<int>(v);
}

Eigen::Vector3d vector3(int narg, char **arg, int &k, const std::string &key)
{
  if (k + 3 >= narg) throw std::invalid_argument("'" + key + "' needs 3 values");
  Eigen::Vector3d r;
  for (int d = 0; d < 3; d++) r[d] = number(arg[k + 1 + d], key + " value");
  k += 4;
  return r;
}

Eigen::Matrix3d inertia(int narg, char **arg, int &k)
{
  if (k + 6 >= narg) throw std::invalid_argument("'inertia' needs 6 values: Ixx Iyy Izz Ixy Ixz Iyz");
  double c[6];
  for (int d = 0; d < 6; d++) c[d] = number(arg[k + 1 + d], "inertia value");
  Eigen::Matrix3d m;
  m << c[0], c[3], c[4],
       c[3], c[1], c[5],
       c[4], c[5], c[2];
  k += 7;
  return m;
}

std::string text(double v)
{
  char buf[64];
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (strtod(buf, NULL) == v) break;
  }
  return buf;
}

}  // namespace FixArgs
}  // namespace WireNet
