// Straight cantilever chain along +x: root (x = 0) to tip (x = L), N elements.
#pragma once
#include "NetModel.h"

namespace wirenet {

struct BeamParams {
    double length = 2.0, diameter = 0.01, nodeDiameter = 0.01;
    int elements = 5;
    double density = 7850.0;  // kg/m3 of the beam cylinder, lumped to the nodes
};

class Beam {
public:
    explicit Beam(const BeamParams& p) : p_(p) {}
    NetModel build() const;
    // The beam's metadata: types, wire, node, the "beam" keys. The command and the box are the
    // caller's.
    NetDescription describe() const;

private:
    BeamParams p_;
};

}  // namespace wirenet
