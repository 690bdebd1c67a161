#include "AtomicFile.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <set>

#include "Usage.h"

namespace wirenet {

namespace {

std::string cannot(const std::string& path, const std::string& why) {
    return "--out cannot write " + path + " (" + why + ")";
}

std::string folderOf(const std::string& path) {
    const auto slash = path.rfind('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

}  // namespace

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp" + std::to_string(::getpid())) {
    out_.open(tmp_, std::ios::out | std::ios::trunc);
    if (!out_) throw UsageError(cannot(path_, std::strerror(errno)));
}

AtomicFile::~AtomicFile() {
    if (out_.is_open()) out_.close();
    if (!committed_) std::remove(tmp_.c_str());
}

void AtomicFile::close() {
    if (!out_.is_open()) return;
    out_.flush();
    bool ok = bool(out_);
    out_.close();
    if (!ok || out_.fail()) throw UsageError(cannot(path_, "write failed"));
}

void AtomicFile::commit() { commitAll({this}); }

void AtomicFile::checkTargets(const std::vector<std::string>& paths) {
    std::set<std::string> seen;
    for (const auto& p : paths) {
        if (p.empty() || p.back() == '/') throw UsageError(cannot(p, "not a file name"));
        if (!seen.insert(p).second) throw UsageError(cannot(p, "named twice"));
        struct stat st;
        if (::stat(p.c_str(), &st) == 0) {
            if (S_ISDIR(st.st_mode)) throw UsageError(cannot(p, "is a directory"));
            if (!S_ISREG(st.st_mode)) throw UsageError(cannot(p, "exists and is not a regular file"));
        }
        const std::string dir = folderOf(p);
        if (::stat(dir.c_str(), &st) != 0) throw UsageError(cannot(p, "folder " + dir + " does not exist"));
        if (!S_ISDIR(st.st_mode)) throw UsageError(cannot(p, dir + " is not a folder"));
        if (::access(dir.c_str(), W_OK | X_OK) != 0)
            throw UsageError(cannot(p, "folder " + dir + " is not writable"));
    }
}

void AtomicFile::commitAll(const std::vector<AtomicFile*>& files) {
    for (AtomicFile* f : files) f->close();
    // Hard-link backups of the outputs being replaced, so that a failed rename can be undone.
    std::vector<std::string> backup(files.size());
    for (size_t i = 0; i < files.size(); ++i) {
        const std::string b = files[i]->path_ + ".bak" + std::to_string(::getpid());
        std::remove(b.c_str());
        if (::link(files[i]->path_.c_str(), b.c_str()) == 0) backup[i] = b;
    }
    for (size_t i = 0; i < files.size(); ++i) {
        if (std::rename(files[i]->tmp_.c_str(), files[i]->path_.c_str()) == 0) {
            files[i]->committed_ = true;
            continue;
        }
        const std::string why = std::strerror(errno);
        for (size_t j = 0; j < i; ++j) {  // undo: restore or remove what was already renamed
            if (!backup[j].empty()) {
                std::rename(backup[j].c_str(), files[j]->path_.c_str());
                backup[j].clear();
            } else {
                std::remove(files[j]->path_.c_str());
            }
        }
        for (const auto& b : backup)
            if (!b.empty()) std::remove(b.c_str());
        throw UsageError(cannot(files[i]->path_, why));
    }
    for (const auto& b : backup)
        if (!b.empty()) std::remove(b.c_str());
}

}  // namespace wirenet
