#include "NetModel.h"

#include <algorithm>

namespace wirenet {

double NetModel::totalMass() const {
    double m = 0;
    for (const auto& n : nodes) m += n.mass;
    return m;
}

double NetModel::bondLength(const Bond& b) const { return (nodes[b.a].x - nodes[b.b].x).norm(); }

double NetModel::maxBondLength() const {
    double m = 0;
    for (const auto& b : bonds) m = std::max(m, bondLength(b));
    return m;
}

std::map<int, long> NetModel::atomsPerType() const {
    std::map<int, long> c;
    for (const auto& n : nodes) ++c[n.type];
    return c;
}

std::map<int, long> NetModel::bondsPerType() const {
    std::map<int, long> c;
    for (const auto& b : bonds) ++c[b.type];
    return c;
}

Eigen::Vector3d NetModel::bboxMin() const {
    Eigen::Vector3d m = nodes.empty() ? Eigen::Vector3d::Zero() : nodes[0].x;
    for (const auto& n : nodes) m = m.cwiseMin(n.x);
    return m;
}

Eigen::Vector3d NetModel::bboxMax() const {
    Eigen::Vector3d m = nodes.empty() ? Eigen::Vector3d::Zero() : nodes[0].x;
    for (const auto& n : nodes) m = m.cwiseMax(n.x);
    return m;
}

void NetModel::append(const NetModel& other) {
    const int shift = int(nodes.size());
    nodes.insert(nodes.end(), other.nodes.begin(), other.nodes.end());
    for (Bond b : other.bonds) {
        b.a += shift;
        b.b += shift;
        bonds.push_back(b);
    }
}

NetDescription panelDescription(const std::string& kind) {
    NetDescription d;
    d.kind = kind;
    d.atomTypeNames = {{1, "hex_interior"},    {2, "hex_edge_x"},    {3, "hex_edge_y"},
                       {4, "hex_corner"},      {5, "square_interior"}, {6, "square_edge_x"},
                       {7, "square_edge_y"},   {8, "square_corner"}};
    d.bondTypeNames = {{1, "DT"}, {2, "SW"}, {3, "selvedge"}, {4, "rope"}};
    return d;
}

Json wireJson(double diameter, const std::string& note) {
    Json w = Json::object();
    w.set("diameter", diameter);
    if (!note.empty()) w.set("note", note);
    return w;
}

Json nodeJson(double diameter, double mass) {
    Json n = Json::object();
    n.set("diameter", diameter).set("mass", mass);
    return n;
}

}  // namespace wirenet
