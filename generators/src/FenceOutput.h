// What a fence writes besides its nodes and bonds (doc/file_formats.md): the metadata of
// PREFIX.data and PREFIX.json, and PREFIX.shackles, the ropes and the atoms that hang on them.
#pragma once
#include <ostream>
#include <string>

#include "Fence.h"

namespace wirenet {

// The fence's description for MeshWriter: types, panel, the "fence" keys and the top-level keys
// (anchors, shackles, ropes, posts, masses). All but the box, which the command line's --margin
// and --ylo give. `command` is the command line after "wirenet-gen ".
NetDescription fenceDescription(const FenceParams& p, const FenceModel& f, const std::string& command,
                                const std::string& shacklesFile);

void writeShackles(std::ostream& os, const FenceModel& f, const std::string& command);

}  // namespace wirenet
