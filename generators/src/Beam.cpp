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

NetDescription Beam::describe() const {
    NetDescription d;
    d.kind = "beam";
    d.atomTypes = 3;
    d.bondTypes = 1;
    d.atomTypeNames = {{atype::BeamInterior, "beam_interior"}, {atype::BeamRoot, "beam_root"}, {atype::BeamTip, "beam_tip"}};
    d.bondTypeNames = {{btype::Beam, "beam"}};
    d.centre << 0.5 * p_.length, 0, 0;
    d.width = p_.length;
    d.height = 0;
    d.wires.set("beam", wireJson(p_.diameter));
    d.node.set("beam", nodeJson(p_.nodeDiameter, p_.density * M_PI * 0.25 * p_.diameter * p_.diameter * p_.length / p_.elements));
    d.extra.set("length", p_.length).set("elements", p_.elements).set("diameter", p_.diameter);
    d.extra.set("density", p_.density).set("mass_rule", "cylinder mass lumped: half element at the ends");
    return d;
}

}  // namespace wirenet
