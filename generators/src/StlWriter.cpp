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

}  // namespace wirenet
