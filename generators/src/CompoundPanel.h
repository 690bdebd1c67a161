// Hexagonal layer over a square layer: square at z = 0, hex on the loaded side at
// z = r_hex + r_sq (spheres just touch). The layers interact by contact; optional ties.
#pragma once
#include "HexPanel.h"
#include "SquarePanel.h"

namespace wirenet {

struct CompoundParams {
    HexParams hex;
    SquareParams square;
    int tieEvery = 0;  // 0: no ties; k: every k-th interior crossing in x and y
    int tieType = btype::SW;
};

class CompoundPanel {
public:
    explicit CompoundPanel(const CompoundParams& p) : p_(p) {}
    NetModel build() const;
    long ties() const { return ties_; }

private:
    CompoundParams p_;
    mutable long ties_ = 0;
};

}  // namespace wirenet
