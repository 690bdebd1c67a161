#include "Beam.h"

#include <cmath>

namespace wirenet {

NetModel Beam::build() const {
    NetModel m;
    const int n = p_.elements;
    const double le = p_.length / n;
    const double elementMass = p_.density * M_PI * 0.25 * p_.diameter * p_.diameter * le;
    for (int i = 0; i <= n; ++i) {
        const int type = i == 0 ? atype::BeamRoot : i == n ? atype::BeamTip : atype::BeamInterior;
        // End nodes carry half an element, interior nodes a full one.
        const double mass = (i == 0 || i == n) ? 0.5 * elementMass : elementMass;
        m.nodes.push_back({{p_.length * i / n, 0.0, 0.0}, type, p_.nodeDiameter, mass, 1});
        if (i > 0) m.bonds.push_back({btype::Beam, i - 1, i});
    }
    return m;
}

}  // namespace wirenet
