// Closed, outward-oriented triangle meshes of the platters and the impact block, and their
// mass properties (exact for the polyhedron, by the divergence theorem).
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "Usage.h"

namespace wirenet {

struct TriMesh {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::array<int, 3>> faces;

    Eigen::Vector3d normal(size_t f) const;  // unit, right-hand rule
    // Flips faces whose normal points towards `inside` (valid for convex solids only).
    void orientOutward(const Eigen::Vector3d& inside);
};

struct MassProperties {
    double volume = 0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the centroid, for `mass`
};

// Volume, centroid and (for mass > 0) the inertia tensor of a closed oriented mesh.
MassProperties massProperties(const TriMesh& mesh, double mass);

class ShapeBuilder {
public:
    // Base disc at z = 0, dome down to z = -height. `segments` around the axis.
    static TriMesh semiSpheroid(double radius, double height, int segments);
    // Base disc at z = 0, apex at z = -height; tipRadius > 0 replaces the apex by a flat disc
    // of that radius at z = -height (a truncated cone of the same height).
    static TriMesh cone(double radius, double height, int segments, double tipRadius = 0.0);
    // Cube of side `side` centred at the origin, each corner cut `cut` along its three edges.
    static TriMesh truncatedCube(double side, double cut);

    static double semiSpheroidVolume(double r, double h);
    static double coneVolume(double r, double h, double tipRadius = 0.0);
    static double truncatedCubeVolume(double s, double c);
    // Principal moment (all three equal by cubic symmetry) of the truncated cube.
    static double truncatedCubeInertia(double s, double c, double mass);
};

enum class ShapeKind { Spheroid, Cone, TruncatedCube };
const char* shapeKindName(ShapeKind k);  // "spheroid", "cone", "truncated-cube"
// Parses a shape kind's name; false for anything else.
bool parseShapeKind(const std::string& text, ShapeKind& k);

// A shape of wirenet-gen shape: a platter (spheroid, cone) or the impact block. No defaults
// here: they depend on the kind (the command line's options hold them).
struct ShapeParams {
    ShapeKind kind = ShapeKind::Spheroid;
    double radius = 0, height = 0;   // spheroid, cone: base radius, depth below z = 0, m
    double tipRadius = 0;            // cone: flat tip disc instead of the apex (0 = sharp), m
    int resolution = 0;              // spheroid, cone: segments around the axis
    double side = 0, cornerCut = 0;  // truncated cube, m
    double mass = 0;                 // kg, for the inertia tensor; 0 = none

    // Throws UsageError unless the cone's tip stays inside its base and the cube's corner cuts
    // inside a face. Each number's own range (> 0) is the option parser's.
    void validate() const;
    TriMesh mesh() const;
    double volume() const;  // analytic
};

}  // namespace wirenet
