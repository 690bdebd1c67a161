#include "SquarePanel.h"

#include <algorithm>
#include <cmath>

namespace wirenet {

void SquareParams::validate(const ValueText& text, const SideNames& sides) const {
    requireLess("--cell", cell, sides.width, width);
    requireLess("--cell", cell, sides.height, height);
    if (!(dropFraction < 0.5))
        throw UsageError("--edge-drop must be < 0.5 (got " + text("edge-drop", dropFraction) + ")");
}

std::vector<double> SquarePanel::ropeLines(double half, double cell, double dropFraction) {
    // Symmetric about 0 with a rope either on the axis or half a cell off, whichever puts
    // a rope closest to the edge (an exact fit gives full cells up to the edge ropes).
    const double r = half / cell, frac = r - std::floor(r);
    const double phase = std::abs(frac - 0.5) < std::min(frac, 1 - frac) ? 0.5 : 0.0;
    std::vector<double> lines{-half, half};
    const int n = int(std::ceil(r)) + 1;
    for (int i = -n; i <= n; ++i) {
        const double x = (i + phase) * cell;
        if (std::abs(x) < half - dropFraction * cell) lines.push_back(x);
    }
    std::sort(lines.begin(), lines.end());
    return lines;
}

int SquarePanel::elementsFor(double length) const {
    return std::max(1, int(std::lround(p_.elements * length / p_.cell)));
}

double SquarePanel::estimateNodes(const SquareParams& p) {
    const double nx = std::ceil(p.width / p.cell) + 2, ny = std::ceil(p.height / p.cell) + 2;
    const double segments = nx * (ny - 1) + ny * (nx - 1);
    // Upper bound (a partial edge cell is shorter than 1.5 cells); far above any limit when large.
    const double bound = nx * ny + (1.5 * p.elements) * segments;
    if (nx > 1e6 || ny > 1e6 || bound > 1e10) return bound;
    // Exact count, as build() makes it.
    const auto xs = ropeLines(0.5 * p.width, p.cell, p.dropFraction);
    const auto ys = ropeLines(0.5 * p.height, p.cell, p.dropFraction);
    auto inner = [&](const std::vector<double>& lines) {  // intermediate nodes along one rope
        double n = 0;
        for (size_t i = 0; i + 1 < lines.size(); ++i)
            n += std::max(1.0, double(std::lround(p.elements * (lines[i + 1] - lines[i]) / p.cell))) - 1;
        return n;
    };
    return double(xs.size()) * ys.size() + inner(xs) * ys.size() + inner(ys) * xs.size();
}

NetModel SquarePanel::build() const {
    const double X = 0.5 * p_.width, Y = 0.5 * p_.height;
    const auto xs = ropeLines(X, p_.cell, p_.dropFraction);
    const auto ys = ropeLines(Y, p_.cell, p_.dropFraction);
    NetModel m;
    auto addNode = [&](double x, double y) {
        const bool ex = std::abs(x) == X, ey = std::abs(y) == Y;
        const int type = ex && ey ? atype::SqCorner : ex ? atype::SqEdgeX : ey ? atype::SqEdgeY : atype::SqInterior;
        m.nodes.push_back({{x, y, p_.z}, type, p_.nodeDiameter, 0.0, p_.molecule});
        return int(m.nodes.size()) - 1;
    };
    // Crossings first (shared by the x-rope and the y-rope).
    std::vector<int> cross(xs.size() * ys.size());
    crossings_.clear();
    for (size_t j = 0; j < ys.size(); ++j)
        for (size_t i = 0; i < xs.size(); ++i) {
            cross[j * xs.size() + i] = addNode(xs[i], ys[j]);
            crossings_.push_back({cross[j * xs.size() + i], int(i), int(j)});
        }
    // Intermediate nodes and rope bonds between neighbouring crossings.
    auto chain = [&](int from, int to) {
        const Eigen::Vector3d a = m.nodes[from].x, b = m.nodes[to].x;
        const int n = elementsFor((b - a).norm());
        int prev = from;
        for (int e = 1; e <= n; ++e) {
            int cur = to;
            if (e < n) {
                const Eigen::Vector3d x = a + (b - a) * (double(e) / n);
                cur = addNode(x.x(), x.y());
            }
            m.bonds.push_back({btype::Rope, prev, cur});
            prev = cur;
        }
    };
    for (size_t j = 0; j < ys.size(); ++j)
        for (size_t i = 0; i + 1 < xs.size(); ++i) chain(cross[j * xs.size() + i], cross[j * xs.size() + i + 1]);
    for (size_t i = 0; i < xs.size(); ++i)
        for (size_t j = 0; j + 1 < ys.size(); ++j) chain(cross[j * xs.size() + i], cross[(j + 1) * xs.size() + i]);
    // Rope mass lumped to the nodes: half of each adjacent element.
    for (const auto& b : m.bonds) {
        const double half = 0.5 * p_.ropeMass * m.bondLength(b);
        m.nodes[b.a].mass += half;
        m.nodes[b.b].mass += half;
    }
    return m;
}

Json SquarePanel::cellJson() const {
    Json c = Json::object();
    c.set("cell", p_.cell).set("elements_per_side", p_.elements);
    c.set("element_length", p_.cell / p_.elements).set("crossing", "shared node");
    c.set("edge_drop_fraction", p_.dropFraction);
    return c;
}

namespace {

double meanMass(const NetModel& m, int molecule) {
    double s = 0;
    long n = 0;
    for (const auto& x : m.nodes)
        if (x.molecule == molecule) { s += x.mass; ++n; }
    return n ? s / n : 0.0;
}

}  // namespace

void SquarePanel::describe(NetDescription& d, const NetModel& m) const {
    d.cells.set("square", cellJson());
    Json w = wireJson(p_.ropeDiameter);
    w.set("mass_per_metre", p_.ropeMass);
    d.wires.set("rope", w);
    Json n = nodeJson(p_.nodeDiameter, meanMass(m, 2));
    n.set("mass_rule", "rope mass lumped: half of each adjacent element");
    d.node.set("square", n);
}

}  // namespace wirenet
