// Writes a file under a temporary name and renames it only on commit(), so that a failed
// run never leaves a partial or stale-looking output behind.
#pragma once
#include <fstream>
#include <string>

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

private:
    std::string path_, tmp_;
    std::ofstream out_;
    bool committed_ = false;
};

}  // namespace wirenet
