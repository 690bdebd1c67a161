// The in-memory net: spheres (nodes) and bonds, plus the metadata the writers need.
#pragma once
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "Json.h"

namespace wirenet {

// Fixed type numbering of doc/file_formats.md (one deck serves every panel).
namespace atype {
constexpr int HexInterior = 1, HexEdgeX = 2, HexEdgeY = 3, HexCorner = 4;
constexpr int SqInterior = 5, SqEdgeX = 6, SqEdgeY = 7, SqCorner = 8;
constexpr int BeamInterior = 1, BeamRoot = 2, BeamTip = 3;
}  // namespace atype
namespace btype {
constexpr int DT = 1, SW = 2, Selvedge = 3, Rope = 4, Beam = 1;
}

struct Node {
    Eigen::Vector3d x;
    int type;
    double diameter;  // m (numerical contact sphere)
    double mass;      // kg
    int molecule;
};

struct Bond {
    int type;
    int a, b;  // 0-based node indices
};

struct NetModel {
    std::vector<Node> nodes;
    std::vector<Bond> bonds;

    double totalMass() const;
    double bondLength(const Bond& b) const;
    double maxBondLength() const;
    std::map<int, long> atomsPerType() const;
    std::map<int, long> bondsPerType() const;
    Eigen::Vector3d bboxMin() const;
    Eigen::Vector3d bboxMax() const;
    // Appends another model (ids shift); used by the compound panel.
    void append(const NetModel& other);
};

// The simulation box written into the data file.
struct Box {
    Eigen::Vector3d lo, hi;
};

// Everything besides nodes and bonds that goes into PREFIX.data / PREFIX.json.
struct NetDescription {
    std::string kind;          // hex | square | compound | beam
    std::string command;       // full command line
    int atomTypes = 8, bondTypes = 4;
    std::map<int, std::string> atomTypeNames, bondTypeNames;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // the net's normal towards the loaded side
    double width = 0, height = 0;
    Json cells = Json::object(), wires = Json::object(), node = Json::object();
    Json extra = Json::object();  // kind-specific additions (ties, beam, rules), under the key `kind`
    Json top = Json::object();    // kind-specific keys at the top level of the JSON (fence)
    double area = 0;              // for areal mass; 0 = not a panel
    Box box;
};

// The standard names of doc/file_formats.md.
NetDescription panelDescription(const std::string& kind);
// Entries of the description's "wires" and "node" objects.
Json wireJson(double diameter, const std::string& note = "");
Json nodeJson(double diameter, double mass);

}  // namespace wirenet
