// Geometry invariants of the generators: closed-form counts, bond-length histograms,
// symmetry, exact edges, masses, STL closure/orientation/volume, mass properties.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "Beam.h"
#include "CompoundPanel.h"
#include "Fence.h"
#include "HexPanel.h"
#include "MeshWriter.h"
#include "Shapes.h"
#include "SquarePanel.h"
#include "StlWriter.h"

using namespace wirenet;

static int failures = 0, checks = 0;
#define CHECK(cond, ...)                                                      \
    do {                                                                      \
        ++checks;                                                             \
        if (!(cond)) {                                                        \
            ++failures;                                                       \
            std::printf("FAIL %s:%d: %s | ", __FILE__, __LINE__, #cond);      \
            std::printf(__VA_ARGS__);                                         \
            std::printf("\n");                                                \
        }                                                                     \
    } while (0)
#define CHECK_EQ(a, b) CHECK((a) == (b), "%s = %ld, expected %ld", #a, long(a), long(b))
#define CHECK_NEAR(a, b, tol) CHECK(std::abs((a) - (b)) <= (tol), "%s = %.15g, expected %.15g", #a, double(a), double(b))

// ---- helpers --------------------------------------------------------------------------------

static long countType(const NetModel& m, int t) { return m.atomsPerType()[t]; }
static long countBonds(const NetModel& m, int t) { return m.bondsPerType()[t]; }

static double minNodeDistance(const NetModel& m) {
    double d = 1e300;
    for (size_t i = 0; i < m.nodes.size(); ++i)
        for (size_t j = i + 1; j < m.nodes.size(); ++j) d = std::min(d, (m.nodes[i].x - m.nodes[j].x).norm());
    return d;
}

// Node set and bond set are invariant under x -> sx x, y -> sy y (types preserved).
static bool symmetric(const NetModel& m, double sx, double sy) {
    auto key = [](Eigen::Vector3d x) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.9f %.9f %.9f", x.x() + 0.0, x.y() + 0.0, x.z() + 0.0);
        return std::string(buf);
    };
    std::map<std::string, int> index;
    for (size_t i = 0; i < m.nodes.size(); ++i) index[key(m.nodes[i].x)] = int(i);
    std::vector<int> image(m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        Eigen::Vector3d x = m.nodes[i].x;
        x.x() *= sx;
        x.y() *= sy;
        auto it = index.find(key(x));
        if (it == index.end() || m.nodes[it->second].type != m.nodes[i].type) return false;
        image[i] = it->second;
    }
    std::set<std::tuple<int, int, int>> bonds;
    for (const auto& b : m.bonds) bonds.insert({b.type, std::min(b.a, b.b), std::max(b.a, b.b)});
    for (const auto& b : m.bonds) {
        const int a = image[b.a], c = image[b.b];
        if (!bonds.count({b.type, std::min(a, c), std::max(a, c)})) return false;
    }
    return true;
}
static bool mirrorSymmetric(const NetModel& m, int axis) {
    return axis == 0 ? symmetric(m, -1, 1) : symmetric(m, 1, -1);
}

// Edge types lie exactly on their edges, interior types strictly inside.
static bool edgesExact(const NetModel& m, double X, double Y, int interior, int ex, int ey, int corner) {
    for (const auto& n : m.nodes) {
        const double ax = std::abs(n.x.x()), ay = std::abs(n.x.y());
        if (ax > X || ay > Y) return false;
        const int expected = ax == X && ay == Y ? corner : ax == X ? ex : ay == Y ? ey : interior;
        if (n.type != expected) return false;
    }
    return true;
}

static bool everyNodeBonded(const NetModel& m) {
    std::vector<int> deg(m.nodes.size(), 0);
    for (const auto& b : m.bonds) {
        if (b.a == b.b) return false;
        ++deg[b.a];
        ++deg[b.b];
    }
    for (int d : deg)
        if (d == 0) return false;
    return true;
}

static bool noDuplicateBonds(const NetModel& m) {
    std::set<std::pair<int, int>> s;
    for (const auto& b : m.bonds)
        if (!s.insert({std::min(b.a, b.b), std::max(b.a, b.b)}).second) return false;
    return true;
}

// Lengths of one bond family, rounded to 1e-9 m, with their counts.
static std::map<long, long> histogram(const NetModel& m, int type) {
    std::map<long, long> h;
    for (const auto& b : m.bonds)
        if (b.type == type) ++h[std::lround(m.bondLength(b) * 1e9)];
    return h;
}
static long nm(double len) { return std::lround(len * 1e9); }

// ---- hexagonal panel ------------------------------------------------------------------------

// Closed formulas (doc/wirenet-gen.md). Half-columns q = -Q..Q at x = q a/2, rows k at
// y = k (t + h); c(k) = number of twists in row k = #{q in [-Q, Q], q = k mod 2}.
struct HexCounts {
    long nodes, dt, sw, selvedge, edgeX, edgeY, corners;
};
static long twistsInRow(long Q, long k) { return ((Q - k) % 2 == 0) ? Q + 1 : Q; }
static long rowsOfParity(long n, long parity) {  // #{k in [-(n-1), n-1] : k = parity mod 2}
    long c = 0;
    for (long k = -(n - 1); k <= n - 1; ++k) c += (((k - parity) % 2) == 0);
    return c;
}
// Family A: W = (2Q+1) a/2 (x-edges cut single wires at mid-length), H = 2 n (t+h) - t
// (y-edges through the twist ends of rows +-n).
static HexCounts hexFamilyA(long Q, long n) {
    const long even = rowsOfParity(n, 0), odd = rowsOfParity(n, 1);
    const long S = even * twistsInRow(Q, 0) + odd * twistsInRow(Q, 1), cn = twistsInRow(Q, n);
    return {2 * S + 2 * cn + 4 * n + 4, S, 2 * n * (2 * Q + 2), 2 * cn + 4 * n + 4, 4 * n, 2 * cn, 4};
}
// Family B: W = 2Q a/2 (x-edges through twist columns +-Q), H as in family A.
static HexCounts hexFamilyB(long Q, long n) {
    const long even = rowsOfParity(n, 0), odd = rowsOfParity(n, 1);
    const long S = even * twistsInRow(Q, 0) + odd * twistsInRow(Q, 1), cn = twistsInRow(Q, n);
    const long RQ = rowsOfParity(n, Q % 2);
    const bool cornerOnLattice = ((n - Q) % 2) == 0;
    const long added = cornerOnLattice ? 0 : 4;
    return {2 * S + 2 * cn + added,
            S - 2 * RQ,
            2 * n * 2 * Q,
            2 * cn + 4 * RQ + added,
            4 * RQ,
            2 * cn - (cornerOnLattice ? 4 : 0),
            4};
}

static void checkHexCounts(const NetModel& m, const HexCounts& c, const char* label) {
    std::printf("  hex %-28s atoms %6zu bonds %6zu\n", label, m.nodes.size(), m.bonds.size());
    CHECK_EQ(long(m.nodes.size()), c.nodes);
    CHECK_EQ(countBonds(m, btype::DT), c.dt);
    CHECK_EQ(countBonds(m, btype::SW), c.sw);
    CHECK_EQ(countBonds(m, btype::Selvedge), c.selvedge);
    CHECK_EQ(countType(m, atype::HexEdgeX), c.edgeX);
    CHECK_EQ(countType(m, atype::HexEdgeY), c.edgeY);
    CHECK_EQ(countType(m, atype::HexCorner), c.corners);
}

static void checkHexInvariants(const NetModel& m, const HexParams& p) {
    const double X = p.width / 2, Y = p.height / 2;
    CHECK(edgesExact(m, X, Y, 1, 2, 3, 4), "edge/corner nodes exactly on the edges");
    if (p.placement == Placement::Twist) {
        CHECK(mirrorSymmetric(m, 0), "mirror symmetry x -> -x");
        CHECK(mirrorSymmetric(m, 1), "mirror symmetry y -> -y");
    }
    if (p.placement == Placement::Wire) CHECK(symmetric(m, -1, -1), "point symmetry (x, y) -> (-x, -y)");
    if (p.placement == Placement::Symmetric) CHECK(mirrorSymmetric(m, 0), "symmetric: mirror symmetry x -> -x");
    CHECK(everyNodeBonded(m), "every node has a bond");
    CHECK(noDuplicateBonds(m), "no duplicate bonds");
    CHECK(minNodeDistance(m) >= p.snapTolerance() - 1e-12, "duplicate or too close nodes: %g",
          minNodeDistance(m));
    // Lattice bonds never exceed their nominal length (+ the snap move); none is a sliver.
    for (const auto& b : m.bonds) {
        const double len = m.bondLength(b);
        const double nominal = b.type == btype::DT ? p.twistLength : b.type == btype::SW ? p.swLength() : 1e9;
        CHECK(len >= p.snapTolerance() - 1e-12 && len <= nominal + p.snapTolerance() + 1e-12,
              "bond type %d length %g", b.type, len);
        // Bonds between interior nodes have exactly the cell geometry.
        if (m.nodes[b.a].type == 1 && m.nodes[b.b].type == 1 && b.type != btype::Selvedge)
            CHECK(std::abs(len - nominal) < 1e-12, "interior bond type %d length %g", b.type, len);
    }
    // Selvedge. Loop: a closed loop, every boundary node on exactly two selvedge bonds. Sides:
    // along the x edges only, from corner to corner (a corner on one, every other x-edge node
    // on two), no y-edge node on any. None: no selvedge bond.
    std::map<int, int> selv;
    for (const auto& b : m.bonds)
        if (b.type == btype::Selvedge) { ++selv[b.a]; ++selv[b.b]; }
    long boundary = 0, xEdge = 0;
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const int type = m.nodes[i].type, n = selv[int(i)];
        if (type == atype::HexInterior) continue;
        ++boundary;
        xEdge += type == atype::HexEdgeX || type == atype::HexCorner;
        const int want = p.selvedge == Selvedge::Loop    ? 2
                         : p.selvedge == Selvedge::None  ? 0
                         : type == atype::HexCorner      ? 1
                         : type == atype::HexEdgeX       ? 2
                                                         : 0;
        CHECK(n == want, "selvedge %s: boundary node %zu (type %d) has %d selvedge bonds, not %d",
              selvedgeName(p.selvedge), i, type, n, want);
    }
    const long expected = p.selvedge == Selvedge::Loop ? boundary : p.selvedge == Selvedge::Sides ? xEdge - 2 : 0;
    CHECK_EQ(countBonds(m, btype::Selvedge), expected);
}

static void testHex() {
    std::printf("hex panels\n");
    HexParams base;
    const double a = base.axisDistance, t = base.twistLength, pitch = base.rowPitch();
    // Family A, several sizes (the first is the paper's 3 m x 3 m default).
    const std::vector<std::pair<long, long>> A = {{37, 19}, {12, 6}, {20, 4}, {5, 3}, {24, 10}, {7, 2}};
    for (auto [Q, n] : A) {
        HexParams p;
        p.width = (2 * Q + 1) * a / 2;
        p.height = 2 * n * pitch - t;
        const NetModel m = HexPanel(p).build();
        char label[64];
        std::snprintf(label, sizeof label, "A %.2f x %.2f (Q=%ld n=%ld)", p.width, p.height, Q, n);
        checkHexCounts(m, hexFamilyA(Q, n), label);
        checkHexInvariants(m, p);
        // Histogram: every DT is a full twist; SW are full or cut exactly at mid-length.
        const auto dt = histogram(m, btype::DT), sw = histogram(m, btype::SW);
        CHECK(dt.size() == 1 && dt.count(nm(t)), "DT histogram has %zu bins", dt.size());
        CHECK(sw.size() == 2, "SW histogram has %zu bins", sw.size());
        CHECK_EQ(sw.count(nm(p.swLength())) ? sw.at(nm(p.swLength())) : 0, 4 * n * Q);
        CHECK_EQ(sw.count(nm(p.swLength() / 2)) ? sw.at(nm(p.swLength() / 2)) : 0, 4 * n);
    }
    const std::vector<std::pair<long, long>> B = {{30, 8}, {25, 5}, {12, 7}, {9, 4}};
    for (auto [Q, n] : B) {
        HexParams p;
        p.width = Q * a;
        p.height = 2 * n * pitch - t;
        const NetModel m = HexPanel(p).build();
        char label[64];
        std::snprintf(label, sizeof label, "B %.2f x %.2f (Q=%ld n=%ld)", p.width, p.height, Q, n);
        checkHexCounts(m, hexFamilyB(Q, n), label);
        checkHexInvariants(m, p);
        const auto dt = histogram(m, btype::DT), sw = histogram(m, btype::SW);
        CHECK(dt.size() == 1 && sw.size() == 1, "B: only full-length DT and SW bonds");
    }
    // Default panel: the paper's numbers, and generic sizes keep the invariants.
    {
        HexParams p;
        const NetModel m = HexPanel(p).build();
        CHECK_EQ(long(m.nodes.size()), 2930);
        CHECK_NEAR(m.totalMass(), 2930 * 0.0039, 1e-12);
        CHECK(std::abs(p.swLength() - 0.0565685424949238) < 1e-15, "SW length %g", p.swLength());
        double minBond = 1e9;
        for (const auto& b : m.bonds) minBond = std::min(minBond, m.bondLength(b));
        CHECK(minBond > p.nodeDiameter, "no bond shorter than the node diameter (%g)", minBond);
    }
    for (auto [W, H] : std::vector<std::pair<double, double>>{{2.5, 1.7}, {3.13, 2.91}, {1.0, 1.0}, {4.4, 2.2}}) {
        HexParams p;
        p.width = W;
        p.height = H;
        const NetModel m = HexPanel(p).build();
        std::printf("  hex generic %.2f x %.2f: atoms %zu bonds %zu\n", W, H, m.nodes.size(), m.bonds.size());
        checkHexInvariants(m, p);
    }
    // Masses: requested areal mass is met exactly; wire mass rule is the steel volume.
    {
        HexParams p;
        p.massRule = HexParams::Mass::Areal;
        p.arealMass = 1.3;
        const NetModel m = HexPanel(p).build();
        CHECK_NEAR(m.totalMass(), 1.3 * 9.0, 1e-9);
        p.massRule = HexParams::Mass::FromWire;
        const NetModel w = HexPanel(p).build();
        auto len = HexPanel::lengthPerType(w);
        const double aw = M_PI / 4 * 0.0027 * 0.0027, as = M_PI / 4 * 0.0034 * 0.0034;
        const double expect = 7850 * (aw * (2 * len[1] + len[2]) + as * len[3]);
        CHECK_NEAR(w.totalMass(), expect, 1e-9);
        CHECK(w.totalMass() / 9 > 1.0 && w.totalMass() / 9 < 1.6, "wire areal mass %g", w.totalMass() / 9);
    }
}

// ---- hex lattice placement ------------------------------------------------------------------

using Key = std::pair<long, long>;  // x, y in nm
static Key key2(double x, double y) { return {nm(x), nm(y)}; }

static std::set<Key> nodeSet(const NetModel& m) {
    std::set<Key> s;
    for (const auto& n : m.nodes) s.insert(key2(n.x.x(), n.x.y()));
    return s;
}

// Bond type and distance of the bond midpoint nearest to the origin.
static std::pair<int, double> nearestMidpoint(const NetModel& m) {
    std::pair<int, double> best{0, 1e300};
    for (const auto& b : m.bonds) {
        const double d = (0.5 * (m.nodes[b.a].x + m.nodes[b.b].x)).head<2>().norm();
        if (d < best.second) best = {b.type, d};
    }
    return best;
}

// YADE's pack.hexaNet convention with startAtCorner=True, corner at (-W/2, -H/2): row i
// (i = 0, 1, ...) spans y0 + i (t + h) .. y0 + i (t + h) + t; its twists lie at x0 + j a for even
// i and x0 + a/2 + j a for odd i. True if (x, y) is the end of such a twist (within 1e-9 m).
static bool onYadeLattice(const HexParams& p, double x, double y) {
    const double u = (x + p.width / 2) / (p.axisDistance / 2), pitch = p.rowPitch();
    const long i = std::lround(u);
    for (double end : {0.0, p.twistLength}) {
        const double v = (y + p.height / 2 - end) / pitch;
        const long j = std::lround(v);
        if (j >= 0 && (i - j) % 2 == 0 && std::abs(u - i) * p.axisDistance / 2 < 1e-9 &&
            std::abs(v - j) * pitch < 1e-9)
            return true;
    }
    return false;
}

// The nodes of a YADE hexaNet of ny rows (startAtCorner=True) on the panel, whose width is a
// multiple of a/2: every twist end with x <= W/2, and the four corners (hexaNet adds the corner
// spheres that no twist provides).
static std::set<Key> yadeNodes(const HexParams& p, long ny) {
    const double x0 = -p.width / 2, y0 = -p.height / 2, a = p.axisDistance;
    std::set<Key> s;
    for (long i = 0; i < ny; ++i)
        for (double x = x0 + (i % 2) * a / 2; x <= -x0 + 1e-9; x += a)
            for (double y : {y0 + i * p.rowPitch(), y0 + i * p.rowPitch() + p.twistLength}) s.insert(key2(x, y));
    for (double sx : {-1, 1})
        for (double sy : {-1, 1}) s.insert(key2(sx * x0, sy * y0));
    return s;
}

static void checkCornerPanel(const NetModel& m, const HexParams& p) {
    const double X = p.width / 2, Y = p.height / 2;
    bool first = false;
    long lattice = 0, clipped = 0;
    for (const auto& n : m.nodes) {
        if (n.x.x() == -X && std::abs(n.x.y() + Y - p.twistLength) < 1e-9) first = n.type == atype::HexEdgeX;
        // Off the right and top edges every node is a twist end of the YADE lattice.
        if (n.x.x() != X && n.x.y() != Y) ++(onYadeLattice(p, n.x.x(), n.x.y()) ? lattice : clipped);
    }
    CHECK(first, "corner: no twist from (-W/2, -H/2) to (-W/2, -H/2 + t)");
    CHECK(clipped == 0, "corner: %ld nodes off the YADE lattice (%ld on it)", clipped, lattice);
}

// --placement symmetric: the twist columns x = q a/2 symmetric about 0, the odd rows i (counted
// from the lower edge, row 0's bottom ends on it) on the columns q = m (mod 2), m a/2 the
// outermost column in the panel. True if (x, y) is the end of such a twist (within 1e-9 m).
static long outermostColumn(const HexParams& p) {
    return long(std::floor((p.width / 2 + p.snapTolerance()) / (p.axisDistance / 2)));
}
static bool onSymmetricLattice(const HexParams& p, double x, double y) {
    const double u = x / (p.axisDistance / 2), pitch = p.rowPitch();
    const long q = std::lround(u), m = outermostColumn(p);
    for (double end : {0.0, p.twistLength}) {
        const double v = (y + p.height / 2 - end) / pitch;
        const long i = std::lround(v);
        if (i >= 0 && (q - m + i + 1) % 2 == 0 && std::abs(u - q) * p.axisDistance / 2 < 1e-9 &&
            std::abs(v - i) * pitch < 1e-9)
            return true;
    }
    return false;
}

// Any size: mirror symmetric in x (checkHexInvariants), and off the x edges and the top edge
// every node is a twist end of that lattice; the outermost twist columns belong to row 1.
static void checkSymmetricPanel(const NetModel& m, const HexParams& p) {
    const double X = p.width / 2, Y = p.height / 2, half = p.axisDistance / 2;
    long off = 0, outer = 0;
    double xo = outermostColumn(p) * half;
    if (X - xo <= p.snapTolerance()) xo = X;  // snapped onto the edge
    for (const auto& n : m.nodes) {
        if (std::abs(n.x.x()) != X && n.x.y() != Y) off += !onSymmetricLattice(p, n.x.x(), n.x.y());
        const double yb = -Y + p.rowPitch();
        outer += std::abs(std::abs(n.x.x()) - xo) < 1e-9 &&
                 (std::abs(n.x.y() - yb) < 1e-9 || std::abs(n.x.y() - yb - p.twistLength) < 1e-9);
    }
    CHECK(off == 0, "symmetric %g x %g: %ld nodes off the lattice", p.width, p.height, off);
    CHECK(outer == 4, "symmetric %g x %g: row 1 is not on the outermost columns (%ld nodes there)",
          p.width, p.height, outer);
}

// YADE's pack.hexaNet(startAtCorner=False, isSymmetric=True) with nx, ny and its lower-left
// corner on (-W/2, -H/2), W = (nx - 1) a, H = ny t + (ny - 1) h (py/pack/pack.py): row i
// (i = 0 .. ny - 1) of twists from y0 + i (t + h) to y0 + i (t + h) + t; the even rows hold
// nx - 1 twists at x0 + a/2 + j a, the odd rows nx at x0 + j a; a sphere on each corner that no
// twist end occupies. Its links as the tensile example makes them (yade_tensile.md): a DT link
// along every twist off the x edges, an SW link from the top of each twist to the bottoms of
// the twists of the next row a/2 to either side, and along each x edge the edge wire between
// consecutive nodes (the edge twists included); the corners keep only that link.
struct YadeSymNet {
    std::set<Key> nodes;
    std::set<std::tuple<int, Key, Key>> links;  // (WireNet bond type, ends in ascending order)
};
static std::tuple<int, Key, Key> link(int type, Key u, Key v) { return {type, std::min(u, v), std::max(u, v)}; }
static YadeSymNet yadeSymmetricNet(const HexParams& p, long nx, long ny) {
    const double a = p.axisDistance, t = p.twistLength, pitch = p.rowPitch();
    const double x0 = -p.width / 2, y0 = -p.height / 2;
    YadeSymNet net;
    std::vector<std::vector<double>> rows(ny);
    for (long i = 0; i < ny; ++i)
        for (long j = 0; j < (i % 2 ? nx : nx - 1); ++j) rows[i].push_back(x0 + (i % 2 ? 0 : a / 2) + j * a);
    std::map<double, std::vector<Key>> xEdge;  // x = -+W/2: the edge's nodes, bottom to top
    for (long i = 0; i < ny; ++i)
        for (double x : rows[i]) {
            const Key b = key2(x, y0 + i * pitch), u = key2(x, y0 + i * pitch + t);
            net.nodes.insert(b);
            net.nodes.insert(u);
            if (std::abs(std::abs(x) + x0) < 1e-9) {
                xEdge[x < 0 ? -1 : 1].push_back(b);
                xEdge[x < 0 ? -1 : 1].push_back(u);
            } else {
                net.links.insert(link(btype::DT, b, u));
            }
            if (i + 1 < ny)
                for (double x1 : rows[i + 1])
                    if (std::abs(std::abs(x1 - x) - a / 2) < 1e-9)
                        net.links.insert(link(btype::SW, u, key2(x1, y0 + (i + 1) * pitch)));
        }
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
            const Key c = key2(sx * x0, sy * y0);
            if (net.nodes.insert(c).second) xEdge[-sx].push_back(c);
        }
    for (auto& [side, edge] : xEdge) {
        std::sort(edge.begin(), edge.end(), [](const Key& u, const Key& v) { return u.second < v.second; });
        for (size_t k = 0; k + 1 < edge.size(); ++k) net.links.insert(link(btype::Selvedge, edge[k], edge[k + 1]));
    }
    return net;
}

// The generated bonds as (type, ends) by position.
static std::set<std::tuple<int, Key, Key>> bondSet(const NetModel& m) {
    std::set<std::tuple<int, Key, Key>> s;
    for (const auto& b : m.bonds)
        s.insert(link(b.type, key2(m.nodes[b.a].x.x(), m.nodes[b.a].x.y()), key2(m.nodes[b.b].x.x(), m.nodes[b.b].x.y())));
    return s;
}

static void testHexSymmetric() {
    std::printf("hex placement symmetric (YADE's hexaNet, startAtCorner=False, isSymmetric=True)\n");
    // (13, 7): the net of YADE's examples/WireMatPM/wiretensiltest.py, 0.96 m x 0.52 m.
    for (auto [nx, ny] : std::vector<std::pair<long, long>>{{13, 7}, {12, 6}, {7, 3}, {20, 10}, {38, 37}, {6, 5}, {5, 4}}) {
        HexParams p;
        p.placement = Placement::Symmetric;
        p.nodeDiameter = 2 * 0.0108;
        p.width = (nx - 1) * p.axisDistance;
        p.height = ny * p.twistLength + (ny - 1) * p.rise;
        const NetModel m = HexPanel(p).build();
        checkHexInvariants(m, p);
        checkSymmetricPanel(m, p);
        const YadeSymNet yade = yadeSymmetricNet(p, nx, ny);
        // Every node where hexaNet puts a sphere, to 1e-9 m, and no other.
        CHECK(nodeSet(m) == yade.nodes, "symmetric nx %ld ny %ld: nodes differ from hexaNet", nx, ny);
        double worst = 0;
        for (const auto& n : m.nodes) {
            const Key k = key2(n.x.x(), n.x.y());
            worst = std::max({worst, std::abs(n.x.x() - k.first * 1e-9), std::abs(n.x.y() - k.second * 1e-9)});
        }
        CHECK(worst < 1e-9, "symmetric nx %ld ny %ld: a node %g m off the nm grid", nx, ny, worst);
        // Counts: twists 2 per row pair, corners added where no twist end is (the bottom ones
        // always: row 0 starts a/2 in; the top ones when the last row is even).
        const long even = (ny + 1) / 2, odd = ny / 2, twists = even * (nx - 1) + odd * nx;
        const long corners = ny % 2 ? 4 : 2;
        CHECK_EQ(long(m.nodes.size()), 2 * twists + corners);
        CHECK_EQ(countBonds(m, btype::DT), twists - 2 * odd);
        CHECK_EQ(countBonds(m, btype::SW), 2 * (nx - 1) * (ny - 1));
        // Bond by bond: YADE's links, and WireNet's selvedge along the y edges besides.
        const auto bonds = bondSet(m);
        long extra = 0, missing = 0;
        for (const auto& l : yade.links) missing += !bonds.count(l);
        for (const auto& b : bonds)
            if (!yade.links.count(b)) {
                const auto& [type, u, v] = b;
                const bool yEdge = type == btype::Selvedge && u.second == v.second &&
                                   std::abs(u.second * 1e-9) > p.height / 2 - 1e-9;
                CHECK(yEdge, "symmetric nx %ld ny %ld: bond type %d (%g, %g)-(%g, %g) not in hexaNet's net", nx, ny,
                      type, u.first * 1e-9, u.second * 1e-9, v.first * 1e-9, v.second * 1e-9);
                ++extra;
            }
        CHECK(missing == 0, "symmetric nx %ld ny %ld: %ld of hexaNet's links missing", nx, ny, missing);
        // The y edges: corner, the row's ends a apart, corner (nx + 1 nodes at the bottom, nx + 1
        // at the top for odd ny, else nx: the last, odd row reaches the corners).
        CHECK_EQ(extra, nx + (ny % 2 ? nx : nx - 1));
        // Lengths: DT t, SW sqrt((a/2)^2 + h^2); along an x edge t (the edge twists), 2 (t + h) - t
        // between them and t + h to a corner; along a y edge a/2 to a corner, a between twists.
        const double t = p.twistLength, pitch = p.rowPitch(), a = p.axisDistance;
        CHECK(histogram(m, btype::DT) == (std::map<long, long>{{nm(t), twists - 2 * odd}}), "DT lengths");
        CHECK(histogram(m, btype::SW) == (std::map<long, long>{{nm(p.swLength()), 2 * (nx - 1) * (ny - 1)}}), "SW lengths");
        std::map<long, long> selv;
        selv[nm(t)] += 2 * odd;
        if (odd > 1) selv[nm(2 * pitch - t)] += 2 * (odd - 1);
        selv[nm(pitch)] += 2 * (ny % 2 ? 2 : 1);
        selv[nm(a / 2)] += ny % 2 ? 4 : 2;
        selv[nm(a)] += nx - 2 + (ny % 2 ? nx - 2 : nx - 1);
        CHECK(histogram(m, btype::Selvedge) == selv, "symmetric nx %ld ny %ld: selvedge lengths", nx, ny);
        // Each corner: its x-edge link (hexaNet's, the tensile example keeps only that one) and
        // the y-edge selvedge (WireNet's), nothing else (a top corner that is a twist end, ny
        // even, is the top of an edge twist: no row above it).
        for (const auto& n : m.nodes)
            if (n.type == atype::HexCorner) {
                long xLink = 0, yLink = 0, other = 0;
                for (const auto& b : m.bonds) {
                    if (b.a != &n - &m.nodes[0] && b.b != &n - &m.nodes[0]) continue;
                    const auto& o = m.nodes[b.a == &n - &m.nodes[0] ? b.b : b.a].x;
                    if (b.type == btype::Selvedge && o.x() == n.x.x()) ++xLink;
                    else if (b.type == btype::Selvedge && o.y() == n.x.y()) ++yLink;
                    else ++other;
                }
                CHECK(xLink == 1 && yLink == 1 && other == 0,
                      "symmetric nx %ld ny %ld: corner (%g, %g) has %ld x-edge, %ld y-edge, %ld other bonds", nx, ny,
                      n.x.x(), n.x.y(), xLink, yLink, other);
            }
        // `twist` has the same net when the middle row (ny odd) holds a twist on the centre.
        HexParams tw = p;
        tw.placement = Placement::Twist;
        const bool same = ny % 2 == 1 && nx % 2 == ((ny - 1) / 2) % 2;
        CHECK((nodeSet(HexPanel(tw).build()) == yade.nodes) == same, "symmetric nx %ld ny %ld: twist %s", nx, ny,
              same ? "should coincide" : "should differ");
        std::printf("  nx %2ld ny %2ld (%.2f x %.2f): atoms %zu, DT %ld SW %ld selvedge %ld (%ld along the y edges)%s\n",
                    nx, ny, p.width, p.height, m.nodes.size(), countBonds(m, btype::DT), countBonds(m, btype::SW),
                    countBonds(m, btype::Selvedge), extra, same ? ", = twist" : "");
    }
    // The tensile example's net, in YADE's numbers (doc/wirenet-gen.md; tests/reference/yade_tensile/).
    HexParams p;
    p.placement = Placement::Symmetric;
    p.width = 0.96;
    p.height = 0.52;
    const NetModel m = HexPanel(p).build();
    CHECK_EQ(long(m.nodes.size()), 178);
    CHECK_EQ(countBonds(m, btype::DT), 81);
    CHECK_EQ(countBonds(m, btype::SW), 144);
    CHECK_EQ(countBonds(m, btype::Selvedge), 14 + 26);
    CHECK(histogram(m, btype::Selvedge) == (std::map<long, long>{{nm(0.04), 6 + 4}, {nm(0.08), 4 + 22}, {nm(0.12), 4}}),
          "tensile net: selvedge lengths");
    CHECK(std::abs(p.latticeOrigin().x() + 0.44) < 1e-15 && std::abs(p.latticeOrigin().y() + 0.24) < 1e-15,
          "tensile net: lattice origin (%g, %g)", p.latticeOrigin().x(), p.latticeOrigin().y());
}

// --selvedge sides: the selvedge of the x edges only (a strip cut from a roll). Every size,
// family and placement keeps the invariants; the lattice bonds are those of the loop, and the
// selvedge is the loop's minus its bonds along the y edges; on hexaNet's symmetric sizes the
// bonds are exactly the links of YADE's tensile example (its corners keep only their x-edge link).
static void testHexSides() {
    std::printf("hex selvedge sides\n");
    const HexParams base;
    const double a = base.axisDistance, t = base.twistLength, pitch = base.rowPitch();
    std::vector<HexParams> panels;
    for (auto [W, H] : std::vector<std::pair<double, double>>{
             {3, 3}, {(2 * 12 + 1) * a / 2, 2 * 6 * pitch - t}, {12 * a, 2 * 7 * pitch - t}, {2.5, 1.7}, {0.96, 0.52}, {0.48, 1.0}})
        for (Placement pl : {Placement::Twist, Placement::Wire, Placement::Corner, Placement::Symmetric}) {
            HexParams p;
            p.width = W;
            p.height = H;
            p.placement = pl;
            panels.push_back(p);
        }
    for (const HexParams& p : panels) {
        HexParams loopP = p, sidesP = p;
        sidesP.selvedge = Selvedge::Sides;
        const NetModel loop = HexPanel(loopP).build(), sides = HexPanel(sidesP).build();
        // (the symmetry checks compare coordinates printed to 1e-9 m: a coordinate on a rounding
        // boundary fails them for the loop too; the sides net must keep the loop's symmetries)
        for (auto [sx, sy] : std::vector<std::pair<double, double>>{{-1, 1}, {1, -1}, {-1, -1}})
            CHECK(symmetric(sides, sx, sy) == symmetric(loop, sx, sy), "sides %g x %g %s: symmetry (%g, %g) differs "
                  "from the loop's", p.width, p.height, placementName(p.placement), sx, sy);
        HexParams checked = sidesP;
        if (p.placement == Placement::Wire && !symmetric(loop, -1, -1)) checked.placement = Placement::Corner;
        checkHexInvariants(sides, checked);
        CHECK(nodeSet(sides) == nodeSet(loop), "sides %g x %g %s: nodes differ from the loop's", p.width, p.height,
              placementName(p.placement));
        const auto loopBonds = bondSet(loop), sidesBonds = bondSet(sides);
        for (const auto& b : loopBonds) {
            const auto& [type, u, v] = b;
            const bool yEdge = type == btype::Selvedge && u.second == v.second &&
                               std::abs(u.second * 1e-9) > p.height / 2 - 1e-9;
            CHECK(sidesBonds.count(b) == !yEdge, "sides %g x %g %s: bond type %d (%g, %g)-(%g, %g) %s", p.width,
                  p.height, placementName(p.placement), type, u.first * 1e-9, u.second * 1e-9, v.first * 1e-9,
                  v.second * 1e-9, yEdge ? "along a y edge kept" : "lost");
        }
        for (const auto& b : sidesBonds) CHECK(loopBonds.count(b), "sides: a bond the loop does not have");
    }
    for (auto [nx, ny] : std::vector<std::pair<long, long>>{{13, 7}, {12, 6}, {7, 3}, {20, 10}, {6, 5}, {5, 4}}) {
        HexParams p;
        p.placement = Placement::Symmetric;
        p.selvedge = Selvedge::Sides;
        p.width = (nx - 1) * a;
        p.height = ny * t + (ny - 1) * base.rise;
        const NetModel m = HexPanel(p).build();
        CHECK(bondSet(m) == yadeSymmetricNet(p, nx, ny).links, "sides nx %ld ny %ld: bonds differ from YADE's links",
              nx, ny);
    }
    HexParams p;  // the tensile example's net: 81 DT + 144 SW + 14 edge wire = YADE's 239 links
    p.placement = Placement::Symmetric;
    p.selvedge = Selvedge::Sides;
    p.width = 0.96;
    p.height = 0.52;
    const NetModel m = HexPanel(p).build();
    CHECK_EQ(long(m.nodes.size()), 178);
    CHECK_EQ(long(m.bonds.size()), 239L);
    CHECK_EQ(countBonds(m, btype::Selvedge), 14L);
    std::printf("  %zu panels; the tensile net: %zu atoms, %zu bonds (YADE: 178, 239)\n", panels.size(),
                m.nodes.size(), m.bonds.size());
}

static void testHexPlacement() {
    std::printf("hex lattice placement\n");
    for (auto [W, H] : std::vector<std::pair<double, double>>{{3, 3}, {2.5, 1.7}, {3.13, 2.91}, {1.0, 1.0}, {4.4, 2.2}}) {
        HexParams p;
        p.width = W;
        p.height = H;
        const NetModel twist = HexPanel(p).build();
        p.placement = Placement::Wire;
        const NetModel wire = HexPanel(p).build();
        checkHexInvariants(wire, p);
        const auto [type, dist] = nearestMidpoint(wire);
        CHECK(type == btype::SW && dist < 1e-9, "wire %g x %g: nearest midpoint type %d at %g", W, H, type, dist);
        CHECK(nodeSet(wire) != nodeSet(twist), "wire %g x %g: same nodes as twist", W, H);
        p.placement = Placement::Corner;
        const NetModel corner = HexPanel(p).build();
        checkHexInvariants(corner, p);
        checkCornerPanel(corner, p);
        p.placement = Placement::Symmetric;
        const NetModel sym = HexPanel(p).build();
        checkHexInvariants(sym, p);
        checkSymmetricPanel(sym, p);
        std::printf("  %.2f x %.2f: atoms twist %zu wire %zu corner %zu symmetric %zu\n", W, H, twist.nodes.size(),
                    wire.nodes.size(), corner.nodes.size(), sym.nodes.size());
        // Same lattice density: the counts differ only along the edges.
        for (const NetModel* m : {&wire, &corner, &sym})
            CHECK(std::abs(double(m->nodes.size()) / twist.nodes.size() - 1) < 0.1, "atom count %zu vs %zu",
                  m->nodes.size(), twist.nodes.size());
    }
    // Panels of YADE's own sizes: lx = (nx - 1/2) a (isSymmetric=False) or (nx - 1) a
    // (isSymmetric=True), ly = ny t + (ny - 1) h. The corner panel has exactly hexaNet's nodes.
    for (auto [nx, ny] : std::vector<std::pair<long, long>>{{38, 37}, {12, 6}, {7, 3}, {20, 10}})
        for (bool sym : {false, true}) {
            HexParams p;
            p.placement = Placement::Corner;
            p.width = (nx - (sym ? 1.0 : 0.5)) * p.axisDistance;
            p.height = ny * p.twistLength + (ny - 1) * p.rise;
            const NetModel m = HexPanel(p).build();
            checkHexInvariants(m, p);
            CHECK(nodeSet(m) == yadeNodes(p, ny), "corner nx %ld ny %ld sym %d: nodes differ from hexaNet", nx, ny, sym);
            const long twists = sym ? (ny + 1) / 2 * nx + ny / 2 * (nx - 1) : nx * ny;
            CHECK_EQ(long(m.nodes.size()), 2 * twists + (sym ? (ny % 2 == 0 ? 2 : 0) : 2));
            // Twists on the x edges run along them: the selvedge replaces their DT bond.
            const long edgeTwists = sym ? 2 * ((ny + 1) / 2) : ny;
            CHECK_EQ(countBonds(m, btype::DT), twists - edgeTwists);
            // Without the selvedge: hexaNet's twist ends only (its extra corner spheres would be
            // on no bond), every twist a DT bond, the edge twists included; no edge wire.
            p.selvedge = Selvedge::None;
            const NetModel bare = HexPanel(p).build();
            CHECK_EQ(long(bare.nodes.size()), 2 * twists);
            CHECK_EQ(countBonds(bare, btype::DT), twists);
            CHECK_EQ(countBonds(bare, btype::Selvedge), 0L);
            CHECK_EQ(countBonds(bare, btype::SW), countBonds(m, btype::SW));
            for (const auto& n : bare.nodes)
                CHECK(onYadeLattice(p, n.x.x(), n.x.y()), "no selvedge: node (%g, %g) off hexaNet's lattice",
                      n.x.x(), n.x.y());
        }
    // Compound: the hex layer follows the placement; ties still find a hex node nearby.
    CompoundParams cp;
    cp.hex.placement = Placement::Corner;
    cp.tieEvery = 2;
    CompoundPanel panel(cp);
    const NetModel c = panel.build();
    const NetModel h = HexPanel(cp.hex).build();
    long hexNodes = 0;
    for (const auto& n : c.nodes) hexNodes += n.molecule == 1;
    CHECK_EQ(hexNodes, long(h.nodes.size()));
    CHECK(c.nodes[0].x.x() == -1.5 && c.nodes[0].x.y() == -1.5 && std::abs(c.nodes[1].x.y() + 1.46) < 1e-9,
          "compound: the hex layer starts at the corner");
    CHECK_EQ(panel.ties(), 16);
    for (size_t b = c.bonds.size() - 16; b < c.bonds.size(); ++b)
        CHECK(c.bondLength(c.bonds[b]) < 0.06, "tie length %g", c.bondLength(c.bonds[b]));
}

// ---- square panel ---------------------------------------------------------------------------

static void testSquare() {
    std::printf("square panels\n");
    struct Case { double W, H, c; int ne; };
    for (const Case& cs : std::vector<Case>{{3, 3, 0.3, 3}, {2.4, 1.5, 0.3, 3}, {3, 3, 0.3, 1}, {1.8, 3.6, 0.3, 5}, {2.7, 2.1, 0.3, 2}}) {
        SquareParams p;
        p.width = cs.W;
        p.height = cs.H;
        p.cell = cs.c;
        p.elements = cs.ne;
        const NetModel m = SquarePanel(p).build();
        const long nx = std::lround(cs.W / cs.c), ny = std::lround(cs.H / cs.c), ne = cs.ne;
        const long segments = (ny + 1) * nx + (nx + 1) * ny;
        std::printf("  square %.1f x %.1f, %d el: atoms %zu bonds %zu\n", cs.W, cs.H, cs.ne, m.nodes.size(), m.bonds.size());
        CHECK_EQ(long(m.nodes.size()), (nx + 1) * (ny + 1) + (ne - 1) * segments);
        CHECK_EQ(countBonds(m, btype::Rope), ne * segments);
        CHECK_EQ(countType(m, atype::SqCorner), 4);
        CHECK_EQ(countType(m, atype::SqEdgeX), 2 * (ny * ne - 1));
        CHECK_EQ(countType(m, atype::SqEdgeY), 2 * (nx * ne - 1));
        CHECK(edgesExact(m, cs.W / 2, cs.H / 2, 5, 6, 7, 8), "square edges exact");
        CHECK(mirrorSymmetric(m, 0) && mirrorSymmetric(m, 1), "square symmetric");
        CHECK(everyNodeBonded(m) && noDuplicateBonds(m), "square connectivity");
        const auto h = histogram(m, btype::Rope);
        CHECK(h.size() == 1 && h.count(nm(cs.c / ne)), "rope element lengths: %zu bins", h.size());
        CHECK_NEAR(m.totalMass(), p.ropeMass * cs.c * segments, 1e-9);
        CHECK(minNodeDistance(m) > 0.99 * cs.c / ne, "duplicate nodes");
    }
    // A panel that is not a whole number of cells: perimeter ropes on the edges, invariants hold.
    SquareParams p;
    p.width = 3.1;
    p.height = 2.0;
    const NetModel m = SquarePanel(p).build();
    CHECK(edgesExact(m, 1.55, 1.0, 5, 6, 7, 8), "square generic edges exact");
    CHECK(mirrorSymmetric(m, 0) && mirrorSymmetric(m, 1), "square generic symmetric");
    double total = 0;
    for (const auto& b : m.bonds) total += m.bondLength(b);
    CHECK_NEAR(m.totalMass(), 0.4 * total, 1e-9);
}

// ---- compound, beam -------------------------------------------------------------------------

static void testCompound() {
    std::printf("compound panel\n");
    CompoundParams p;
    const NetModel hex = HexPanel(p.hex).build(), sq = SquarePanel(p.square).build();
    const NetModel m = CompoundPanel(p).build();
    CHECK_EQ(long(m.nodes.size()), long(hex.nodes.size() + sq.nodes.size()));
    CHECK_EQ(long(m.bonds.size()), long(hex.bonds.size() + sq.bonds.size()));
    const double zHex = 0.5 * (0.0108 + 0.010);
    for (const auto& n : m.nodes) {
        if (n.molecule == 1) CHECK(n.x.z() == zHex && n.type <= 4, "hex layer z/type");
        else CHECK(n.molecule == 2 && n.x.z() == 0 && n.type >= 5, "square layer z/type");
    }
    CHECK(mirrorSymmetric(m, 0) && mirrorSymmetric(m, 1), "compound symmetric");
    for (const auto& b : m.bonds) CHECK(m.nodes[b.a].molecule == m.nodes[b.b].molecule, "no inter-layer bond");
    for (int k : {1, 2, 3, 4}) {
        p.tieEvery = k;
        CompoundPanel panel(p);
        const NetModel t = panel.build();
        const long expect = (9 / k) * (9 / k);  // 10 cells: interior lines 1..9
        CHECK_EQ(panel.ties(), expect);
        CHECK_EQ(long(t.bonds.size()), long(m.bonds.size()) + expect);
        for (size_t b = m.bonds.size(); b < t.bonds.size(); ++b) {
            const Bond& tie = t.bonds[b];
            CHECK(tie.type == btype::SW && t.nodes[tie.a].molecule == 1 && t.nodes[tie.b].molecule == 2, "tie");
            CHECK(t.bondLength(tie) < 0.06, "tie length %g", t.bondLength(tie));
        }
    }
}

static void testBeam() {
    std::printf("beam\n");
    for (int n : {1, 5, 11, 21}) {
        BeamParams p;
        p.elements = n;
        const NetModel m = Beam(p).build();
        CHECK_EQ(long(m.nodes.size()), n + 1);
        CHECK_EQ(long(m.bonds.size()), n);
        CHECK(m.nodes.front().type == 2 && m.nodes.back().type == 3 && m.nodes.back().x.x() == 2.0, "ends");
        CHECK_EQ(countType(m, 1), n - 1);
        CHECK_NEAR(m.totalMass(), 7850 * M_PI / 4 * 1e-4 * 2.0, 1e-12);
        const auto h = histogram(m, 1);
        CHECK(h.size() == 1 && h.count(nm(2.0 / n)), "beam element lengths");
    }
}

// ---- parameter validation -------------------------------------------------------------------

// The message a check throws; "" if it passes.
template <class Check>
static std::string errorOf(Check check) {
    try {
        check();
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

// A message as expected; starts: only its beginning (the rest holds computed numbers).
#define CHECK_MESSAGE(got, expect)                                                       \
    do {                                                                                 \
        const std::string got_ = (got);                                                  \
        CHECK(got_ == (expect), "got '%s', expected '%s'", got_.c_str(), (expect));      \
    } while (0)
#define CHECK_MESSAGE_STARTS(got, expect)                                                \
    do {                                                                                 \
        const std::string got_ = (got);                                                  \
        CHECK(got_.rfind((expect), 0) == 0, "got '%s', expected '%s...'", got_.c_str(), (expect)); \
    } while (0)

// The message FenceParams::validate() throws for the defaults with one change.
template <class Change>
static std::string fenceError(Change change, const ValueText& text = formatted) {
    FenceParams p;
    change(p);
    return errorOf([&] { p.validate(text); });
}

static void testFenceValidation() {
    std::printf("fence parameter validation\n");
    // The defaults (wirenet-gen fence's) pass, for every net.
    for (NetKind net : {NetKind::Compound, NetKind::Hex, NetKind::Square})
        CHECK_MESSAGE(fenceError([net](FenceParams& p) { p.net = net; }), "");
    // One bad value: one line naming the option and the value.
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.postTilt = 45; }), "--post-tilt must be >= 0 and < 45 degrees (got 45)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.fill = 1.5; }), "--rope-fill must be <= 1 (got 1.5)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.shackleGap = 3; }),
                  "--shackle-gap must be < --height/2 (got 3)");
    // The top and bottom edges clear the support ropes' spheres, the side edges the posts'.
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.shackleGap = 0.01; }),
                  "--shackle-gap must be > 0.0164, a net node's radius plus a support rope node's radius (got 0.01)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.postGap = 0.1; }),
                  "--post-gap must be > 0.1054, a net node's radius plus a post node's radius (got 0.1)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.postGap = 5; }), "--post-gap must be < --spacing/2 (got 5)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.postGap = 0.11; }), "");
    // (its default, from the other options: what they imply is named)
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.postNodeDiameter = 10; }),
                  "--post-gap must be < --spacing/2 (got 5.05, its default from --shackle-gap and --post-node-diameter)");
    // By default the side edges hang the shackle gap from the post's face (its sphere's
    // surface), rounded up to the cm: 0.05 + 0.2/2 = 0.15 m (in doubles 0.15000000000000002,
    // which must not become 0.16).
    {
        FenceParams d;
        CHECK(d.postNodeDiameter == 0.2 && d.sideGap() == 0.15 && d.panelWidth() == 10 - 2 * 0.15 &&
                  d.panelHeight() == 5 - 2 * 0.05,
              "defaults: post nodes %g, post gap %g, panel %g x %g", d.postNodeDiameter, d.sideGap(), d.panelWidth(),
              d.panelHeight());
        d.shackleGap = 0.08;
        d.postNodeDiameter = 0.19;
        CHECK(d.sideGap() == 0.18, "0.08 + 0.095 -> 0.18, got %g", d.sideGap());
        d.postNodeDiameter = 0.02;
        CHECK(d.sideGap() == 0.09, "0.08 + 0.01 is 0.09, got %g", d.sideGap());
        d.supportDiameter = 0.05;  // the post gap does not depend on the ropes
        CHECK(d.sideGap() == 0.09, "got %g", d.sideGap());
        d.postGap = 0.3;
        CHECK(d.sideGap() == 0.3 && d.panelWidth() == 10 - 0.6, "given: %g", d.sideGap());
    }
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.upslopeHeight = 5; }), "--upslope-height must be < --height (got 5 >= 5)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.net = NetKind::Hex; p.panel.tieEvery = 2; }),
                  "--ties needs --net compound (got --net hex)");
    // The module's panel is checked at the module's size, named after the options it comes from.
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.panel.hex.axisDistance = 20; }),
                  "--axis-distance must be <= --spacing - 2 x --post-gap (got 20 > 9.7)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.net = NetKind::Square; p.panel.square.cell = 6; }),
                  "--cell must be <= (--height - 2 x --shackle-gap) (got 6 > 4.9)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.net = NetKind::Square; p.panel.hex.axisDistance = 20; }), "");
    // The ropes' bonds and brakes.
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.brakes = 6; }),
                  "--brakes must be <= 5, the bonds between a lateral anchor and the end post (got 6)");
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.upslopeBrakes = 25; }),
                  "--upslope-brakes must be <= 24, the bonds of an upslope rope (got 25)");
    CHECK_MESSAGE_STARTS(fenceError([](FenceParams& p) { p.ropeSegment = 0.02; }),
                         "--rope-segment 0.02 gives the support rope's bond");
    // ... which are the second step, after the command line's size guard.
    FenceParams p;
    p.brakes = 6;
    CHECK_MESSAGE(errorOf([&] { p.validateLayout(); }), "");
    // The command line quotes a value as typed.
    const ValueText typed = [](const std::string& name, double v) { return name == "post-tilt" ? "45.0" : fmt(v); };
    CHECK_MESSAGE(fenceError([](FenceParams& p) { p.postTilt = 45; }, typed),
                  "--post-tilt must be >= 0 and < 45 degrees (got 45.0)");
    // The panels' own checks, named after the panel options.
    HexParams hp;
    hp.snapFraction = 0.7;
    CHECK_MESSAGE(errorOf([&] { hp.validate(); }), "--snap must be < 0.5 (got 0.7)");
    SquareParams sp;
    sp.cell = 5;
    CHECK_MESSAGE(errorOf([&] { sp.validate(); }), "--cell must be <= --width (got 5 > 3)");
}

static void testShapeValidation() {
    std::printf("shape parameter validation\n");
    ShapeParams cube;
    cube.kind = ShapeKind::TruncatedCube;
    cube.side = 0.45;
    cube.cornerCut = 0.15;
    CHECK_MESSAGE(errorOf([&] { cube.validate(); }), "");
    cube.cornerCut = 0.225;
    CHECK_MESSAGE(errorOf([&] { cube.validate(); }), "--corner-cut must be < --side/2 (got 0.225 >= 0.225)");
    ShapeParams cone;
    cone.kind = ShapeKind::Cone;
    cone.radius = 0.34;
    cone.height = 0.78;
    cone.tipRadius = 0.5;
    CHECK_MESSAGE(errorOf([&] { cone.validate(); }), "--tip-radius must be < --radius (got 0.5 >= 0.34)");
    cone.kind = ShapeKind::Spheroid;  // a spheroid has no tip
    CHECK_MESSAGE(errorOf([&] { cone.validate(); }), "");
}

// ---- shapes ---------------------------------------------------------------------------------

// Closed two-manifold with consistent orientation: each directed edge once, its reverse once.
static bool closedConsistent(const TriMesh& m) {
    std::map<std::pair<int, int>, int> directed;
    for (const auto& f : m.faces)
        for (int e = 0; e < 3; ++e) ++directed[{f[e], f[(e + 1) % 3]}];
    for (const auto& kv : directed) {
        if (kv.second != 1) return false;
        auto rev = directed.find({kv.first.second, kv.first.first});
        if (rev == directed.end() || rev->second != 1) return false;
    }
    return true;
}

// Outward: positive volume and, the shapes being convex, every facet faces away from the centroid.
static bool outward(const TriMesh& m) {
    const MassProperties p = massProperties(m, 0);
    if (!(p.volume > 0)) return false;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        const auto& t = m.faces[f];
        const Eigen::Vector3d c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0;
        if (m.normal(f).dot(c - p.centroid) <= 0) return false;
    }
    return true;
}

// Reads back an ASCII STL, merging vertices by their printed coordinates.
static TriMesh readStl(const std::string& text) {
    TriMesh m;
    std::map<std::string, int> ids;
    std::istringstream in(text);
    std::string word;
    std::array<int, 3> face{};
    int k = 0;
    while (in >> word) {
        if (word != "vertex") continue;
        std::string x, y, z;
        in >> x >> y >> z;
        const std::string key = x + " " + y + " " + z;
        auto it = ids.find(key);
        if (it == ids.end()) {
            it = ids.emplace(key, int(m.vertices.size())).first;
            m.vertices.emplace_back(std::stod(x), std::stod(y), std::stod(z));
        }
        face[k++] = it->second;
        if (k == 3) { m.faces.push_back(face); k = 0; }
    }
    return m;
}

static void checkShape(const TriMesh& mesh, double analytic, const char* label) {
    std::ostringstream os;
    StlWriter::write(os, mesh, label);
    const TriMesh back = readStl(os.str());
    const MassProperties p = massProperties(back, 0);
    std::printf("  %-28s facets %5zu volume %.6g (analytic %.6g, %+.3f %%)\n", label, back.faces.size(),
                p.volume, analytic, 100 * (p.volume / analytic - 1));
    CHECK(closedConsistent(back), "%s: closed with consistent orientation", label);
    // LIGGGHTS' fix mesh/surface refuses facets with an angle below about 0.256 deg (its default
    // curvature): keep a margin.
    double smallest = 180;
    for (const auto& t : back.faces)
        for (int e = 0; e < 3; ++e) {
            const Eigen::Vector3d u = back.vertices[t[(e + 1) % 3]] - back.vertices[t[e]];
            const Eigen::Vector3d w = back.vertices[t[(e + 2) % 3]] - back.vertices[t[e]];
            smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * 180 / M_PI);
        }
    CHECK(smallest > 0.3, "%s: smallest facet angle %g deg", label, smallest);
    CHECK(outward(back), "%s: outward normals", label);
    CHECK(std::abs(p.volume / analytic - 1) < 0.005, "%s: volume error %g", label, p.volume / analytic - 1);
    // The written facet normals agree with the vertex order.
    std::istringstream in(os.str());
    std::string w;
    size_t f = 0;
    while (in >> w)
        if (w == "normal") {
            Eigen::Vector3d n;
            in >> n.x() >> n.y() >> n.z();
            CHECK(n.dot(back.normal(f)) > 0.999999, "%s: facet %zu normal", label, f);
            ++f;
        }
}

static void testShapes() {
    std::printf("shapes\n");
    for (int res : {64, 96, 256}) {
        char l1[64], l2[64];
        std::snprintf(l1, sizeof l1, "spheroid res %d", res);
        std::snprintf(l2, sizeof l2, "cone res %d", res);
        checkShape(ShapeBuilder::semiSpheroid(0.5, 0.15, res), ShapeBuilder::semiSpheroidVolume(0.5, 0.15), l1);
        checkShape(ShapeBuilder::cone(0.34, 0.78, res), ShapeBuilder::coneVolume(0.34, 0.78), l2);
        std::snprintf(l2, sizeof l2, "flat-tip cone res %d", res);
        checkShape(ShapeBuilder::cone(0.34, 0.78, res, 0.02), ShapeBuilder::coneVolume(0.34, 0.78, 0.02), l2);
    }
    // Flat tip: every tip vertex at z = -height within the tip radius; the axis point of the tip
    // lies inside one facet, at least a few millimetres from every edge of the tip (the panel's
    // centre node rests there: no facet edge may pass through it, see addRing).
    for (int res : {8, 48, 96}) {
        const double a = 0.02, h = 0.78;
        const TriMesh m = ShapeBuilder::cone(0.34, h, res, a);
        double closest = 1;
        int inside = 0;
        for (const auto& t : m.faces) {
            const Eigen::Vector3d &p0 = m.vertices[t[0]], &p1 = m.vertices[t[1]], &p2 = m.vertices[t[2]];
            if (p0.z() != -h || p1.z() != -h || p2.z() != -h) continue;
            for (const Eigen::Vector3d* v : {&p0, &p1, &p2})
                CHECK(v->head<2>().norm() <= a * (1 + 1e-12), "tip vertex at r = %g", v->head<2>().norm());
            const Eigen::Vector3d c(0, 0, -h);
            for (int e = 0; e < 3; ++e) {
                const Eigen::Vector3d& u = m.vertices[t[e]];
                const Eigen::Vector3d& w = m.vertices[t[(e + 1) % 3]];
                const double s = std::clamp((c - u).dot(w - u) / (w - u).squaredNorm(), 0.0, 1.0);
                closest = std::min(closest, (c - (u + s * (w - u))).norm());
            }
            // barycentric test in the plane z = -h
            const Eigen::Vector2d q0 = p0.head<2>(), q1 = p1.head<2>(), q2 = p2.head<2>();
            auto side = [](const Eigen::Vector2d& x, const Eigen::Vector2d& y, const Eigen::Vector2d& z) {
                return (y - x).x() * (z - x).y() - (y - x).y() * (z - x).x();
            };
            const Eigen::Vector2d o(0, 0);
            const double s0 = side(q0, q1, o), s1 = side(q1, q2, o), s2 = side(q2, q0, o);
            if ((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0)) ++inside;
        }
        CHECK_EQ(inside, 1);
        CHECK(closest > 0.1 * a, "res %d: tip axis point %g m from a tip edge", res, closest);
    }
    CHECK_NEAR(ShapeBuilder::coneVolume(0.34, 0.78, 0.34), M_PI * 0.34 * 0.34 * 0.78, 1e-15);
    // Orientation conventions: base disc at z = 0, tip at -height.
    const TriMesh sph = ShapeBuilder::semiSpheroid(0.5, 0.15, 96);
    double zmin = 0, zmax = -1;
    for (const auto& v : sph.vertices) { zmin = std::min(zmin, v.z()); zmax = std::max(zmax, v.z()); }
    CHECK(zmin == -0.15 && zmax == 0.0, "spheroid z range %g %g", zmin, zmax);

    for (double cut : {0.15, 0.1, 0.01, 0.2}) {
        const TriMesh m = ShapeBuilder::truncatedCube(0.45, cut);
        char label[64];
        std::snprintf(label, sizeof label, "truncated cube cut %.2f", cut);
        checkShape(m, ShapeBuilder::truncatedCubeVolume(0.45, cut), label);
        CHECK_EQ(long(m.vertices.size()), 24);
        CHECK_EQ(long(m.faces.size()), 8 + 6 * 6);
        const MassProperties p = massProperties(m, 44.5);
        CHECK_NEAR(p.volume, ShapeBuilder::truncatedCubeVolume(0.45, cut), 1e-14);
        CHECK(p.centroid.norm() < 1e-15, "centroid %g", p.centroid.norm());
        const double I = ShapeBuilder::truncatedCubeInertia(0.45, cut, 44.5);
        CHECK((p.inertia - I * Eigen::Matrix3d::Identity()).norm() < 1e-12 * I, "inertia %g vs %g",
              p.inertia(0, 0), I);
    }
    // Symmetry-plane points of the platters and the block must not lie on a facet edge (LIGGGHTS
    // drops a contact whose point falls exactly on an edge between coplanar facets): the apex
    // fans put no edge in the planes x = 0, y = 0; the block's face centres lie inside a facet.
    for (const TriMesh& shape : {ShapeBuilder::semiSpheroid(0.5, 0.15, 96), ShapeBuilder::cone(0.34, 0.78, 48)})
        for (const auto& t : shape.faces)
            for (int e = 0; e < 3; ++e) {
                const Eigen::Vector3d& a = shape.vertices[t[e]];
                const Eigen::Vector3d& b = shape.vertices[t[(e + 1) % 3]];
                const bool apex_edge = a.head<2>().norm() < 1e-12 || b.head<2>().norm() < 1e-12;
                if (!apex_edge) continue;
                const Eigen::Vector2d rim = (a.head<2>().norm() > b.head<2>().norm() ? a : b).head<2>();
                CHECK(std::abs(rim.x()) > 1e-3 && std::abs(rim.y()) > 1e-3, "apex edge towards (%g, %g)",
                      rim.x(), rim.y());
            }
    {
        const TriMesh cube = ShapeBuilder::truncatedCube(0.45, 0.15);
        for (int axis = 0; axis < 3; ++axis)
            for (int sgn : {-1, 1}) {
                Eigen::Vector3d c = Eigen::Vector3d::Zero();
                c[axis] = sgn * 0.225;
                double closest = 1;  // distance of the face centre from the nearest edge line
                for (const auto& t : cube.faces)
                    for (int e = 0; e < 3; ++e) {
                        const Eigen::Vector3d& a = cube.vertices[t[e]];
                        const Eigen::Vector3d& b = cube.vertices[t[(e + 1) % 3]];
                        if (std::abs(a[axis] - c[axis]) > 1e-12 || std::abs(b[axis] - c[axis]) > 1e-12) continue;
                        closest = std::min(closest, (c - a).cross(b - a).norm() / (b - a).norm());
                    }
                CHECK(closest > 0.01, "face centre axis %d sign %d lies %g from an edge", axis, sgn, closest);
            }
    }
    // Limit: a tiny cut gives the cube's m s^2 / 6.
    CHECK_NEAR(ShapeBuilder::truncatedCubeInertia(0.45, 1e-6, 44.5), 44.5 * 0.45 * 0.45 / 6, 1e-9);
    // Off-centre solid: mass properties move with it (parallel-axis theorem).
    TriMesh shifted = ShapeBuilder::truncatedCube(0.45, 0.15);
    for (auto& v : shifted.vertices) v += Eigen::Vector3d(1, -2, 3);
    const MassProperties ps = massProperties(shifted, 44.5);
    CHECK((ps.centroid - Eigen::Vector3d(1, -2, 3)).norm() < 1e-12, "shifted centroid");
    CHECK(std::abs(ps.inertia(0, 0) - ShapeBuilder::truncatedCubeInertia(0.45, 0.15, 44.5)) < 1e-10, "shifted I");
}

// ---- writer ---------------------------------------------------------------------------------

static void testWriter() {
    std::printf("data file\n");
    BeamParams bp;
    const NetModel m = Beam(bp).build();
    NetDescription d;
    d.kind = "beam";
    d.command = "beam --elements 5";
    d.atomTypes = 3;
    d.bondTypes = 1;
    d.box.lo << -0.1, -0.1, -2;
    d.box.hi << 2.1, 0.1, 2;
    std::ostringstream os;
    MeshWriter(m, d).writeData(os);
    const std::string s = os.str();
    CHECK(s.rfind("LIGGGHTS data file from wirenet-gen beam --elements 5\n\n6 atoms\n5 bonds\n3 atom types\n1 bond types\n", 0) == 0,
          "header");
    CHECK(s.find("\nAtoms\n\n1 2 0 0 0 0.01 ") != std::string::npos, "first atom line");
    CHECK(s.find("\nBonds\n\n1 1 1 2\n") != std::string::npos, "first bond line");
    CHECK(s.find("-0.1 2.1 xlo xhi\n") != std::string::npos, "box line");
}

int main() {
    testHex();
    testHexPlacement();
    testHexSymmetric();
    testHexSides();
    testSquare();
    testCompound();
    testBeam();
    testFenceValidation();
    testShapeValidation();
    testShapes();
    testWriter();
    std::printf("%d checks, %d failures\n", checks, failures);
    return failures ? 1 : 0;
}
