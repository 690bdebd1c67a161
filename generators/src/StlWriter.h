// ASCII STL (LIGGGHTS' mesh reader takes ASCII), facet normals from the vertex order.
#pragma once
#include <ostream>
#include <string>

#include "Shapes.h"

namespace wirenet {

class StlWriter {
public:
    static void write(std::ostream& os, const TriMesh& mesh, const std::string& name);
};

}  // namespace wirenet
