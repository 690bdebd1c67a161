#include "MeshWriter.h"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "AtomicFile.h"

namespace wirenet {

static const char* kVersion = "0.1.0";

static std::string g(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.12g", v);
    return buf;
}

void MeshWriter::writeData(std::ostream& os) const {
    // LIGGGHTS reads the title line into a 256-byte buffer and takes the rest of a longer one
    // for the next line ("Unknown identifier in data file"); the whole command is in the JSON
    std::string title = "LIGGGHTS data file from wirenet-gen " + desc_.command;
    if (title.size() > 200) title = title.substr(0, 196) + " ...";
    os << title << "\n\n";
    os << model_.nodes.size() << " atoms\n" << model_.bonds.size() << " bonds\n";
    os << desc_.atomTypes << " atom types\n" << desc_.bondTypes << " bond types\n\n";
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
        os << g(desc_.box.lo[i]) << " " << g(desc_.box.hi[i]) << " " << axis[i] << "lo " << axis[i]
           << "hi\n";
    os << "\nAtoms\n\n";
    long id = 1;
    for (const auto& n : model_.nodes) {
        // Density makes the sphere carry the lumped wire mass (the sphere itself is numerical).
        const double volume = M_PI * n.diameter * n.diameter * n.diameter / 6.0;
        os << id++ << " " << n.type << " " << g(n.x.x()) << " " << g(n.x.y()) << " " << g(n.x.z())
           << " " << g(n.diameter) << " " << g(n.mass / volume) << " " << n.molecule << "\n";
    }
    os << "\nBonds\n\n";
    id = 1;
    for (const auto& b : model_.bonds) os << id++ << " " << b.type << " " << b.a + 1 << " " << b.b + 1 << "\n";
}

void MeshWriter::writeTypes(std::ostream& os) const {
    os << "# WireNet deck include from wirenet-gen " << desc_.command.substr(0, 160) << "\n"
       << "# The type numbers of its data file by name (doc/file_formats.md): decks name types as\n"
       << "# ${atom_NAME} and ${bond_NAME}, the generator alone numbers them.\n";
    for (const auto& kv : desc_.atomTypeNames)
        os << "variable        atom_" << kv.second << " index " << kv.first << "\n";
    for (const auto& kv : desc_.bondTypeNames)
        os << "variable        bond_" << kv.second << " index " << kv.first << "\n";
}

static Json countsByType(const std::map<int, long>& counts, int ntypes) {
    Json j = Json::object();
    for (int t = 1; t <= ntypes; ++t) {
        auto it = counts.find(t);
        j.set(std::to_string(t), it == counts.end() ? 0L : it->second);
    }
    return j;
}

static Json names(const std::map<int, std::string>& m) {
    Json j = Json::object();
    for (const auto& kv : m) j.set(std::to_string(kv.first), kv.second);
    return j;
}

Json MeshWriter::metadata() const {
    Json j = Json::object();
    j.set("generator", "wirenet-gen").set("version", kVersion).set("kind", desc_.kind);
    j.set("command", "wirenet-gen " + desc_.command);
    Json counts = Json::object();
    counts.set("atoms", long(model_.nodes.size())).set("bonds", long(model_.bonds.size()));
    counts.set("atoms_per_type", countsByType(model_.atomsPerType(), desc_.atomTypes));
    counts.set("bonds_per_type", countsByType(model_.bondsPerType(), desc_.bondTypes));
    j.set("counts", counts);
    j.set("atom_types", names(desc_.atomTypeNames)).set("bond_types", names(desc_.bondTypeNames));
    j.set("centre", Json::vec3(desc_.centre));
    Json normal = Json::array();
    for (int i = 0; i < 3; ++i) normal.push(desc_.normal[i]);
    j.set("normal", normal);
    Json panel = Json::object();
    panel.set("width", desc_.width).set("height", desc_.height);
    j.set("panel", panel);
    j.set("cells", desc_.cells).set("wires", desc_.wires).set("node", desc_.node);
    const double mass = model_.totalMass();
    j.set("total_mass", mass).set("areal_mass", desc_.area > 0 ? Json(mass / desc_.area) : Json());
    Json bbox = Json::array(), box = Json::array();
    bbox.push(Json::vec3(model_.bboxMin())).push(Json::vec3(model_.bboxMax()));
    box.push(Json::vec3(desc_.box.lo)).push(Json::vec3(desc_.box.hi));
    j.set("bbox", bbox).set("box", box);
    j.set("max_bond_length", model_.maxBondLength());
    if (!desc_.extra.empty()) j.set(desc_.kind, desc_.extra);
    for (const auto& kv : desc_.top.items()) j.set(kv.first, kv.second);
    return j;
}

void MeshWriter::write(const std::string& prefix) const {
    AtomicFile::checkTargets({prefix + ".data", prefix + ".json", prefix + ".types.in"});
    AtomicFile data(prefix + ".data"), meta(prefix + ".json"), types(prefix + ".types.in");
    writeData(data.stream());
    meta.stream() << metadata().dump(2) << "\n";
    writeTypes(types.stream());
    AtomicFile::commitAll({&data, &meta, &types});
}

}  // namespace wirenet
