// inotify on the parent directories of the watched files: close-after-write, rename into place
// and deletion, matched by name.
#include "app/preview_watch.h"

#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>

namespace wsd::app {

namespace {

namespace fs = std::filesystem;

std::string absolute_path(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::absolute(fs::path(path), ec);
    if (ec) return path;
    return p.lexically_normal().string();
}

constexpr uint32_t kEvents = IN_CLOSE_WRITE | IN_MOVED_TO | IN_DELETE | IN_MOVED_FROM;

// How long after a save further events are taken as part of it (an editor's write, rename and
// attribute change), in milliseconds.
constexpr int kSettleMs = 25;

}  // namespace

FileWatcher::FileWatcher() {
    fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (fd_ < 0) error_ = std::string("inotify: ") + std::strerror(errno);
}

FileWatcher::~FileWatcher() {
    if (fd_ >= 0) ::close(fd_);
}

void FileWatcher::watch(const std::vector<std::string>& files, bool whole_directories) {
    files_.clear();
    whole_directories_ = whole_directories;
    for (const std::string& file : files) {
        const std::string path = absolute_path(file);
        files_.insert(path);
        const std::string dir = fs::path(path).parent_path().string();
        if (fd_ < 0 || watched_dirs_.count(dir)) continue;
        const int wd = inotify_add_watch(fd_, dir.c_str(), kEvents);
        if (wd < 0) continue;  // a directory that does not exist (yet): the file's load reports it
        directories_[wd] = dir;
        watched_dirs_.insert(dir);
    }
}

bool FileWatcher::read_events() {
    alignas(inotify_event) char buffer[16384];
    bool matched = false;
    for (;;) {
        const ssize_t n = ::read(fd_, buffer, sizeof buffer);
        if (n <= 0) break;  // EAGAIN: drained
        for (ssize_t at = 0; at < n;) {
            const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
            at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
            if (event->mask & IN_IGNORED) {
                auto it = directories_.find(event->wd);
                if (it != directories_.end()) {
                    watched_dirs_.erase(it->second);
                    directories_.erase(it);
                }
                continue;
            }
            auto it = directories_.find(event->wd);
            if (it == directories_.end() || event->len == 0) continue;
            const std::string path = (fs::path(it->second) / event->name).string();
            if (files_.count(path) || whole_directories_) matched = true;
        }
    }
    return matched;
}

bool FileWatcher::wait(int timeout_ms) {
    if (fd_ < 0) {
        ::poll(nullptr, 0, timeout_ms);
        return false;
    }
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
    if (!read_events()) return false;
    // Take the rest of the save's events with it (for at most a few settling periods).
    for (int i = 0; i < 8 && ::poll(&p, 1, kSettleMs) > 0; ++i) read_events();
    return true;
}

}  // namespace wsd::app
