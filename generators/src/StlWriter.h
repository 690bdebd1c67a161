// A shape's files: ASCII STL (LIGGGHTS' mesh reader takes ASCII), facet normals from the vertex
// order, and the metadata of FILE.json (parameters, volumes, centroid, inertia).
#pragma once
#include <ostream>
#include <string>

#include "Json.h"
#include "Shapes.h"

namespace wirenet {

class StlWriter {
public:
    static void write(std::ostream& os, const TriMesh& mesh, const std::string& name);
    // `mp` the mesh's mass properties (an inertia tensor if p.mass > 0); `command` the command
    // line after "wirenet-gen ", `stl` the STL file's path.
    static Json metadata(const ShapeParams& p, const TriMesh& mesh, const MassProperties& mp,
                         const std::string& command, const std::string& stl);
};

}  // namespace wirenet
