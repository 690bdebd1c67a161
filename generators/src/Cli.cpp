#include "Cli.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <new>
#include <sstream>

#include "AtomicFile.h"
#include "Beam.h"
#include "CompoundPanel.h"
#include "Fence.h"
#include "FenceOutput.h"
#include "MeshWriter.h"
#include "Options.h"
#include "Shapes.h"
#include "StlWriter.h"

namespace wirenet {
namespace {

const char* kUsage =
    "usage: wirenet-gen hex|square|compound|beam|fence [options] --out PREFIX\n"
    "       wirenet-gen shape spheroid|cone|truncated-cube [options] --out FILE.stl\n"
    "Panels write PREFIX.data (LIGGGHTS read_data), PREFIX.json (metadata) and PREFIX.types.in\n"
    "(the type numbers by name, a deck include), a fence also\n"
    "PREFIX.shackles; "
    "shapes write FILE.stl (ASCII) and FILE.json. `wirenet-gen SUB --help` lists the options.\n"
    "See doc/wirenet-gen.md.\n";

// ---- option groups --------------------------------------------------------------------------

void addPanelSize(Options& o) {
    o.addNumber("width", 3.0, "m", "panel size along x (clipped at +-W/2)");
    o.addNumber("height", 3.0, "m", "panel size along y (clipped at +-H/2)");
}

// The hex layer's options (`pre` prefixes the node's in a compound net); defaults HexParams'.
void addHexOptions(Options& o, const std::string& pre) {
    const HexParams d;
    o.addNumber("axis-distance", d.axisDistance, "m", "distance between neighbouring twist axes (x)");
    o.addNumber("twist-length", d.twistLength, "m", "length of a double twist (y)");
    o.addNumber("rise", d.rise, "m", "y-distance spanned by a single-wire bond");
    o.addNumber("wire-diameter", d.wireDiameter, "m", "mesh wire diameter");
    o.addNumber("selvedge-diameter", d.selvedgeDiameter, "m", "selvedge (edge) wire diameter");
    o.addNumber(pre + "node-diameter", d.nodeDiameter, "m", "hex node sphere DIAMETER (numerical, 4 d)");
    o.addOptionalNumber(pre + "node-radius", "m", "hex node sphere RADIUS instead of --" + pre +
                        "node-diameter (YADE's hexaNet gives radii)", Bound::Positive);
    o.addString(pre + "node-mass", fmt(d.nodeMass), "hex node mass in kg, or 'wire' (steel wire mass lumped evenly)");
    o.addOptionalNumber(pre + "areal-mass", "kg/m2", "if set, hex node mass = areal mass x W x H / nodes");
    o.addNumber("snap", d.snapFraction, "-", "boundary merge tolerance as a fraction of the shortest lattice bond");
    o.addString("placement", placementName(d.placement), "hex lattice: twist (a twist on the centre), wire (a single-wire "
                "midpoint there), corner (a twist on the lower-left corner, as YADE's hexaNet) or symmetric (the odd "
                "rows of twists on both x edges, as YADE's hexaNet with startAtCorner=False, isSymmetric=True)");
    o.addString("selvedge", selvedgeName(d.selvedge), "hex edge wire: loop (a selvedge bond between consecutive edge "
                "nodes), none (no edge wire, as YADE's hexaNet) or sides (along the two x edges only, parallel to the "
                "twists: a strip cut from a roll, its y edges bare)");
}

// The square layer's options (`pre` prefixes the node's in a compound net); defaults SquareParams'.
void addSquareOptions(Options& o, const std::string& pre) {
    const SquareParams d;
    o.addNumber("cell", d.cell, "m", "square cell size (rope spacing)");
    o.addNumber("rope-diameter", d.ropeDiameter, "m", "strand-rope diameter");
    o.addInt("elements", d.elements, 1, "rope elements per cell side");
    o.addOptionalNumber(pre + "node-diameter", "m", "square node sphere DIAMETER", Bound::Positive, "rope diameter");
    o.addOptionalNumber(pre + "node-radius", "m", "square node sphere RADIUS instead of --" + pre +
                        "node-diameter", Bound::Positive);
    o.addNumber("rope-mass", d.ropeMass, "kg/m", "rope mass per metre, lumped to the nodes");
    o.addNumber("edge-drop", d.dropFraction, "-", "drop an interior rope closer than this x cell to the edge");
}

void addBox(Options& o, double margin, double zlo, double zhi, const std::string& zhint) {
    o.addNumber("margin-x", margin, "m", "box margin beyond the nodes in x", Bound::NonNegative);
    o.addNumber("margin-y", margin, "m", "box margin beyond the nodes in y", Bound::NonNegative);
    if (zhint.empty()) {
        o.addNumber("zlo", zlo, "m", "box lower z bound (net deflects towards -z)", Bound::Any);
        o.addNumber("zhi", zhi, "m", "box upper z bound (loads come from +z)", Bound::Any);
    } else {
        o.addOptionalNumber("zlo", "m", "box lower z bound", Bound::Any, zhint);
        o.addOptionalNumber("zhi", "m", "box upper z bound", Bound::Any, "+" + zhint.substr(1));
    }
}

// Models larger than this are refused unless --max-nodes raises the limit: a typing slip such
// as --width 1e6 would otherwise allocate until the machine runs out of memory.
constexpr long kDefaultMaxNodes = 5000000;
// Peak memory per node of a run, measured on hex (about 290 B), square (150 B) and beam (80 B).
constexpr double kBytesPerNode = 300;

void addMaxNodes(Options& o) {
    o.addInt("max-nodes", kDefaultMaxNodes, 1,
             "refuse a model estimated above this many nodes (about 300 bytes of memory per node)");
}

// ---- shared: output targets, guards, the report ---------------------------------------------

std::string requireOut(const Options& o) {
    const std::string& out = o.str("out");
    if (!o.wasGiven("out")) throw UsageError("--out is required (got nothing)");
    return out;
}

std::string fmt3(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

// Memory the system can still give (MemAvailable), in bytes; 0 if unknown.
double availableMemory() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    double kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024.0;
    return 0;
}

// Size guard, before anything is allocated: the estimated node count against --max-nodes and
// the estimated memory against what the machine has.
void checkSize(const Options& o, double nodes) {
    const long limit = o.integer("max-nodes");
    const double bytes = nodes * kBytesPerNode;
    const std::string values = o.givenExcept("out");
    const std::string what = values.empty() ? "the defaults give" : values + " gives";
    if (!(nodes <= double(limit)))
        throw UsageError(what + " about " + fmt3(nodes) + " nodes (about " + fmt3(bytes / 1073741824.0) +
                         " GiB of memory), more than --max-nodes " + std::to_string(limit) +
                         " (give --max-nodes N to allow more)");
    const double avail = availableMemory();
    if (bytes > 256.0 * 1048576.0 && avail > 0 && bytes > avail)
        throw UsageError(what + " about " + fmt3(nodes) + " nodes, which need about " +
                         fmt3(bytes / 1073741824.0) + " GiB of memory, more than the " +
                         fmt3(avail / 1073741824.0) + " GiB available");
}

// Derived quantities (positions, masses, densities, the box) must be finite before anything is
// written: extreme but finite option values can still overflow or underflow in them.
void checkModel(const Options& o, const NetModel& m, const Box& box) {
    const std::string values = o.givenExcept("out");
    auto bad = [&](const std::string& what, double v) {
        throw UsageError(what + " is not a finite positive number (got " + fmt(v) + ") with " +
                         (values.empty() ? std::string("the defaults") : values));
    };
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const Node& n = m.nodes[i];
        const std::string atom = "atom " + std::to_string(i + 1);
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(n.x[k])) bad(atom + " coordinate", n.x[k]);
        if (!(std::isfinite(n.diameter) && n.diameter > 0)) bad(atom + " diameter", n.diameter);
        if (!(std::isfinite(n.mass) && n.mass > 0)) bad(atom + " mass", n.mass);
        const double density = n.mass / (M_PI * n.diameter * n.diameter * n.diameter / 6.0);
        if (!(std::isfinite(density) && density > 0)) bad(atom + " density", density);
    }
    for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(box.lo[k])) bad("box lower bound", box.lo[k]);
        if (!std::isfinite(box.hi[k])) bad("box upper bound", box.hi[k]);
    }
    const double mass = m.totalMass();
    if (!(std::isfinite(mass) && mass > 0)) bad("total mass", mass);
}

// --out is a file prefix and every PREFIX.EXT can be written, before anything is built.
void checkPrefix(const std::string& out, const std::vector<std::string>& extensions = {".data", ".json", ".types.in"}) {
    if (!out.empty() && out.back() == '/')
        throw UsageError("--out must be a file prefix, not a folder (got " + out + ")");
    std::vector<std::string> targets;
    for (const auto& ext : extensions) targets.push_back(out + ext);
    AtomicFile::checkTargets(targets);
}

// The one-line report of a net: counts per bond type, mass, bond lengths.
std::string summary(const std::string& sub, const NetModel& m, const NetDescription& d) {
    std::ostringstream os;
    os << "wirenet-gen " << sub << ": " << m.nodes.size() << " atoms, " << m.bonds.size() << " bonds (";
    bool first = true;
    for (const auto& kv : m.bondsPerType()) {
        os << (first ? "" : ", ") << d.bondTypeNames.at(kv.first) << " " << kv.second;
        first = false;
    }
    double minLen = m.bonds.empty() ? 0 : 1e300;
    for (const auto& b : m.bonds) minLen = std::min(minLen, m.bondLength(b));
    os << "), mass " << fmt(m.totalMass()) << " kg";
    if (d.area > 0) os << " (" << fmt(m.totalMass() / d.area) << " kg/m2)";
    os << ", bond length " << fmt(minLen) << " .. " << fmt(m.maxBondLength()) << " m";
    return os.str();
}

// ---- panels: hex, square, compound ----------------------------------------------------------

// The node sphere's diameter: --node-radius doubled when given (never together with
// --node-diameter: a size stated twice is a size stated ambiguously), else `diameter`.
double nodeDiameter(const Options& o, const std::string& pre, double diameter) {
    if (!o.isSet(pre + "node-radius")) return diameter;
    if (o.wasGiven(pre + "node-diameter"))
        throw UsageError("give --" + pre + "node-diameter or --" + pre + "node-radius, not both");
    return 2.0 * o.num(pre + "node-radius");
}

// The hex options as given: node size, mass rule and the words. HexParams::validate() checks
// them against each other once the panel's size is set.
HexParams hexParams(const Options& o, const std::string& pre) {
    HexParams p;
    p.axisDistance = o.num("axis-distance");
    p.twistLength = o.num("twist-length");
    p.rise = o.num("rise");
    p.wireDiameter = o.num("wire-diameter");
    p.selvedgeDiameter = o.num("selvedge-diameter");
    p.nodeDiameter = nodeDiameter(o, pre, o.num(pre + "node-diameter"));
    p.snapFraction = o.num("snap");
    const std::string& mass = o.str(pre + "node-mass");
    if (mass == "wire") {
        p.massRule = HexParams::Mass::FromWire;
    } else {
        double v = 0;
        if (!parseFinite(mass, v) || !(v > 0) || v > kMaxMagnitude)
            throw UsageError("--" + pre + "node-mass must be a number > 0 or 'wire' (got " + mass + ")");
        p.nodeMass = v;
    }
    if (o.isSet(pre + "areal-mass")) {
        p.massRule = HexParams::Mass::Areal;
        p.arealMass = o.num(pre + "areal-mass");
    }
    if (!parsePlacement(o.str("placement"), p.placement))
        throw UsageError("--placement must be twist, wire, corner or symmetric (got " + o.str("placement") + ")");
    if (!parseSelvedge(o.choice("selvedge", {"loop", "none", "sides"}), p.selvedge))
        throw UsageError("--selvedge must be loop, none or sides (got " + o.str("selvedge") + ")");
    return p;
}

// The square options as given; SquareParams::validate() checks them once the size is set.
SquareParams squareParams(const Options& o, const std::string& pre) {
    SquareParams p;
    p.cell = o.num("cell");
    p.ropeDiameter = o.num("rope-diameter");
    p.elements = int(o.integer("elements"));
    p.nodeDiameter = nodeDiameter(o, pre, o.isSet(pre + "node-diameter")
                                              ? o.num(pre + "node-diameter") : p.ropeDiameter);
    p.ropeMass = o.num("rope-mass");
    p.dropFraction = o.num("edge-drop");
    return p;
}

// A panel subcommand's layer: sized by --width and --height, then checked.
template <class Layer>
Layer onPanel(Layer p, const Options& o) {
    p.width = o.num("width");
    p.height = o.num("height");
    p.validate(o.valueText());
    return p;
}

Box panelBox(const Options& o, const NetModel& m) {
    Box b;
    const Eigen::Vector3d lo = m.bboxMin(), hi = m.bboxMax();
    b.lo << lo.x() - o.num("margin-x"), lo.y() - o.num("margin-y"), o.num("zlo");
    b.hi << hi.x() + o.num("margin-x"), hi.y() + o.num("margin-y"), o.num("zhi");
    if (!(b.lo.z() < lo.z())) throw UsageError("--zlo must be below the nodes (got " + o.str("zlo") + ")");
    if (!(b.hi.z() > hi.z())) throw UsageError("--zhi must be above the nodes (got " + o.str("zhi") + ")");
    return b;
}

void finishPanel(const std::string& sub, const Options& o, const NetModel& m, NetDescription& d) {
    const std::string out = requireOut(o);
    d.command = sub + " " + o.given();
    d.width = o.num("width");
    d.height = o.num("height");
    d.area = d.width * d.height;
    d.box = panelBox(o, m);
    checkModel(o, m, d.box);
    MeshWriter(m, d).write(out);
    std::cout << summary(sub, m, d) << "\n  -> " << out << ".data, " << out << ".json, " << out << ".types.in\n";
}

int runHex(const std::vector<std::string>& args) {
    Options o("hex");
    o.setSummary("Double-twist hexagonal mesh (twists parallel to y), clipped at +-W/2, +-H/2,\n"
                 "selvedge wire around the edges. Defaults: the paper's 3 m panel, 8x10 mesh, 2.7 mm wire.");
    addPanelSize(o);
    addHexOptions(o, "");
    addBox(o, 0.2, -2.0, 1.0, "");
    addMaxNodes(o);
    o.addString("out", "required", "output prefix (writes PREFIX.data, PREFIX.json, PREFIX.types.in)");
    if (!o.parse(args)) { std::cout << o.help(); return 0; }
    checkPrefix(requireOut(o));
    const HexParams p = onPanel(hexParams(o, ""), o);
    checkSize(o, HexPanel::estimateNodes(p));
    const NetModel m = HexPanel(p).build();
    NetDescription d = panelDescription("hex");
    HexPanel(p).describe(d, m);
    finishPanel("hex", o, m, d);
    return 0;
}

int runSquare(const std::vector<std::string>& args) {
    Options o("square");
    o.setSummary("Strand-rope square mesh: ropes along x and y, shared node at each crossing,\n"
                 "perimeter ropes on the edges. Defaults: 3 m panel, 300 mm cell, 10 mm rope.");
    addPanelSize(o);
    addSquareOptions(o, "");
    addBox(o, 0.2, -2.0, 1.0, "");
    addMaxNodes(o);
    o.addString("out", "required", "output prefix (writes PREFIX.data, PREFIX.json, PREFIX.types.in)");
    if (!o.parse(args)) { std::cout << o.help(); return 0; }
    checkPrefix(requireOut(o));
    const SquareParams p = onPanel(squareParams(o, ""), o);
    checkSize(o, SquarePanel::estimateNodes(p));
    const NetModel m = SquarePanel(p).build();
    NetDescription d = panelDescription("square");
    SquarePanel(p).describe(d, m);
    finishPanel("square", o, m, d);
    return 0;
}

int runCompound(const std::vector<std::string>& args) {
    Options o("compound");
    o.setSummary("Hexagonal layer (z = r_hex + r_sq, loaded side) over a square layer (z = 0);\n"
                 "no bonds between the layers unless --ties is given. Both layers pinned at the edges.");
    addPanelSize(o);
    addHexOptions(o, "hex-");
    addSquareOptions(o, "square-");
    o.addInt("ties", 0, 0, "tie every k-th interior crossing (in x and y) to the nearest hex node; 0 = none");
    addBox(o, 0.2, -2.0, 1.0, "");
    addMaxNodes(o);
    o.addString("out", "required", "output prefix (writes PREFIX.data, PREFIX.json, PREFIX.types.in)");
    if (!o.parse(args)) { std::cout << o.help(); return 0; }
    checkPrefix(requireOut(o));
    CompoundParams p;
    p.hex = onPanel(hexParams(o, "hex-"), o);
    p.square = onPanel(squareParams(o, "square-"), o);
    p.tieEvery = int(o.integer("ties"));
    checkSize(o, HexPanel::estimateNodes(p.hex) + SquarePanel::estimateNodes(p.square));
    CompoundPanel panel(p);
    const NetModel m = panel.build();
    NetDescription d = panelDescription("compound");
    HexPanel(p.hex).describe(d, m);
    SquarePanel(p.square).describe(d, m);
    d.extra.set("hex_z", 0.5 * (p.hex.nodeDiameter + p.square.nodeDiameter)).set("square_z", 0.0);
    d.extra.set("tie_every", p.tieEvery).set("ties", panel.ties()).set("tie_bond_type", p.tieType);
    finishPanel("compound", o, m, d);
    return 0;
}

// ---- beam -----------------------------------------------------------------------------------

// The beam's options; the defaults are BeamParams'.
void addBeamOptions(Options& o) {
    const BeamParams d;
    o.setSummary("Straight cantilever chain along +x: root (type 2) at x = 0, tip (type 3) at x = L.");
    o.addNumber("length", d.length, "m", "beam length");
    o.addInt("elements", d.elements, 1, "number of elements (bonds)");
    o.addNumber("diameter", d.diameter, "m", "beam (bonded cylinder) diameter");
    o.addOptionalNumber("node-diameter", "m", "node sphere diameter", Bound::Positive, "beam diameter");
    o.addNumber("density", d.density, "kg/m3", "density of the cylinder, lumped to the nodes");
    addBox(o, 0.1, 0, 0, "-length");
    addMaxNodes(o);
    o.addString("out", "required", "output prefix (writes PREFIX.data, PREFIX.json, PREFIX.types.in)");
}

BeamParams beamParams(const Options& o) {
    BeamParams p;
    p.length = o.num("length");
    p.elements = int(o.integer("elements"));
    p.diameter = o.num("diameter");
    p.nodeDiameter = o.isSet("node-diameter") ? o.num("node-diameter") : p.diameter;
    p.density = o.num("density");
    return p;
}

// --margin-x and --margin-y around the beam; in z --zlo and --zhi, by default +-length (room
// for the tip to deflect either way).
Box beamBox(const Options& o, const BeamParams& p) {
    const double zlo = o.isSet("zlo") ? o.num("zlo") : -p.length, zhi = o.isSet("zhi") ? o.num("zhi") : p.length;
    if (!(zlo < 0)) throw UsageError("--zlo must be below the nodes (got " + o.str("zlo") + ")");
    if (!(zhi > 0)) throw UsageError("--zhi must be above the nodes (got " + o.str("zhi") + ")");
    Box b;
    b.lo << -o.num("margin-x"), -o.num("margin-y"), zlo;
    b.hi << p.length + o.num("margin-x"), o.num("margin-y"), zhi;
    if (!(b.lo.y() < b.hi.y())) throw UsageError("--margin-y must be > 0 for a beam (got " + o.str("margin-y") + ")");
    return b;
}

int runBeam(const std::vector<std::string>& args) {
    Options o("beam");
    addBeamOptions(o);
    if (!o.parse(args)) { std::cout << o.help(); return 0; }
    const std::string out = requireOut(o);
    checkPrefix(out);
    const BeamParams p = beamParams(o);
    checkSize(o, p.elements + 1.0);
    const NetModel m = Beam(p).build();
    NetDescription d = Beam(p).describe();
    d.command = "beam " + o.given();
    d.box = beamBox(o, p);
    checkModel(o, m, d.box);
    MeshWriter(m, d).write(out);
    std::cout << summary("beam", m, d) << "\n  -> " << out << ".data, " << out << ".json, " << out << ".types.in\n";
    return 0;
}

// ---- fence ----------------------------------------------------------------------------------

// The fence's options; the defaults are FenceParams' (the fence inputs/fence.in brings to rest).
void addFenceOptions(Options& o) {
    const FenceParams d;
    o.setSummary("Rockfall fence in the form of EAD 340059-00-0106 (ETAG 027): net modules between hinged posts,\n"
                 "top and bottom support ropes from lateral anchor to lateral anchor with brakes, upslope ropes\n"
                 "with brakes, and the shackles that hang the net on the ropes (PREFIX.shackles). Frame: x along\n"
                 "the fence (centred), y upslope (the block comes from +y), z up (post bases at z = 0).\n"
                 "Defaults: 3 modules, 10 m post spacing, 5 m posts, compound net, HEA 200 posts, 22 mm ropes.");
    o.addInt("modules", d.modules, 1, "functional modules (one net panel between two posts each)");
    o.addNumber("spacing", d.spacing, "m", "post spacing");
    o.addNumber("height", d.height, "m", "post height = nominal height of the fence");
    o.addString("net", netKindName(d.net), "net of each module: hex, square or compound");
    addHexOptions(o, "hex-");
    addSquareOptions(o, "square-");
    o.addInt("ties", d.panel.tieEvery, 0, "compound: tie every k-th interior crossing to the nearest hex node; 0 = none");
    o.addNumber("shackle-gap", d.shackleGap, "m", "gap between the net's top and bottom edges and their support ropes (panel height = height - 2 gap)");
    o.addOptionalNumber("post-gap", "m", "gap between the net's side edges and their posts' axes (panel width = spacing - 2 post gap); "
                        "by default the sides hang the shackle gap from the post's face as the top and bottom edges from the ropes' axes",
                        Bound::Positive, "shackle-gap + post-node-diameter/2 rounded up to the cm: " + fmt(d.defaultPostGap()));
    o.addString("side-shackles", d.sideShackles ? "post" : "none", "module sides: post (shackled to the neighbouring post) or none (free)");
    o.addString("head-guides", d.clampHeads ? "clamp" : "slide", "top rope at the post heads: clamp (fixed to the head) or slide (through a guide, a shackle; the posts sway)");
    o.addNumber("rope-segment", d.ropeSegment, "m", "target bond length of the support and upslope ropes");
    o.addNumber("support-rope-diameter", d.supportDiameter, "m", "top and bottom support rope diameter");
    o.addNumber("upslope-rope-diameter", d.upslopeDiameter, "m", "upslope rope diameter");
    o.addNumber("rope-fill", d.fill, "-", "metallic fill factor of the wire ropes: mass = fill x density x pi d^2/4 per metre");
    o.addNumber("anchor-distance", d.anchorDistance, "m", "the top rope's lateral anchors beyond the end posts, on the ground (z = 0)");
    o.addNumber("bottom-anchor-distance", d.bottomAnchorDistance, "m", "the bottom rope's lateral anchors beyond the end posts (z = 0)");
    o.addInt("brakes", d.brakes, 0, "brake bonds in each support rope next to each lateral anchor");
    o.addNumber("upslope-distance", d.upslopeDistance, "m", "upslope anchors behind the posts (at y = this)");
    o.addNumber("upslope-height", d.upslopeHeight, "m", "height of the upslope anchors above the post bases", Bound::Any);
    o.addInt("upslope-brakes", d.upslopeBrakes, 0, "brake bonds in each upslope rope next to its anchor");
    o.addNumber("upslope-sag", d.upslopeSag, "-", "installed sag of the upslope ropes at mid-chord, a fraction of the chord "
                "(0: built straight; a straight rope pulls its hinged post upslope until the head gives it a sag)",
                Bound::NonNegative);
    o.addInt("post-elements", d.postElements, 1, "beam elements per post");
    o.addNumber("post-tilt", d.postTilt, "deg", "posts, net and support ropes lean downslope (towards -y) by this angle about the ground line; "
                "a vertical hinged post is an inverted pendulum that only its tension-only upslope rope holds", Bound::Any);
    o.addNumber("post-area", d.postArea, "m2", "post section area A (HEA 200)");
    o.addNumber("post-iy", d.postIy, "m4", "post second moment Iy about the strong axis, which lies along the fence (HEA 200)");
    o.addNumber("post-iz", d.postIz, "m4", "post second moment Iz about the weak axis, which lies along y (HEA 200)");
    o.addNumber("post-j", d.postJ, "m4", "post torsion constant It (HEA 200)");
    o.addNumber("post-node-diameter", d.postNodeDiameter, "m", "post node sphere diameter: the profile's width, HEA 200's "
                "flange width b = 200 mm (EN 10365:2017), where the net touches the post; its rotary inertia 0.4 m r^2 is "
                "within a factor of two of the section's (Iy/A) m; give another profile's width with its section");
    o.addNumber("density", d.density, "kg/m3", "steel density of ropes and posts");
    o.addNumber("margin", 1.0, "m", "box margin beyond the nodes in x, +y and z");
    o.addNumber("ylo", -10.0, "m", "box lower y bound (the net deflects towards -y)", Bound::Any);
    addMaxNodes(o);
    o.addString("out", "required", "output prefix (writes PREFIX.data, PREFIX.json, PREFIX.types.in, PREFIX.shackles)");
}

// The fence's options as given; FenceParams::validateLayout() and validateRopes() check them.
// The layers of the net are read only if the net has them (--net square ignores --placement).
FenceParams fenceParams(const Options& o) {
    FenceParams p;
    p.modules = int(o.integer("modules"));
    p.spacing = o.num("spacing");
    p.height = o.num("height");
    if (!parseNetKind(o.str("net"), p.net))
        throw UsageError("--net must be hex, square or compound (got " + o.str("net") + ")");
    if (p.net != NetKind::Square) p.panel.hex = hexParams(o, "hex-");
    if (p.net != NetKind::Hex) p.panel.square = squareParams(o, "square-");
    p.panel.tieEvery = int(o.integer("ties"));
    p.shackleGap = o.num("shackle-gap");
    if (o.isSet("post-gap")) p.postGap = o.num("post-gap");
    p.sideShackles = o.choice("side-shackles", {"post", "none"}) == "post";
    p.clampHeads = o.choice("head-guides", {"slide", "clamp"}) == "clamp";
    p.ropeSegment = o.num("rope-segment");
    p.supportDiameter = o.num("support-rope-diameter");
    p.upslopeDiameter = o.num("upslope-rope-diameter");
    p.fill = o.num("rope-fill");
    p.anchorDistance = o.num("anchor-distance");
    p.bottomAnchorDistance = o.num("bottom-anchor-distance");
    p.brakes = int(o.integer("brakes"));
    p.upslopeDistance = o.num("upslope-distance");
    p.upslopeHeight = o.num("upslope-height");
    p.upslopeBrakes = int(o.integer("upslope-brakes"));
    p.upslopeSag = o.num("upslope-sag");
    p.postElements = int(o.integer("post-elements"));
    p.postTilt = o.num("post-tilt");
    p.postArea = o.num("post-area");
    p.postIy = o.num("post-iy");
    p.postIz = o.num("post-iz");
    p.postJ = o.num("post-j");
    p.postNodeDiameter = o.num("post-node-diameter");
    p.density = o.num("density");
    return p;
}

// --margin around the nodes, but downslope (-y) down to --ylo: room for the net's deflection.
Box fenceBox(const Options& o, const NetModel& m) {
    const Eigen::Vector3d lo = m.bboxMin(), hi = m.bboxMax();
    const double margin = o.num("margin");
    Box b;
    b.lo << lo.x() - margin, o.num("ylo"), lo.z() - margin;
    b.hi << hi.x() + margin, hi.y() + margin, hi.z() + margin;
    if (!(b.lo.y() < lo.y())) throw UsageError("--ylo must be below the nodes (got " + o.str("ylo") + ")");
    return b;
}

int runFence(const std::vector<std::string>& args) {
    Options o("fence");
    addFenceOptions(o);
    if (!o.parse(args)) { std::cout << o.help(); return 0; }
    const std::string out = requireOut(o);
    checkPrefix(out, {".data", ".json", ".types.in", ".shackles"});
    const FenceParams p = fenceParams(o);
    p.validateLayout(o.valueText());
    checkSize(o, Fence::estimateNodes(p));
    p.validateRopes(o.valueText());

    const FenceModel f = Fence(p).build();
    NetDescription d = fenceDescription(p, f, "fence " + o.given(), out + ".shackles");
    d.box = fenceBox(o, f.model);
    checkModel(o, f.model, d.box);

    MeshWriter writer(f.model, d);
    AtomicFile data(out + ".data"), meta(out + ".json"), types(out + ".types.in"), sh(out + ".shackles");
    writer.writeData(data.stream());
    meta.stream() << writer.metadata().dump(2) << "\n";
    writer.writeTypes(types.stream());
    writeShackles(sh.stream(), f, d.command);
    AtomicFile::commitAll({&data, &meta, &types, &sh});
    std::cout << summary("fence", f.model, d) << "\n  " << f.shackles.size() << " shackles on " << f.ropes.size()
              << " ropes, " << f.anchors.size() << " anchors\n  -> " << out << ".data, " << out << ".json, "
              << out << ".types.in, " << out << ".shackles\n";
    return 0;
}

// ---- shapes ---------------------------------------------------------------------------------

std::string jsonPathFor(const std::string& stl) {
    const auto dot = stl.rfind('.');
    const auto slash = stl.rfind('/');
    if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) return stl.substr(0, dot) + ".json";
    return stl + ".json";
}

// A shape's options: its size by kind, the resolution of the round ones, the mass.
void addShapeOptions(Options& o, ShapeKind kind) {
    const bool cube = kind == ShapeKind::TruncatedCube;
    if (kind == ShapeKind::Spheroid) {
        o.setSummary("Semi-spheroid platter (Pol et al. 2017): base disc at z = 0, dome towards -z.");
        o.addNumber("radius", 0.5, "m", "base radius");
        o.addNumber("height", 0.15, "m", "dome height");
    } else if (kind == ShapeKind::Cone) {
        o.setSummary("Cone platter (Bonati et al. 2004): base disc at z = 0, apex at z = -height.");
        o.addNumber("radius", 0.34, "m", "base radius");
        o.addNumber("height", 0.78, "m", "height");
        o.addNumber("tip-radius", 0.0, "m", "radius of a flat tip disc replacing the apex (0 = sharp)", Bound::NonNegative);
    } else {
        o.setSummary("Truncated cube (impact block, EOTA 2013 / ETAG 027 shape), centroid at the origin.");
        o.addNumber("side", 0.45, "m", "cube side");
        o.addOptionalNumber("corner-cut", "m", "length cut off each cube edge at every corner", Bound::Positive, "side/3");
    }
    // 1024 segments: about 0.5 million facets (130 MB of ASCII STL) for the spheroid.
    if (!cube) o.addInt("resolution", 96, 8, "segments around the axis, dome rings = resolution/4 (>= 64 keeps the volume within 0.5 %)", 1024);
    if (cube) o.addNumber("mass", 44.5, "kg", "mass for the inertia tensor");
    else o.addOptionalNumber("mass", "kg", "mass for the inertia tensor", Bound::Positive, "none");
    o.addString("out", "required", "output STL file (also writes FILE.json)");
}

// The shape's options as given; ShapeParams::validate() checks them.
ShapeParams shapeParams(const Options& o, ShapeKind kind) {
    ShapeParams p;
    p.kind = kind;
    if (kind == ShapeKind::TruncatedCube) {
        p.side = o.num("side");
        p.cornerCut = o.isSet("corner-cut") ? o.num("corner-cut") : p.side / 3.0;
        p.mass = o.num("mass");
        return p;
    }
    p.radius = o.num("radius");
    p.height = o.num("height");
    p.resolution = int(o.integer("resolution"));
    if (kind == ShapeKind::Cone) p.tipRadius = o.num("tip-radius");
    if (o.isSet("mass")) p.mass = o.num("mass");
    return p;
}

// The mesh's mass properties, refused unless finite: extreme but finite sizes can still over-
// or underflow in them. Round-off of exactly symmetric quantities is printed as 0.
MassProperties checkedMassProperties(const Options& o, const TriMesh& mesh, double mass, double analytic) {
    MassProperties mp = massProperties(mesh, mass);
    const double scale = mesh.vertices.empty() ? 1.0 : (mesh.vertices[0] - mp.centroid).norm();
    for (int i = 0; i < 3; ++i)
        if (std::abs(mp.centroid[i]) < 1e-12 * scale) mp.centroid[i] = 0;
    const std::string values = o.givenExcept("out");
    auto bad = [&](const std::string& what, double v) {
        throw UsageError("the shape's " + what + " is not a finite positive number (got " + fmt(v) +
                         ") with " + (values.empty() ? std::string("the defaults") : values));
    };
    if (!(std::isfinite(mp.volume) && mp.volume > 0)) bad("volume", mp.volume);
    if (!(std::isfinite(analytic) && analytic > 0)) bad("analytic volume", analytic);
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(mp.centroid[i])) bad("centroid", mp.centroid[i]);
    if (mass > 0) {
        if (!(std::isfinite(mass / mp.volume))) bad("density", mass / mp.volume);
        for (int i = 0; i < 9; ++i)
            if (!std::isfinite(mp.inertia(i))) bad("inertia", mp.inertia(i));
    }
    for (const auto& v : mesh.vertices)
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(v[i])) bad("vertex coordinate", v[i]);
    const double imax = mp.inertia.cwiseAbs().maxCoeff();
    mp.inertia = mp.inertia.unaryExpr([imax](double v) { return std::abs(v) < 1e-12 * imax ? 0.0 : v; });
    return mp;
}

std::string shapeSummary(const ShapeParams& p, const TriMesh& mesh, const MassProperties& mp) {
    const double analytic = p.volume();
    std::ostringstream os;
    os << "wirenet-gen shape " << shapeKindName(p.kind) << ": " << mesh.faces.size() << " facets, volume "
       << fmt(mp.volume) << " m3 (analytic " << fmt(analytic) << ", " << fmt(100 * (mp.volume / analytic - 1))
       << " %), centroid (" << fmt(mp.centroid.x()) << ", " << fmt(mp.centroid.y()) << ", " << fmt(mp.centroid.z())
       << ")\n";
    if (p.mass > 0) {
        os << "  mass " << fmt(p.mass) << " kg, density " << fmt(p.mass / mp.volume)
           << " kg/m3, inertia about the centroid [kg m2]:\n";
        for (int i = 0; i < 3; ++i)
            os << "    " << fmt(mp.inertia(i, 0)) << " " << fmt(mp.inertia(i, 1)) << " " << fmt(mp.inertia(i, 2)) << "\n";
    }
    return os.str();
}

int runShape(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "--help" || args[0] == "-h") {
        std::cout << "usage: wirenet-gen shape spheroid|cone|truncated-cube [options] --out FILE.stl\n"
                     "`wirenet-gen shape KIND --help` lists the options.\n";
        if (args.empty()) throw UsageError("shape kind missing (got nothing)");
        return 0;
    }
    const std::string name = args[0];
    ShapeKind kind;
    if (!parseShapeKind(name, kind))
        throw UsageError("unknown shape " + name + " (expected spheroid, cone or truncated-cube)");
    Options o("shape " + name);
    addShapeOptions(o, kind);
    if (!o.parse({args.begin() + 1, args.end()})) { std::cout << o.help(); return 0; }
    const std::string out = requireOut(o), json = jsonPathFor(out);
    if (json == out) throw UsageError("--out must name the STL file, not its .json (got " + out + ")");
    AtomicFile::checkTargets({out, json});

    const ShapeParams p = shapeParams(o, kind);
    p.validate();
    const TriMesh mesh = p.mesh();
    const MassProperties mp = checkedMassProperties(o, mesh, p.mass, p.volume());
    AtomicFile stl(out), meta(json);
    StlWriter::write(stl.stream(), mesh, name);
    meta.stream() << StlWriter::metadata(p, mesh, mp, "shape " + name + " " + o.given(), out).dump(2) << "\n";
    AtomicFile::commitAll({&stl, &meta});
    std::cout << shapeSummary(p, mesh, mp) << "  -> " << out << ", " << json << "\n";
    return 0;
}

}  // namespace

int runCli(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "--help" || args[0] == "-h") {
        std::cout << kUsage;
        if (args.empty()) {
            std::cerr << "wirenet-gen: error: subcommand missing (got nothing)\n";
            return 2;
        }
        return 0;
    }
    const std::string sub = args[0];
    std::vector<std::string> rest(args.begin() + 1, args.end());
    std::string label = sub;
    if (sub == "shape" && !rest.empty() && rest[0].rfind("--", 0) != 0) label += " " + rest[0];
    try {
        if (sub == "hex") return runHex(rest);
        if (sub == "square") return runSquare(rest);
        if (sub == "compound") return runCompound(rest);
        if (sub == "beam") return runBeam(rest);
        if (sub == "fence") return runFence(rest);
        if (sub == "shape") return runShape(rest);
        std::cerr << "wirenet-gen: error: unknown subcommand " << sub
                  << " (expected hex, square, compound, beam, fence or shape)\n";
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "wirenet-gen " << label << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        // Temporary files are gone: their destructors ran while the exception unwound.
        std::cerr << "wirenet-gen " << label
                  << ": error: out of memory (the model is too large for this machine;"
                     " use smaller sizes)\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "wirenet-gen " << label << ": error: internal error: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace wirenet
