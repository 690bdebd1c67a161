// Writes a NetModel as PREFIX.data (LIGGGHTS read_data), PREFIX.json (metadata) and PREFIX.types.in
// (the type numbers by name, a deck include), exactly as doc/file_formats.md fixes them. The files
// appear together or not at all.
#pragma once
#include <string>

#include "NetModel.h"

namespace wirenet {

class MeshWriter {
public:
    MeshWriter(const NetModel& model, const NetDescription& desc) : model_(model), desc_(desc) {}

    void write(const std::string& prefix) const;
    void writeData(std::ostream& os) const;
    // `variable atom_NAME index T` / `variable bond_NAME index T` for every named type: the decks
    // name types, the generator alone numbers them
    void writeTypes(std::ostream& os) const;
    Json metadata() const;

private:
    const NetModel& model_;
    const NetDescription& desc_;
};

}  // namespace wirenet
