#include "AtomicFile.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "Options.h"

namespace wirenet {

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp" + std::to_string(::getpid())) {
    out_.open(tmp_, std::ios::out | std::ios::trunc);
    if (!out_) throw UsageError("--out cannot write " + path_ + " (" + std::strerror(errno) + ")");
}

AtomicFile::~AtomicFile() {
    if (out_.is_open()) out_.close();
    if (!committed_) std::remove(tmp_.c_str());
}

void AtomicFile::close() {
    out_.flush();
    bool ok = bool(out_);
    out_.close();
    if (!ok) throw UsageError("--out cannot write " + path_ + " (write failed)");
}

void AtomicFile::commit() {
    if (out_.is_open()) close();
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
        throw UsageError("--out cannot write " + path_ + " (" + std::strerror(errno) + ")");
    committed_ = true;
}

}  // namespace wirenet
