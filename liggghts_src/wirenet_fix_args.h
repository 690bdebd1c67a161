/* WireNet: argument readers shared by the fixes' parsers (fix wirenet/body, wirenet/rigidmesh).
   Each reader checks what it reads and throws std::invalid_argument with a message naming the
   keyword and the value; the fix turns it into one LIGGGHTS error line. */

#ifndef WIRENET_FIX_ARGS_H
#define WIRENET_FIX_ARGS_H

#include <Eigen/Dense>
#include <string>

namespace WireNet {
namespace FixArgs {

// a finite number (strtod's "inf"/"nan" and overflows are refused), else throws naming `what`
double number(const char *s, const std::string &what);
// the value after keyword arg[k], finite and > lo (lo_open) or >= lo; k advances past it
double value(int narg, char **arg, int &k, const std::string &key, double lo, bool lo_open);
// the value after keyword arg[k] as a whole number of steps, 1 .. 1e9; k advances past it
int steps(int narg, char **arg, int &k, const std::string &key);
// the three values after keyword arg[k]; k advances past them
Eigen::Vector3d vector3(int narg, char **arg, int &k, const std::string &key);
// the six values Ixx Iyy Izz Ixy Ixz Iyz after keyword arg[k] as a symmetric tensor
Eigen::Matrix3d inertia(int narg, char **arg, int &k);
// shortest text that reads back as v (for messages and restart checks)
std::string text(double v);

}  // namespace FixArgs
}  // namespace WireNet

#endif
