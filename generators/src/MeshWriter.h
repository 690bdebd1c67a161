// Writes a NetModel as PREFIX.data (LIGGGHTS read_data) and PREFIX.json (metadata), exactly as
// doc/file_formats.md fixes them. Both files appear together or not at all.
#pragma once
#include <string>

#include "NetModel.h"

namespace wirenet {

class MeshWriter {
public:
    MeshWriter(const NetModel& model, const NetDescription& desc) : model_(model), desc_(desc) {}

    void write(const std::string& prefix) const;
    void writeData(std::ostream& os) const;
    Json metadata() const;

private:
    const NetModel& model_;
    const NetDescription& desc_;
};

}  // namespace wirenet
