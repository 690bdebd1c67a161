// Output files written all-or-nothing: every target is checked before anything is written,
// each file is written under a temporary name in its own folder, and all are renamed only when
// all were written. A failed run leaves no file behind and never replaces an earlier good one.
#pragma once
#include <fstream>
#include <string>
#include <vector>

namespace wirenet {

class AtomicFile {
public:
    explicit AtomicFile(std::string path);
    ~AtomicFile();  // removes the temporary file unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return out_; }
    // Flushes and closes; throws UsageError("--out cannot write ...") on I/O failure.
    void close();
    void commit();  // rename temp -> final
    const std::string& path() const { return path_; }

    // Throws UsageError("--out cannot write PATH (why)") unless every path can be created or
    // replaced: a file name (not a folder, not a device), in an existing writable folder, all
    // distinct. Call before building anything that writes.
    static void checkTargets(const std::vector<std::string>& paths);
    // Closes all files, then renames them all; if one rename fails, the ones already renamed
    // are undone (earlier outputs restored from hard-link backups) and UsageError is thrown.
    static void commitAll(const std::vector<AtomicFile*>& files);

private:
    std::string path_, tmp_;
    std::ofstream out_;
    bool committed_ = false;
};

}  // namespace wirenet
