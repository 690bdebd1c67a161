// Strand-rope square mesh: ropes along x and y, shared nodes at the crossings, each rope
// segment between crossings split into beam elements.
#pragma once
#include "NetModel.h"
#include "Usage.h"

namespace wirenet {

struct SquareParams {
    double width = 3.0, height = 3.0;
    double cell = 0.30;            // rope spacing, m
    double ropeDiameter = 0.010;   // m
    int elements = 3;              // elements per full cell side
    double nodeDiameter = 0.010;   // m
    double ropeMass = 0.40;        // kg per metre of rope
    double dropFraction = 0.25;    // interior rope closer than this x cell to the edge is dropped
    double z = 0;
    int molecule = 2;

    // Throws UsageError unless a cell fits the panel and the edge drop stays below half a cell.
    // Each number's own range (> 0) is the option parser's; `sides` names the panel's width
    // and height in the message.
    void validate(const ValueText& text = formatted, const SideNames& sides = {}) const;
};

class SquarePanel {
public:
    explicit SquarePanel(const SquareParams& p) : p_(p) {}
    NetModel build() const;
    // Upper estimate of the nodes of build(), computed in floating point before allocating.
    static double estimateNodes(const SquareParams& p);
    // Rope positions along one axis (sorted, both edges included).
    static std::vector<double> ropeLines(double half, double cell, double dropFraction);
    // Crossing node index of rope lines (i along x, j along y) in the last build().
    struct Crossing { int node, i, j; };
    const std::vector<Crossing>& crossings() const { return crossings_; }
    Json cellJson() const;
    // The layer's cells, wires and node entries of the metadata; `m` is the built model (a
    // compound's or a fence module's), whose molecule-2 nodes are this layer.
    void describe(NetDescription& d, const NetModel& m) const;

private:
    int elementsFor(double length) const;
    SquareParams p_;
    mutable std::vector<Crossing> crossings_;
};

}  // namespace wirenet
