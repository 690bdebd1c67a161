#include "StlWriter.h"

#include <cstdio>

namespace wirenet {

void StlWriter::write(std::ostream& os, const TriMesh& mesh, const std::string& name) {
    char buf[160];
    os << "solid " << name << "\n";
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Eigen::Vector3d n = mesh.normal(f);
        std::snprintf(buf, sizeof buf, "  facet normal %.9g %.9g %.9g\n", n.x(), n.y(), n.z());
        os << buf << "    outer loop\n";
        for (int v : mesh.faces[f]) {
            const Eigen::Vector3d& p = mesh.vertices[v];
            std::snprintf(buf, sizeof buf, "      vertex %.12g %.12g %.12g\n", p.x(), p.y(), p.z());
            os << buf;
        }
        os << "    endloop\n  endfacet\n";
    }
    os << "endsolid " << name << "\n";
}

namespace {

Json matrixJson(const Eigen::Matrix3d& m) {
    Json a = Json::array();
    for (int i = 0; i < 3; ++i) a.push(Json::vec3(m.row(i)));
    return a;
}

// The options that made the shape, by kind.
Json parametersJson(const ShapeParams& p) {
    Json j = Json::object();
    if (p.kind == ShapeKind::TruncatedCube) return j.set("side", p.side).set("corner_cut", p.cornerCut);
    j.set("radius", p.radius).set("height", p.height).set("resolution", p.resolution);
    if (p.kind == ShapeKind::Cone) j.set("tip_radius", p.tipRadius);
    return j;
}

}  // namespace

Json StlWriter::metadata(const ShapeParams& p, const TriMesh& mesh, const MassProperties& mp,
                         const std::string& command, const std::string& stl) {
    const double analytic = p.volume();
    Json j = Json::object();
    j.set("generator", "wirenet-gen").set("kind", "shape").set("shape", shapeKindName(p.kind));
    j.set("command", "wirenet-gen " + command).set("stl", stl);
    j.set("parameters", parametersJson(p)).set("facets", long(mesh.faces.size()));
    j.set("volume", mp.volume).set("volume_analytic", analytic);
    j.set("volume_rel_error", mp.volume / analytic - 1).set("centroid", Json::vec3(mp.centroid));
    if (p.mass > 0) {
        j.set("mass", p.mass).set("density", p.mass / mp.volume).set("inertia", matrixJson(mp.inertia));
        j.set("inertia_note", "about the centroid, axes of the STL frame, kg m2");
    }
    return j;
}

}  // namespace wirenet
