#include "CompoundPanel.h"

#include <limits>

namespace wirenet {

NetModel CompoundPanel::build() const {
    HexParams hp = p_.hex;
    SquareParams sp = p_.square;
    hp.molecule = 1;
    sp.molecule = 2;
    sp.z = 0;
    hp.z = 0.5 * (hp.nodeDiameter + sp.nodeDiameter);
    NetModel m = HexPanel(hp).build();
    const int nHex = int(m.nodes.size());
    SquarePanel square(sp);
    m.append(square.build());

    ties_ = 0;
    if (p_.tieEvery <= 0) return m;
    const int ni = int(SquarePanel::ropeLines(0.5 * sp.width, sp.cell, sp.dropFraction).size());
    const int nj = int(SquarePanel::ropeLines(0.5 * sp.height, sp.cell, sp.dropFraction).size());
    for (const auto& c : square.crossings()) {
        // Interior crossings only (edge nodes are pinned anyway); counted from the -x/-y edge.
        if (c.i == 0 || c.j == 0 || c.i == ni - 1 || c.j == nj - 1) continue;
        if (c.i % p_.tieEvery != 0 || c.j % p_.tieEvery != 0) continue;
        const Eigen::Vector2d at = m.nodes[nHex + c.node].x.head<2>();
        int best = -1;
        double bestD = std::numeric_limits<double>::max();
        for (int k = 0; k < nHex; ++k) {
            const double d = (m.nodes[k].x.head<2>() - at).squaredNorm();
            if (d < bestD) { bestD = d; best = k; }
        }
        m.bonds.push_back({p_.tieType, best, nHex + c.node});
        ++ties_;
    }
    return m;
}

}  // namespace wirenet
