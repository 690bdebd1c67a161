#include "Fence.h"

#include <algorithm>
#include <cmath>

namespace wirenet {

const char* netKindName(NetKind k) {
    switch (k) {
        case NetKind::Hex: return "hex";
        case NetKind::Square: return "square";
        case NetKind::Compound: return "compound";
    }
    return "compound";
}

bool parseNetKind(const std::string& text, NetKind& k) {
    static const NetKind all[] = {NetKind::Hex, NetKind::Square, NetKind::Compound};
    return parseByName(text, all, netKindName, k);
}

namespace {

// Bonds of a straight run of the given length with bonds of about `seg` (at least one); in
// floating point so that the size guard can use it before anything is allocated.
double bondsFor(double length, double seg) { return std::max(1.0, std::round(length / seg)); }

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (p - (a + t * ab)).norm();
}

Eigen::Vector3d mirrorX(const Eigen::Vector3d& x) { return {-x.x(), x.y(), x.z()}; }

}  // namespace

long FenceParams::spanBonds() const { return long(bondsFor(spacing, ropeSegment)); }

double FenceParams::topLegLength() const {
    return std::hypot(anchorDistance, height) - 0.5 * spanBond();
}
double FenceParams::bottomLegLength() const { return bottomAnchorDistance - 0.5 * spanBond(); }
long FenceParams::topLegBonds() const { return long(bondsFor(topLegLength(), ropeSegment)); }
long FenceParams::bottomLegBonds() const { return long(bondsFor(bottomLegLength(), ropeSegment)); }
Eigen::Vector3d FenceParams::lean(const Eigen::Vector3d& x) const {
    const double t = postTilt * M_PI / 180.0, c = std::cos(t), s = std::sin(t);
    return {x.x(), c * x.y() - s * x.z(), s * x.y() + c * x.z()};
}
double FenceParams::upslopeLength() const {
    const Eigen::Vector3d head = lean({0.0, 0.0, height});
    return std::hypot(upslopeDistance - head.y(), head.z() - upslopeHeight);
}
long FenceParams::upslopeBonds() const { return long(bondsFor(upslopeLength(), ropeSegment)); }
double FenceParams::ropeMass(double d) const { return fill * density * M_PI * 0.25 * d * d; }

double FenceParams::defaultPostGap() const {
    // in cm, less a round-off's worth so that an exact number of cm stays that number
    return std::ceil(100.0 * (shackleGap + 0.5 * postNodeDiameter) - 1e-9) / 100.0;
}

CompoundParams FenceParams::module() const {
    CompoundParams cp = panel;
    cp.hex.width = cp.square.width = panelWidth();
    cp.hex.height = cp.square.height = panelHeight();
    cp.hex.molecule = 1;
    cp.square.molecule = 2;
    cp.hex.z = cp.square.z = 0;
    return cp;
}

void FenceParams::validateLayout(const ValueText& text) const {
    // the post gap as given, or the default and what it comes from
    const std::string postGapText = postGap ? text("post-gap", *postGap)
                                            : fmt(sideGap()) + ", its default from --shackle-gap and "
                                              "--post-node-diameter";
    if (!(shackleGap < 0.5 * height))
        throw UsageError("--shackle-gap must be < --height/2 (got " + text("shackle-gap", shackleGap) + ")");
    if (!(sideGap() < 0.5 * spacing))
        throw UsageError("--post-gap must be < --spacing/2 (got " + postGapText + ")");
    const CompoundParams m = module();
    const SideNames sides{"--spacing - 2 x --post-gap", "(--height - 2 x --shackle-gap)"};
    if (net != NetKind::Square) m.hex.validate(text, sides);
    if (net != NetKind::Hex) m.square.validate(text, sides);
    if (panel.tieEvery > 0 && net != NetKind::Compound)
        throw UsageError(std::string("--ties needs --net compound (got --net ") + netKindName(net) + ")");
    if (!(fill <= 1)) throw UsageError("--rope-fill must be <= 1 (got " + text("rope-fill", fill) + ")");
    if (!(upslopeHeight < height))
        throw UsageError("--upslope-height must be < --height (got " + fmt(upslopeHeight) + " >= " + fmt(height) + ")");
    if (!(upslopeSag <= 0.5))
        throw UsageError("--upslope-sag must be <= 0.5 (got " + text("upslope-sag", upslopeSag) + ")");
    if (!(postTilt >= 0.0 && postTilt < 45.0))
        throw UsageError("--post-tilt must be >= 0 and < 45 degrees (got " + text("post-tilt", postTilt) + ")");
    // No two spheres may overlap at the start: a net edge node next to its rope (top and bottom
    // edges) or post (side edges), a rope node next to the post head (base) it passes at half a
    // bond (validateRopes()). A net corner is farther from the post head (base) than either gap.
    const double rNet = std::max(net != NetKind::Square ? 0.5 * m.hex.nodeDiameter : 0.0,
                                 net != NetKind::Hex ? 0.5 * m.square.nodeDiameter : 0.0);
    const double rRope = 0.5 * supportDiameter, rPost = 0.5 * postNodeDiameter;
    if (!(shackleGap > rNet + rRope))
        throw UsageError("--shackle-gap must be > " + fmt(rNet + rRope) +
                         ", a net node's radius plus a support rope node's radius (got " +
                         text("shackle-gap", shackleGap) + ")");
    if (!(sideGap() > rNet + rPost))
        throw UsageError("--post-gap must be > " + fmt(rNet + rPost) +
                         ", a net node's radius plus a post node's radius (got " + postGapText + ")");
}

void FenceParams::validateRopes(const ValueText& text) const {
    const double a = spanBond();
    const std::string bond = " the support rope's bond in a module span (--spacing / round(--spacing / "
                             "--rope-segment) = " + fmt(a) + " m)";
    const double clearance = 0.5 * (supportDiameter + postNodeDiameter);
    if (!(0.5 * a > clearance))
        throw UsageError("--rope-segment " + text("rope-segment", ropeSegment) + " gives" + bond +
                         ", too short for the rope and post node spheres (" + fmt(clearance) +
                         " m apart at least, twice)");
    if (!(bottomAnchorDistance >= a))
        throw UsageError("--bottom-anchor-distance must be >=" + bond + " (got " +
                         text("bottom-anchor-distance", bottomAnchorDistance) + ")");
    if (!(std::hypot(anchorDistance, height) >= a))
        throw UsageError("--anchor-distance must make the top rope's leg >=" + bond + " (got " +
                         text("anchor-distance", anchorDistance) + ")");
    const long legs = std::min(topLegBonds(), bottomLegBonds());
    if (brakes > legs)
        throw UsageError("--brakes must be <= " + std::to_string(legs) +
                         ", the bonds between a lateral anchor and the end post (got " + std::to_string(brakes) + ")");
    if (upslopeBrakes > upslopeBonds())
        throw UsageError("--upslope-brakes must be <= " + std::to_string(upslopeBonds()) +
                         ", the bonds of an upslope rope (got " + std::to_string(upslopeBrakes) + ")");
}

double Fence::estimateNodes(const FenceParams& p) {
    const CompoundParams m = p.module();
    double panel = 0;
    if (p.net != NetKind::Square) panel += HexPanel::estimateNodes(m.hex);
    if (p.net != NetKind::Hex) panel += SquarePanel::estimateNodes(m.square);
    const double a = p.spacing / bondsFor(p.spacing, p.ropeSegment);
    const double top = bondsFor(std::hypot(p.anchorDistance, p.height) - 0.5 * a, p.ropeSegment);
    const double bottom = bondsFor(p.bottomAnchorDistance - 0.5 * a, p.ropeSegment);
    const double span = bondsFor(p.spacing, p.ropeSegment);
    const double n = p.modules, posts = n + 1;
    const double upslope = bondsFor(p.upslopeLength(), p.ropeSegment);
    return n * panel + 4 + 2 * (top + bottom) + 2 * n * span + posts * (p.postElements + 1 + upslope);
}

NetModel Fence::panel() const {
    const CompoundParams cp = p_.module();
    switch (p_.net) {
        case NetKind::Hex: return HexPanel(cp.hex).build();
        case NetKind::Square: return SquarePanel(cp.square).build();
        case NetKind::Compound: return CompoundPanel(cp).build();
    }
    return NetModel();
}

FenceModel Fence::build() const {
    FenceModel f;
    NetModel& m = f.model;
    const int N = p_.modules, P = p_.postElements;
    const double H = p_.height, s = p_.spacing;
    constexpr int kTop = 1, kBottom = 2, kFirstPost = 3;
    auto addNode = [&](const Eigen::Vector3d& x, int type, double d, int mol) {
        m.nodes.push_back({x, type, d, 0.0, mol});
        return int(m.nodes.size()) - 1;
    };
    auto chain = [&](const std::vector<int>& atoms, auto bondType) {
        for (size_t k = 0; k + 1 < atoms.size(); ++k) m.bonds.push_back({bondType(k), atoms[k], atoms[k + 1]});
    };

    // Net modules: the panel moved into the plane of the posts, (x, y, z) -> (x_c + x, z, H/2 + y).
    f.panel = this->panel();
    const NetModel& panel = f.panel;
    f.panelNodes = long(panel.nodes.size());
    f.panelBonds = long(panel.bonds.size());
    for (int k = 0; k < N; ++k) {
        const double xc = p_.postX(k) + 0.5 * s;
        f.moduleCentres.push_back({xc, 0.0, 0.5 * H});
        const int shift = int(m.nodes.size());
        for (const Node& n : panel.nodes) {
            const int id = addNode({xc + n.x.x(), n.x.z(), 0.5 * H + n.x.y()}, n.type, n.diameter, n.molecule);
            m.nodes[id].mass = n.mass;
            f.netMass += n.mass;
            // Edge types of doc/file_formats.md: 3/4 and 7/8 lie on the top or bottom edge (corners
            // included), 2 and 6 on a side next to a post.
            const int t = n.type;
            if (t == atype::HexEdgeY || t == atype::HexCorner || t == atype::SqEdgeY || t == atype::SqCorner)
                f.shackles.push_back({id, n.x.y() > 0 ? kTop : kBottom});
            else if (p_.sideShackles && (t == atype::HexEdgeX || t == atype::SqEdgeX))
                f.shackles.push_back({id, kFirstPost + (n.x.x() < 0 ? k : k + 1)});
        }
        for (const Bond& b : panel.bonds) m.bonds.push_back({b.type, b.a + shift, b.b + shift});
    }

    // Posts: base (hinge) to head, P beam elements.
    std::vector<FenceRope> postRopes;
    for (int i = 0; i <= N; ++i) {
        std::vector<int> atoms;
        for (int e = 0; e <= P; ++e) {
            const int type = e == 0 ? ftype::PostBase : e == P ? ftype::PostHead : ftype::Post;
            atoms.push_back(addNode({p_.postX(i), 0.0, H * e / P}, type, p_.postNodeDiameter, fmol::Posts));
        }
        chain(atoms, [](size_t) { return fbond::Post; });
        f.postBases.push_back(atoms.front());
        f.postHeads.push_back(atoms.back());
        postRopes.push_back({kFirstPost + i, "post_" + std::to_string(i), "post", atoms});
    }

    // Support ropes: lateral anchor, leg to half a span bond before the end post, the horizontal
    // part with the post heads (bases) at bond midpoints, the mirrored leg, the other anchor. The
    // right half is the exact mirror image of the left one.
    const double a = p_.spanBond();
    const long span = p_.spanBonds();
    const double x0 = p_.postX(0);
    auto supportRope = [&](const std::string& level, double z, double anchorDistance, long leg, int mol) {
        const Eigen::Vector3d anchor(x0 - anchorDistance, 0.0, 0.0), post(x0, 0.0, z);
        const Eigen::Vector3d legEnd = post - 0.5 * a * (post - anchor).normalized();
        std::vector<Eigen::Vector3d> left{anchor};
        for (long j = 1; j <= leg; ++j) left.push_back(anchor + (legEnd - anchor) * (double(j) / leg));
        const long half = (N * span) / 2;
        for (long k = 0; k < half; ++k) left.push_back({x0 + (k + 0.5) * a, 0.0, z});
        std::vector<int> atoms;
        const double d = p_.supportDiameter;
        atoms.push_back(addNode(left[0], ftype::Anchor, d, fmol::Anchors));
        for (size_t k = 1; k < left.size(); ++k) atoms.push_back(addNode(left[k], ftype::SupportRope, d, mol));
        if ((N * span) % 2 == 1) atoms.push_back(addNode({0.0, 0.0, z}, ftype::SupportRope, d, mol));
        for (size_t k = left.size() - 1; k >= 1; --k)
            atoms.push_back(addNode(mirrorX(left[k]), ftype::SupportRope, d, mol));
        atoms.push_back(addNode(mirrorX(left[0]), ftype::Anchor, d, fmol::Anchors));
        const size_t bonds = atoms.size() - 1;
        const size_t brakes = size_t(p_.brakes);
        chain(atoms, [&](size_t k) { return k < brakes || k >= bonds - brakes ? fbond::Brake : fbond::SupportRope; });
        const std::string rope = level + "_support";
        f.anchors.push_back({atoms.front(), "lateral_left_" + level, rope});
        f.anchors.push_back({atoms.back(), "lateral_right_" + level, rope});
        return atoms;
    };
    f.ropes.push_back({kTop, "top_support", "support_rope",
                       supportRope("top", H, p_.anchorDistance, p_.topLegBonds(), fmol::TopRope)});
    f.ropes.push_back({kBottom, "bottom_support", "support_rope",
                       supportRope("bottom", 0.0, p_.bottomAnchorDistance, p_.bottomLegBonds(), fmol::BottomRope)});
    // The rope runs past each post base (a shackle) and through a guide on each post head: a
    // shackle too, or, clamped, the head joins the rope: the rope bond it sits on is split there.
    for (int i = 0; i <= N; ++i) {
        f.shackles.push_back({f.postBases[i], kBottom});
        if (!p_.clampHeads) {
            f.shackles.push_back({f.postHeads[i], kTop});
            continue;
        }
        // the rope bond nearest the head (its midpoint, or at an end post the bond where the
        // rope turns down to the anchor) becomes two bonds through the head
        std::vector<int>& top = f.ropes.front().atoms;
        const Eigen::Vector3d head = m.nodes[f.postHeads[i]].x;
        size_t best = 0;
        double dmin = 1e300;
        for (size_t k = 0; k + 1 < top.size(); ++k) {
            const double d = distanceToSegment(head, m.nodes[top[k]].x, m.nodes[top[k + 1]].x);
            if (d < dmin) { dmin = d; best = k; }
        }
        size_t bond = m.bonds.size();
        for (size_t j = 0; j < m.bonds.size(); ++j)
            if (m.bonds[j].a == top[best] && m.bonds[j].b == top[best + 1]) bond = j;
        const int type = m.bonds[bond].type;
        m.bonds[bond].b = f.postHeads[i];
        m.bonds.push_back({type, f.postHeads[i], top[best + 1]});
        top.insert(top.begin() + long(best) + 1, f.postHeads[i]);
    }
    if (p_.sideShackles) f.ropes.insert(f.ropes.end(), postRopes.begin(), postRopes.end());

    // The leaned fence: everything so far turns about the ground line (the lateral anchors stay);
    // the upslope ropes below then run from the leaned heads to anchors on the slope.
    if (p_.postTilt != 0.0) {
        for (Node& n : m.nodes) n.x = p_.lean(n.x);
        for (auto& c : f.moduleCentres) c = p_.lean(c);
    }

    // Upslope ropes: post head to its anchor, brakes next to the anchor, hanging with their
    // installed sag below the chord (the bonds' initial lengths, hence the rope's length, follow);
    // where the sag would take it under the ground it lies on it, as the bottom rope does (the
    // deck's ground plane is the support rope's radius below z = 0).
    const long mu = p_.upslopeBonds();
    const double ground = std::max(0.0, 0.5 * (p_.upslopeDiameter - p_.supportDiameter));
    for (int i = 0; i <= N; ++i) {
        const Eigen::Vector3d head = m.nodes[f.postHeads[i]].x;
        const Eigen::Vector3d anchor(p_.postX(i), p_.upslopeDistance, p_.upslopeHeight);
        const double sag = p_.upslopeSag * (anchor - head).norm();
        std::vector<int> atoms{f.postHeads[i]};
        for (long j = 1; j <= mu; ++j) {
            const double s = double(j) / mu;
            Eigen::Vector3d x = head + (anchor - head) * s - Eigen::Vector3d::UnitZ() * (4.0 * sag * s * (1.0 - s));
            if (j < mu) x.z() = std::max(x.z(), ground);
            atoms.push_back(addNode(x, j == mu ? ftype::Anchor : ftype::UpslopeRope, p_.upslopeDiameter,
                                    j == mu ? fmol::Anchors : fmol::Upslope));
        }
        const size_t firstBrake = size_t(mu - p_.upslopeBrakes);
        chain(atoms, [&](size_t k) { return k >= firstBrake ? fbond::UpslopeBrake : fbond::Upslope; });
        f.anchors.push_back({atoms.back(), "upslope_" + std::to_string(i), "upslope_" + std::to_string(i)});
        f.upslopeRopes.push_back(atoms);
    }

    // Masses of ropes and posts, lumped: half of each bond to each of its nodes.
    const double muSupport = p_.ropeMass(p_.supportDiameter), muUpslope = p_.ropeMass(p_.upslopeDiameter);
    const double muPost = p_.density * p_.postArea;
    for (const Bond& b : m.bonds) {
        double mu = 0, *total = nullptr;
        switch (b.type) {
            case fbond::SupportRope: case fbond::Brake: mu = muSupport; total = &f.supportMass; break;
            case fbond::Upslope: case fbond::UpslopeBrake: mu = muUpslope; total = &f.upslopeMass; break;
            case fbond::Post: mu = muPost; total = &f.postMass; break;
            default: continue;  // net bonds: the panels lumped their own mass
        }
        const double mass = mu * m.bondLength(b);
        m.nodes[b.a].mass += 0.5 * mass;
        m.nodes[b.b].mass += 0.5 * mass;
        *total += mass;
    }

    std::sort(f.shackles.begin(), f.shackles.end(), [](const Shackle& x, const Shackle& y) { return x.atom < y.atom; });
    for (const Shackle& sh : f.shackles) {
        const FenceRope* rope = nullptr;
        for (const auto& r : f.ropes)
            if (r.id == sh.rope) rope = &r;
        double best = 1e300;
        for (size_t k = 0; k + 1 < rope->atoms.size(); ++k)
            best = std::min(best, distanceToSegment(m.nodes[sh.atom].x, m.nodes[rope->atoms[k]].x,
                                                    m.nodes[rope->atoms[k + 1]].x));
        f.shackleMaxDistance = std::max(f.shackleMaxDistance, best);
    }
    return f;
}

}  // namespace wirenet
