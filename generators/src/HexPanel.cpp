#include "HexPanel.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace wirenet {

double HexParams::swLength() const { return std::hypot(0.5 * axisDistance, rise); }

void HexParams::validate(const ValueText& text, const SideNames& sides) const {
    requireLess("--axis-distance", axisDistance, sides.width, width);
    requireLess("--twist-length + --rise", twistLength + rise, sides.height + "/2", 0.5 * height);
    if (!(snapFraction < 0.5)) throw UsageError("--snap must be < 0.5 (got " + text("snap", snapFraction) + ")");
}

double HexParams::snapTolerance() const { return snapFraction * std::min(twistLength, swLength()); }

const char* placementName(Placement p) {
    switch (p) {
        case Placement::Twist: return "twist";
        case Placement::Wire: return "wire";
        case Placement::Corner: return "corner";
        case Placement::Symmetric: return "symmetric";
    }
    return "twist";
}

bool parsePlacement(const std::string& text, Placement& p) {
    static const Placement all[] = {Placement::Twist, Placement::Wire, Placement::Corner, Placement::Symmetric};
    return parseByName(text, all, placementName, p);
}

const char* selvedgeName(Selvedge s) {
    switch (s) {
        case Selvedge::Loop: return "loop";
        case Selvedge::None: return "none";
        case Selvedge::Sides: return "sides";
    }
    return "loop";
}

bool parseSelvedge(const std::string& text, Selvedge& s) {
    static const Selvedge all[] = {Selvedge::Loop, Selvedge::None, Selvedge::Sides};
    return parseByName(text, all, selvedgeName, s);
}

Eigen::Vector2d HexParams::latticeOrigin() const {
    switch (placement) {
        case Placement::Twist: return {0.0, 0.0};
        // The SW bond from the top of twist (0, 0) to the bottom of twist (1, 1) has its
        // midpoint at (a/4, (t + h)/2) from the twist centre: put that midpoint on the origin.
        case Placement::Wire: return {-0.25 * axisDistance, -0.5 * rowPitch()};
        // The bottom end of twist (0, 0) on the lower-left corner (YADE's startAtCorner).
        case Placement::Corner: return {-0.5 * width, -0.5 * height + 0.5 * twistLength};
        // Row 0 from the lower edge upwards, as Corner; in x the twist columns x = q a/2 stay
        // symmetric about 0 and the odd rows hold the outermost one in the panel, q = m (or
        // within the snap tolerance of its edge, which puts it on the edge: W = m a). Row 0
        // holds the columns of the other parity: its first twist at (1 - m) a/2, which is
        // -W/2 + a/2 for W = m a (YADE's startAtCorner=False, isSymmetric=True).
        case Placement::Symmetric: {
            const double half = 0.5 * axisDistance;
            const double m = std::floor((0.5 * width + snapTolerance()) / half);
            return {(1 - m) * half, -0.5 * height + 0.5 * twistLength};
        }
    }
    return {0.0, 0.0};
}

namespace {

// The lattice origin moved by whole lattice periods ((a/2, t + h) from row to row, a along a
// row) to within half a row pitch and a/2 of the panel centre, so that the index ranges of
// build() and estimateNodes() cover the panel for every placement. Twist: (0, 0) unchanged.
Eigen::Vector2d reducedOrigin(const HexParams& p) {
    Eigen::Vector2d o = p.latticeOrigin();
    const double rows = std::round(o.y() / p.rowPitch());
    o -= rows * Eigen::Vector2d(0.5 * p.axisDistance, p.rowPitch());
    o.x() -= std::round(o.x() / p.axisDistance) * p.axisDistance;
    return o;
}

// Builds the clipped graph: lattice nodes (snapped), boundary crossings (merged), bonds.
class ClippedGraph {
public:
    ClippedGraph(double X, double Y, double eps, Selvedge selvedge)
        : X_(X), Y_(Y), eps_(eps), selvedge_(selvedge) {}

    // Lattice node; coordinates within eps of an edge line are moved onto it so that
    // no sliver bond appears between a node and the edge.
    int addLatticeNode(Eigen::Vector2d p) {
        p.x() = snap(p.x(), X_);
        p.y() = snap(p.y(), Y_);
        const bool inside = std::abs(p.x()) <= X_ && std::abs(p.y()) <= Y_;
        pos_.push_back(p);
        alive_.push_back(inside);
        if (inside && onBoundary(p)) boundary_.push_back(int(pos_.size()) - 1);
        return int(pos_.size()) - 1;
    }

    // Corner nodes close the selvedge loop exactly along the edges.
    void addCorners() {
        for (double sx : {-1.0, 1.0})
            for (double sy : {-1.0, 1.0}) boundaryNode({sx * X_, sy * Y_});
    }

    // Adds the part of lattice segment i-j that lies inside the panel.
    void addSegment(int i, int j, int type) {
        const Eigen::Vector2d p = pos_[i], q = pos_[j];
        double t0, t1;
        if (!clip(p, q, t0, t1)) return;
        const int a = alive_[i] && t0 == 0 ? i : boundaryNode(onEdge(p + t0 * (q - p)));
        const int b = alive_[j] && t1 == 1 ? j : boundaryNode(onEdge(p + t1 * (q - p)));
        if (a == b) return;
        if (covered(pos_[a], pos_[b])) return;  // along an edge with a selvedge: it covers it
        if ((a != i || b != j) && (pos_[a] - pos_[b]).norm() < eps_) return;  // sliver
        if (!pairs_.insert({std::min(a, b), std::max(a, b)}).second) return;
        bonds_.push_back({type, a, b});
    }

    // Selvedge: consecutive boundary nodes around the perimeter, a closed loop (Loop), or only
    // the pairs of consecutive nodes on one x edge (Sides: from corner to corner along x = -W/2
    // and x = +W/2; the y edges bare).
    void addSelvedge(int type) {
        std::vector<int> ring = boundary_;
        std::sort(ring.begin(), ring.end(),
                  [&](int u, int v) { return perimeter(pos_[u]) < perimeter(pos_[v]); });
        for (size_t k = 0; k < ring.size(); ++k) {
            const int a = ring[k], b = ring[(k + 1) % ring.size()];
            if (selvedge_ == Selvedge::Sides && !sameXEdge(pos_[a], pos_[b])) continue;
            if (pairs_.insert({std::min(a, b), std::max(a, b)}).second) bonds_.push_back({type, a, b});
        }
    }

    // Nodes on no bond (a corner without a selvedge) are left out.
    NetModel toModel(const HexParams& hp) const {
        NetModel m;
        std::vector<char> bonded(pos_.size(), 0);
        for (const Bond& b : bonds_) bonded[b.a] = bonded[b.b] = 1;
        std::vector<int> newId(pos_.size(), -1);
        for (size_t i = 0; i < pos_.size(); ++i) {
            if (!alive_[i] || !bonded[i]) continue;
            newId[i] = int(m.nodes.size());
            const bool ex = std::abs(pos_[i].x()) == X_, ey = std::abs(pos_[i].y()) == Y_;
            const int type = ex && ey ? atype::HexCorner
                             : ex     ? atype::HexEdgeX
                             : ey     ? atype::HexEdgeY
                                      : atype::HexInterior;
            m.nodes.push_back({{pos_[i].x(), pos_[i].y(), hp.z}, type, hp.nodeDiameter, 0.0, hp.molecule});
        }
        for (const Bond& b : bonds_) m.bonds.push_back({b.type, newId[b.a], newId[b.b]});
        return m;
    }

private:
    double snap(double v, double L) const {
        if (std::abs(v - L) <= eps_) return L;
        if (std::abs(v + L) <= eps_) return -L;
        return v;
    }
    bool onBoundary(const Eigen::Vector2d& p) const {
        return std::abs(p.x()) == X_ || std::abs(p.y()) == Y_;
    }
    bool sameXEdge(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
        return std::abs(a.x()) == X_ && a.x() == b.x();
    }
    bool sameYEdge(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
        return std::abs(a.y()) == Y_ && a.y() == b.y();
    }
    // A lattice segment along an edge that carries a selvedge (which then replaces it).
    bool covered(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
        switch (selvedge_) {
            case Selvedge::Loop: return sameXEdge(a, b) || sameYEdge(a, b);
            case Selvedge::Sides: return sameXEdge(a, b);
            case Selvedge::None: return false;
        }
        return false;
    }
    // Puts a clipped point exactly on the edge line it was clipped against.
    Eigen::Vector2d onEdge(Eigen::Vector2d p) const {
        p.x() = std::clamp(p.x(), -X_, X_);
        p.y() = std::clamp(p.y(), -Y_, Y_);
        if (X_ - std::abs(p.x()) <= Y_ - std::abs(p.y()))
            p.x() = std::copysign(X_, p.x());
        else
            p.y() = std::copysign(Y_, p.y());
        return p;
    }
    // Reuses a boundary node closer than eps, else creates one (no sliver selvedge bonds).
    int boundaryNode(const Eigen::Vector2d& p) {
        for (int b : boundary_)
            if ((pos_[b] - p).norm() < eps_) return b;
        pos_.push_back(p);
        alive_.push_back(true);
        boundary_.push_back(int(pos_.size()) - 1);
        return int(pos_.size()) - 1;
    }
    // Liang-Barsky clipping of p + t (q - p), t in [0, 1], to the panel.
    bool clip(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double& t0, double& t1) const {
        const Eigen::Vector2d d = q - p;
        t0 = 0;
        t1 = 1;
        auto edge = [&](double den, double num) {  // constraint: den * t <= num
            if (den == 0) return num >= 0;
            const double r = num / den;
            if (den < 0) {
                if (r > t1) return false;
                t0 = std::max(t0, r);
            } else {
                if (r < t0) return false;
                t1 = std::min(t1, r);
            }
            return true;
        };
        return edge(-d.x(), X_ + p.x()) && edge(d.x(), X_ - p.x()) && edge(-d.y(), Y_ + p.y()) &&
               edge(d.y(), Y_ - p.y()) && t0 <= t1;
    }
    // Arc length along the perimeter, counter-clockwise from (-X, -Y).
    double perimeter(const Eigen::Vector2d& p) const {
        const double W = 2 * X_, H = 2 * Y_;
        if (p.y() == -Y_) return p.x() + X_;
        if (p.x() == X_) return W + p.y() + Y_;
        if (p.y() == Y_) return W + H + X_ - p.x();
        return 2 * W + H + Y_ - p.y();
    }

    double X_, Y_, eps_;
    Selvedge selvedge_;
    std::vector<Eigen::Vector2d> pos_;
    std::vector<char> alive_;
    std::vector<int> boundary_;
    std::vector<Bond> bonds_;
    std::set<std::pair<int, int>> pairs_;
};

}  // namespace

double HexPanel::estimateNodes(const HexParams& p) {
    // Same K and Q as build(): two nodes per twist, twists on half of the (2K+1) x (2Q+1) slots.
    const double pitch = p.rowPitch(), half = 0.5 * p.axisDistance;
    const double K = std::ceil((0.5 * p.height + pitch) / pitch) + 1;
    const double Q = std::ceil(0.5 * p.width / half) + 2;
    return (2 * K + 1) * (2 * Q + 1);
}

NetModel HexPanel::build() const {
    const double X = 0.5 * p_.width, Y = 0.5 * p_.height;
    const double half = 0.5 * p_.axisDistance, pitch = p_.rowPitch(), t = p_.twistLength;
    ClippedGraph g(X, Y, p_.snapTolerance(), p_.selvedge);
    const Eigen::Vector2d o = reducedOrigin(p_);

    // Row k: twists centred at y = k * pitch + o.y; twist columns at x = q * half + o.x with
    // q - k even. Twist placement: o = 0, row 0 on the x axis, the panel mirror symmetric.
    // Symmetric placement: o.x is a whole number s of half columns (0 or +-1, up to the rounding
    // of the reduction): x = (q + s) * half, so that the panel is mirror symmetric bit for bit
    // (the middle column exactly on x = 0).
    const bool columns = p_.placement == Placement::Symmetric;
    const long s = columns ? std::lround(o.x() / half) : 0;
    const int K = int(std::ceil((Y + pitch) / pitch)) + 1;
    const int Q = int(std::ceil(X / half)) + 2;
    const int nq = 2 * Q + 1;
    auto slot = [&](int k, int q) { return size_t(k + K) * nq + size_t(q + Q); };
    std::vector<int> bottom(size_t(2 * K + 1) * nq, -1), top(bottom.size(), -1);
    for (int k = -K; k <= K; ++k)
        for (int q = -Q; q <= Q; ++q) {
            if ((q - k) % 2 != 0) continue;
            const double x = columns ? double(q + s) * half : q * half + o.x(), yc = k * pitch + o.y();
            bottom[slot(k, q)] = g.addLatticeNode({x, yc - 0.5 * t});
            top[slot(k, q)] = g.addLatticeNode({x, yc + 0.5 * t});
        }
    if (p_.selvedge != Selvedge::None) g.addCorners();
    for (int k = -K; k <= K; ++k)
        for (int q = -Q; q <= Q; ++q) {
            const int up = top[slot(k, q)];
            if (up < 0) continue;
            g.addSegment(bottom[slot(k, q)], up, btype::DT);
            if (k == K) continue;
            // SW bonds from the top of this twist to the bottoms of the two twists above.
            for (int dq : {-1, 1})
                if (std::abs(q + dq) <= Q) g.addSegment(up, bottom[slot(k + 1, q + dq)], btype::SW);
        }
    if (p_.selvedge != Selvedge::None) g.addSelvedge(btype::Selvedge);

    NetModel m = g.toModel(p_);
    const double mass = nodeMass(m);
    for (auto& n : m.nodes) n.mass = mass;
    return m;
}

std::map<int, double> HexPanel::lengthPerType(const NetModel& m) {
    std::map<int, double> len;
    for (const auto& b : m.bonds) len[b.type] += m.bondLength(b);
    return len;
}

double HexPanel::nodeMass(const NetModel& m) const {
    const double n = double(m.nodes.size());
    switch (p_.massRule) {
        case HexParams::Mass::PerNode: return p_.nodeMass;
        case HexParams::Mass::Areal: return p_.arealMass * p_.width * p_.height / n;
        case HexParams::Mass::FromWire: {
            // Steel wire lumped evenly: a DT bond holds two wires, selvedge has its own diameter.
            auto len = lengthPerType(m);
            const double aw = M_PI * 0.25 * p_.wireDiameter * p_.wireDiameter;
            const double as = M_PI * 0.25 * p_.selvedgeDiameter * p_.selvedgeDiameter;
            const double v = aw * (2 * len[btype::DT] + len[btype::SW]) + as * len[btype::Selvedge];
            return kSteelDensity * v / n;
        }
    }
    return p_.nodeMass;
}

Json HexPanel::cellJson() const {
    Json c = Json::object();
    c.set("axis_distance", p_.axisDistance).set("twist_length", p_.twistLength).set("rise", p_.rise);
    c.set("sw_length", p_.swLength()).set("row_pitch", p_.rowPitch());
    c.set("opening_height", p_.twistLength + 2 * p_.rise);
    c.set("nominal", "100 x 80 mm (paper, Pol et al. 2017); see doc/wirenet-gen.md");
    c.set("snap_tolerance", p_.snapTolerance());
    Json origin = Json::array();
    origin.push(p_.latticeOrigin().x()).push(p_.latticeOrigin().y());
    c.set("placement", placementName(p_.placement)).set("lattice_origin", origin);
    c.set("selvedge", selvedgeName(p_.selvedge));
    return c;
}

namespace {

// The hex layer alone (molecule 1) of a compound or fence model, for the per-node mass rule.
NetModel hexLayer(const NetModel& m) {
    NetModel h;
    std::vector<int> id(m.nodes.size(), -1);
    for (size_t i = 0; i < m.nodes.size(); ++i)
        if (m.nodes[i].molecule == 1) { id[i] = int(h.nodes.size()); h.nodes.push_back(m.nodes[i]); }
    for (const auto& b : m.bonds)
        if (id[b.a] >= 0 && id[b.b] >= 0 && b.type != btype::Rope) h.bonds.push_back({b.type, id[b.a], id[b.b]});
    return h;
}

}  // namespace

void HexPanel::describe(NetDescription& d, const NetModel& m) const {
    d.cells.set("hex", cellJson());
    d.wires.set("DT", wireJson(p_.wireDiameter, "two twisted wires"));
    d.wires.set("SW", wireJson(p_.wireDiameter)).set("selvedge", wireJson(p_.selvedgeDiameter));
    Json n = nodeJson(p_.nodeDiameter, nodeMass(hexLayer(m)));
    n.set("mass_rule", p_.massRule == HexParams::Mass::FromWire ? "steel wire lumped evenly"
                       : p_.massRule == HexParams::Mass::Areal  ? "areal mass x area / nodes"
                                                                : "fixed per node");
    d.node.set("hex", n);
}

}  // namespace wirenet
