/* WireNet: the shackle file. See wirenet_shackle_file.h and doc/file_formats.md. */

#include "wirenet_shackle_file.h"

#include <cerrno>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace WireNet {

namespace {

[[noreturn]] void fail(int line, const std::string &msg)
{
  throw std::invalid_argument("line " + std::to_string(line) + ": " + msg);
}

// a whole number >= lo (atom IDs: >= 1; counts: >= 0): digits only (strtoll also took '+5' and
// ' 5'), and no larger than a LIGGGHTS atom ID can be (a larger one was later reported as atom -1)
long long whole(const std::string &w, int line, const std::string &what, long long lo)
{
  const long long hi = std::numeric_limits<int>::max();
  errno = 0;
  const long long v = strtoll(w.c_str(), NULL, 10);
  if (w.empty() || w.find_first_not_of("0123456789") != std::string::npos || v < lo)
    fail(line, what + " must be a whole number >= " + std::to_string(lo) + " (got '" + w + "')");
  if (errno || v > hi) fail(line, what + " " + w + " is too large (at most " + std::to_string(hi) + ")");
  return v;
}

}  // namespace

ShackleFile parse_shackle_file(const std::string &text)
{
  // the non-empty lines without comments, with their numbers
  std::vector<std::pair<int, std::vector<std::string>>> lines;
  std::istringstream in(text);
  std::string raw;
  for (int no = 1; std::getline(in, raw); no++) {
    const size_t hash = raw.find('#');
    if (hash != std::string::npos) raw.erase(hash);
    std::istringstream ws(raw);
    std::vector<std::string> words;
    for (std::string w; ws >> w;) words.push_back(w);
    if (!words.empty()) lines.emplace_back(no, words);
  }

  ShackleFile f;
  size_t k = 0;
  auto header = [&](const char *key) -> long long {
    if (k >= lines.size()) fail(lines.empty() ? 1 : lines.back().first + 1, std::string("missing '") + key + " COUNT' line");
    const auto &[no, w] = lines[k];
    if (w[0] != key || w.size() != 2) fail(no, std::string("expected '") + key + " COUNT' (got '" + w[0] + "')");
    k++;
    return whole(w[1], no, std::string(key) + " count", 0);
  };

  const long long nropes = header("ropes");
  std::map<std::string, int> rope_index;
  for (long long r = 0; r < nropes; r++) {
    if (k >= lines.size() || lines[k].second[0] == "shackles")
      fail(k < lines.size() ? lines[k].first : lines.back().first + 1,
           "expected " + std::to_string(nropes) + " rope lines 'ROPE_ID N ID_1 ... ID_N', found " + std::to_string(r));
    const auto &[no, w] = lines[k++];
    ShackleRope rope;
    rope.id = w[0];
    rope.line = no;
    if (rope_index.count(rope.id)) fail(no, "rope '" + rope.id + "' is listed twice");
    if (w.size() < 2) fail(no, "rope '" + rope.id + "': missing the atom count N");
    const long long n = whole(w[1], no, "rope '" + rope.id + "' atom count", 0);
    if ((long long)w.size() - 2 != n)
      fail(no, "rope '" + rope.id + "' says " + std::to_string(n) + " atoms but lists " + std::to_string(w.size() - 2));
    if (n < 2) fail(no, "rope '" + rope.id + "' has " + std::to_string(n) + " atom(s) (a rope needs at least 2)");
    std::set<long long> seen;
    for (size_t m = 2; m < w.size(); m++) {
      const long long id = whole(w[m], no, "rope '" + rope.id + "' atom ID", 1);
      if (!seen.insert(id).second) fail(no, "rope '" + rope.id + "' lists atom " + std::to_string(id) + " twice");
      rope.atoms.push_back(id);
    }
    rope_index[rope.id] = (int)f.ropes.size();
    f.ropes.push_back(rope);
  }

  const long long nshackles = header("shackles");
  std::map<long long, int> shackle_line;
  for (long long s = 0; s < nshackles; s++) {
    if (k >= lines.size())
      fail(lines.back().first + 1, "expected " + std::to_string(nshackles) + " shackle lines 'ATOM_ID ROPE_ID', found " + std::to_string(s));
    const auto &[no, w] = lines[k++];
    if (w.size() != 2) fail(no, "a shackle line is 'ATOM_ID ROPE_ID' (got " + std::to_string(w.size()) + " words)");
    ShackleEntry e;
    e.atom = whole(w[0], no, "shackle atom ID", 1);
    e.line = no;
    auto it = rope_index.find(w[1]);
    if (it == rope_index.end()) fail(no, "shackle atom " + w[0] + ": unknown rope '" + w[1] + "'");
    e.rope = it->second;
    if (shackle_line.count(e.atom))
      fail(no, "shackle atom " + w[0] + " is listed twice (first on line " + std::to_string(shackle_line[e.atom]) + ")");
    for (long long id : f.ropes[e.rope].atoms)
      if (id == e.atom) fail(no, "shackle atom " + w[0] + " is an atom of its own rope '" + w[1] + "'");
    shackle_line[e.atom] = no;
    f.shackles.push_back(e);
  }
  if (k < lines.size())
    fail(lines[k].first, "unexpected line after the " + std::to_string(nshackles) + " shackle lines (starts '" + lines[k].second[0] + "')");
  return f;
}

}  // namespace WireNet
