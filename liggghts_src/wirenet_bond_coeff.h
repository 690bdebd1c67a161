/* WireNet: parser of `bond_coeff T wire|beam|brake ...` arguments into a law specification.
   Throws std::invalid_argument with a one-line message naming the offending item. */

#ifndef WIRENET_BOND_COEFF_H
#define WIRENET_BOND_COEFF_H

#include <string>
#include <vector>

#include "wirenet_beam_law.h"
#include "wirenet_brake_law.h"
#include "wirenet_wire_law.h"

namespace WireNet {

enum class LawKind { NONE = 0, WIRE = 1, BEAM = 2, BRAKE = 3 };

struct BondTypeSpec {
  LawKind kind = LawKind::NONE;
  std::string family;
  WireLawParams wire;
  BeamLawParams beam;
  BrakeLawParams brake;

  // flat form for restart files
  std::vector<double> serialize() const;
  static BondTypeSpec deserialize(const std::vector<double> &v, const std::string &family);
};

// args are the bond_coeff arguments after the type range
BondTypeSpec parse_bond_coeff(const std::vector<std::string> &args);

}  // namespace WireNet

#endif
