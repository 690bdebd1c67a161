// A rockfall fence in the form of EAD 340059-00-0106 (formerly ETAG 027): net modules between
// posts, a top and a bottom support rope from lateral anchor to lateral anchor with brakes,
// hinged posts with upslope ropes, and the shackles that hang the net on the ropes
// (doc/wirenet-gen.md, "fence"). The net modules are the panel generators' panels, moved into
// the fence's frame; nothing of their construction is repeated here.
//
// Frame: x along the fence (posts at x_i = (i - N/2) s), y upslope (the side the block comes
// from: it travels towards -y), z up (post bases at z = 0, heads at z = H). The net hangs in
// the plane y = 0 of the posts; a panel's own (x, y, z) becomes (x_c + x, z, H/2 + y), so its
// loaded side (+z) faces upslope (+y).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "CompoundPanel.h"
#include "Usage.h"

namespace wirenet {

// Atom and bond types of a fence beyond the panels' 1-8 and 1-4 (doc/file_formats.md).
namespace ftype {
constexpr int SupportRope = 9, UpslopeRope = 10, Post = 11, PostBase = 12, PostHead = 13, Anchor = 14;
constexpr int Count = 14;
}  // namespace ftype
namespace fbond {
constexpr int SupportRope = 5, Brake = 6, Upslope = 7, UpslopeBrake = 8, Post = 9;
constexpr int Count = 9;
}  // namespace fbond
// Molecule ids: 1 hexagonal layer, 2 square layer (as in the panels), then the fence's parts.
namespace fmol {
constexpr int TopRope = 3, BottomRope = 4, Upslope = 5, Posts = 6, Anchors = 7;
}

enum class NetKind { Hex, Square, Compound };
const char* netKindName(NetKind k);
// Parses "hex", "square" or "compound"; false for anything else.
bool parseNetKind(const std::string& text, NetKind& k);

// HEA 200 (EN 10365:2017; the values of ArcelorMittal's sales programme of its sections):
// A = 53.83 cm2, Iy = 3692 cm4 (strong axis, parallel to the flanges), Iz = 1336 cm4,
// It = 20.98 cm4, 42.3 kg/m.
constexpr double kHeaArea = 53.83e-4, kHeaIy = 3692e-8, kHeaIz = 1336e-8, kHeaJ = 20.98e-8;
// Its flange width b = 200 mm (EN 10365:2017; h = 190 mm): the post nodes' sphere diameter. The
// net meets the post at its flange, b/2 from the axis, and the sphere's rotary inertia 0.4 m r^2
// = 4.0e-3 m2 x m is within a factor of two of the section's about its strong axis, (Iy / A) m =
// 6.9e-3 m2 x m (a 50 mm sphere had 2.5e-4 m2 x m: the posts' rotation set the fence's stable
// time step).
constexpr double kHeaWidth = 0.200;
// Steel, EN 1993-1-1 3.2.6: E = 210 GPa, nu = 0.3 (recorded for the deck's beam section line).
constexpr double kSteelE = 2.1e11, kSteelNu = 0.3;

// The defaults are wirenet-gen fence's: the fence inputs/fence.in brings to rest.
struct FenceParams {
    // Each default's source: EAD/ETAG = EAD 340059-00-0106 (ETAG 027); unverified: a standard or
    // catalogue whose table was not read; none: a design choice of this test fence; numerical:
    // discretisation only (doc/fence.md, "Sources").
    int modules = 3;                 // functional modules (panels between posts); EAD: three modules
    double spacing = 10.0;           // post spacing, m; EAD (the kit's typical spacing)
    double height = 5.0;             // post height = nominal height, m; none: a 5 m kit (issue #18)
    NetKind net = NetKind::Compound;
    CompoundParams panel;            // hex / square parameters and ties; module() sizes them
    double shackleGap = 0.05;        // net's top and bottom edges to their support ropes, m; numerical
    // Net's side edges to their posts, m; unset: defaultPostGap().
    std::optional<double> postGap;
    bool sideShackles = true;        // module sides shackled to the posts
    bool clampHeads = true;          // top rope clamped at the post heads (false: it slides, the posts sway)
    double ropeSegment = 0.5;        // target rope bond length, m; numerical
    // m; none: a design choice (22 mm ropes of 500 kJ kits: unverified, manufacturers' kit sheets)
    double supportDiameter = 0.022, upslopeDiameter = 0.022;
    // rope mass per metre over steel's per metre of the gross section (1.94 kg/m at 22 mm);
    // unverified: the nominal length mass of 6x36WS-IWRC ropes, about 0.004 d^2 kg/m with d in mm
    // (EN 12385-4, table not read)
    double fill = 0.65;
    double density = kSteelDensity;  // steel, kg/m3; EN 1991-1-1, Table A.4 (7850 kg/m3)
    double anchorDistance = 5.0;     // top rope's lateral anchors beyond the end posts, m; none
    double bottomAnchorDistance = 2.5;  // bottom rope's lateral anchors beyond the end posts, m; none
    int brakes = 1;                  // brake bonds per support-rope end (next to the lateral anchor)
    double upslopeDistance = 10.0;   // upslope anchors behind the posts (+y), m; none
    double upslopeHeight = 0.0;      // height of the upslope anchors above the post bases, m; none: flat ground
    int upslopeBrakes = 1;           // brake bonds per upslope rope (next to its anchor)
    // Installed sag of the upslope ropes at mid-chord, a fraction of the chord (a parabola in the
    // vertical plane of the chord, lying on the ground where it would go under it); none: a
    // design choice (doc/fence.md, "Why a hinged post stands"). A rope built straight pulls its
    // head upslope with H = w L^2 / (8 f) until the head has come close enough to give it a sag
    // f: more than the lean of a hinged post holds.
    double upslopeSag = 0.1;
    int postElements = 5;            // beam elements per post; numerical
    double postTilt = 10.0;          // degrees: posts and net lean downslope (-y) about the base line; none
    // A point of the vertical fence (posts, net, support ropes) leaned by postTilt about the x axis
    // at the ground: (y, z) -> (y cos t - z sin t, y sin t + z cos t); the ground line stays.
    Eigen::Vector3d lean(const Eigen::Vector3d& x) const;
    double postArea = kHeaArea, postIy = kHeaIy, postIz = kHeaIz, postJ = kHeaJ;
    double postNodeDiameter = kHeaWidth;  // m: the profile's width (contact sphere)

    // The post gap without --post-gap: the side edges hang the shackle gap from the post's face
    // (the flange, postNodeDiameter/2 from its axis) as the top and bottom edges hang it from
    // their ropes' axes, shackleGap + postNodeDiameter/2 rounded up to the cm, 0.15 m for the
    // defaults. Its nodes clear the post spheres by shackleGap - r_net, more than the top and
    // bottom nodes clear the rope spheres (shackleGap - r_net - r_rope). (The same clearance
    // alone, 0.139 -> 0.14 m, makes the panel 9.72 m wide, whose hexagonal mesh ends in 15 mm
    // bonds at the sides: the default fence's stable step fell from 9.96e-6 to 7.04e-6 s;
    // 9.70 m: 1.15e-5 s. doc/wirenet-gen.md, "fence".)
    double defaultPostGap() const;
    double sideGap() const { return postGap ? *postGap : defaultPostGap(); }
    double panelWidth() const { return spacing - 2 * sideGap(); }
    double panelHeight() const { return height - 2 * shackleGap; }
    // One module's panel: `panel` sized panelWidth() x panelHeight(), in the plane z = 0, the
    // hex layer molecule 1 and the square layer molecule 2.
    CompoundParams module() const;
    double postX(int i) const { return (i - 0.5 * modules) * spacing; }
    // Rope bonds per module span (the horizontal parts: post heads/bases at bond midpoints).
    long spanBonds() const;
    double spanBond() const { return spacing / double(spanBonds()); }
    // Bonds of the legs from a lateral anchor to the rope's first horizontal node.
    long topLegBonds() const;
    long bottomLegBonds() const;
    double topLegLength() const;      // anchor to the node half a span bond before the end post head
    double bottomLegLength() const;
    double upslopeLength() const;     // the chord, head to anchor
    long upslopeBonds() const;
    double ropeMass(double diameter) const;  // kg/m: fill x density x pi d^2 / 4

    // Checks of the options against each other (each number's own range is the option
    // parser's); they throw UsageError naming the option and its value as `text` shows it. Two
    // steps, for the command line's size guard runs between them: the layout (shackle and post
    // gaps, the module's panel, ties, fill, upslope height, tilt, sphere clearances), which
    // Fence::estimateNodes() needs sane, then the ropes' bonds and brakes, whose integer bond
    // counts only exist once the guard has bounded them. validate() runs both.
    void validateLayout(const ValueText& text = formatted) const;
    void validateRopes(const ValueText& text = formatted) const;
    void validate(const ValueText& text = formatted) const {
        validateLayout(text);
        validateRopes(text);
    }
};

struct FenceRope {
    int id;                      // rope id of the .shackles file
    std::string name, kind;      // e.g. top_support / support_rope, post_0 / post
    std::vector<int> atoms;      // 0-based node indices along the rope
};
struct FenceAnchor {
    int atom;
    std::string name, rope;
};
struct Shackle {
    int atom, rope;              // 0-based node index, rope id
};

struct FenceModel {
    NetModel model;
    NetModel panel;                          // one module's net in the panel frame
    std::vector<FenceRope> ropes;            // the ropes of the .shackles file
    std::vector<Shackle> shackles;
    std::vector<FenceAnchor> anchors;
    std::vector<std::vector<int>> upslopeRopes;  // post head .. upslope anchor, per post
    std::vector<int> postBases, postHeads;
    long panelNodes = 0, panelBonds = 0;     // per module
    double netMass = 0, supportMass = 0, upslopeMass = 0, postMass = 0;
    double shackleMaxDistance = 0;
    std::vector<Eigen::Vector3d> moduleCentres;
};

class Fence {
public:
    explicit Fence(const FenceParams& p) : p_(p) {}
    // One module's net in the panel frame (centred on the origin, normal +z).
    NetModel panel() const;
    FenceModel build() const;
    // Nodes build() allocates, in floating point, before anything is allocated.
    static double estimateNodes(const FenceParams& p);

private:
    FenceParams p_;
};

}  // namespace wirenet
