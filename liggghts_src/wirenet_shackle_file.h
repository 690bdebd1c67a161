/* WireNet: the shackle file of fix wirenet/shackle (doc/file_formats.md, "shackle file"): the
   ropes as ordered lists of atom IDs and the shackles as (atom ID, rope ID). No LIGGGHTS
   dependency; every check that needs only the text is made here, the atoms' existence by the fix. */

#ifndef WIRENET_SHACKLE_FILE_H
#define WIRENET_SHACKLE_FILE_H

#include <string>
#include <vector>

namespace WireNet {

struct ShackleRope {
  std::string id;               // ROPE_ID as written (a word)
  std::vector<long long> atoms; // atom IDs in order along the rope, >= 2, no repeats
  int line = 0;
};

struct ShackleEntry {
  long long atom = 0;  // the shackle atom's ID
  int rope = 0;        // index into ShackleFile::ropes
  int line = 0;
};

struct ShackleFile {
  std::vector<ShackleRope> ropes;
  std::vector<ShackleEntry> shackles;
};

// Parses the file's text; throws std::invalid_argument with a one-line message naming the line
// and the item ("line 7: rope 'top' has 1 atom (a rope needs at least 2)").
ShackleFile parse_shackle_file(const std::string &text);

}  // namespace WireNet

#endif
