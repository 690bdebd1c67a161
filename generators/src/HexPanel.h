// Double-twist hexagonal mesh clipped to a W x H panel (twists parallel to y).
#pragma once
#include <string>

#include "NetModel.h"
#include "Usage.h"

namespace wirenet {

// Where the lattice sits in the panel (doc/wirenet-gen.md, "Lattice placement"):
// Twist  - the twist of row 0 centred on the origin (mirror symmetric in x and y);
// Wire   - the midpoint of a single-wire bond on the origin (point symmetric);
// Corner - a twist from the lower-left corner upwards, as YADE's pack.hexaNet(startAtCorner=True);
// Symmetric - mirror symmetric in x with the odd rows of twists on the outermost twist columns
//   (the x edges when W is a multiple of a) and row 0 from the lower edge upwards, as YADE's
//   pack.hexaNet(startAtCorner=False, isSymmetric=True).
enum class Placement { Twist, Wire, Corner, Symmetric };
const char* placementName(Placement p);
// Parses "twist", "wire", "corner" or "symmetric"; false for anything else.
bool parsePlacement(const std::string& text, Placement& p);

// The edge wire (doc/wirenet-gen.md, "Selvedge"):
// Loop  - a selvedge bond between consecutive edge nodes all around the panel (a woven panel);
// None  - no edge wire, the lattice's own bonds along the edges kept (YADE's hexaNet);
// Sides - the selvedge along the two x edges only (x = +-W/2, parallel to the twists: the roll's
//   edges), none along the y edges (the roll's cut ends): a strip cut from a roll.
enum class Selvedge { Loop, None, Sides };
const char* selvedgeName(Selvedge s);
// Parses "loop", "none" or "sides"; false for anything else.
bool parseSelvedge(const std::string& text, Selvedge& s);

struct HexParams {
    double width = 3.0, height = 3.0;  // panel, m
    double axisDistance = 0.080;       // distance between neighbouring twist axes (x), m
    double twistLength = 0.040;        // length of a twist (y), m
    double rise = 0.040;               // y-distance covered by a single-wire bond, m
    double wireDiameter = 0.0027, selvedgeDiameter = 0.0034;  // m
    double nodeDiameter = 0.0108;      // numerical sphere, m
    enum class Mass { PerNode, FromWire, Areal } massRule = Mass::PerNode;
    double nodeMass = 0.0039;          // kg, used with Mass::PerNode
    double arealMass = 0;              // kg/m2, used with Mass::Areal
    double snapFraction = 0.3;         // merge tolerance = fraction x shortest lattice bond
    double z = 0;                      // plane of the layer
    int molecule = 1;
    Placement placement = Placement::Twist;
    // The edge wire (type 3): around the panel (Loop, as a woven panel has), none (YADE's
    // hexaNet has no selvedge; the lattice's own bonds along the edges are kept) or along the x
    // edges only (Sides: a strip cut from a roll, its cut y edges bare).
    Selvedge selvedge = Selvedge::Loop;

    double swLength() const;
    double rowPitch() const { return twistLength + rise; }
    double snapTolerance() const;
    // Centre of the twist of row 0, half-column 0 for the placement (origin for Twist).
    Eigen::Vector2d latticeOrigin() const;
    // Throws UsageError unless the lattice fits the panel and the snap tolerance stays below
    // half a bond. Each number's own range (> 0) is the option parser's; `sides` names the
    // panel's width and height in the message.
    void validate(const ValueText& text = formatted, const SideNames& sides = {}) const;
};

constexpr double kSteelDensity = 7850.0;  // kg/m3; EN 1991-1-1, Table A.4 (steel)

class HexPanel {
public:
    explicit HexPanel(const HexParams& p) : p_(p) {}
    NetModel build() const;
    // Nodes build() allocates (the whole lattice before clipping), computed in floating point
    // so that it can be checked before anything is allocated.
    static double estimateNodes(const HexParams& p);
    // Mass per node actually used for a model with n nodes and the given wire lengths.
    double nodeMass(const NetModel& m) const;
    // Total wire length per bond family (DT counted once, it holds two wires).
    static std::map<int, double> lengthPerType(const NetModel& m);
    Json cellJson() const;
    // The layer's cells, wires and node entries of the metadata; `m` is the built model (a
    // compound's or a fence module's), whose molecule-1 nodes are this layer.
    void describe(NetDescription& d, const NetModel& m) const;

private:
    HexParams p_;
};

}  // namespace wirenet
