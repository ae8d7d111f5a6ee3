// inotify on the parent directories of the watched files (and of their links' targets): writes,
// renames, creations and deletions, matched by name; the directories' own deletion and renaming,
// and the creation of directories, make the watches be set up again.
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

// The path with its symbolic links resolved as far as it exists; empty when that fails.
std::string resolved_path(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::path(path), ec);
    if (ec) return {};
    return p.string();
}

constexpr uint32_t kEvents =
    IN_CLOSE_WRITE | IN_MOVED_TO | IN_DELETE | IN_MOVED_FROM | IN_CREATE | IN_DELETE_SELF | IN_MOVE_SELF;

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
    requested_.clear();
    for (const std::string& file : files) requested_.push_back(absolute_path(file));
    whole_directories_ = whole_directories;
    const size_t before = watched_.size();
    // After a failed load, a directory watched only now may have gained the missing file since.
    if (refresh() || (whole_directories && watched_.size() > before)) pending_ = true;
}

bool FileWatcher::add_watch(const std::string& dir) {
    if (watched_.count(dir)) return true;
    if (fd_ < 0) return false;
    const int wd = inotify_add_watch(fd_, dir.c_str(), kEvents | IN_ONLYDIR);
    if (wd < 0) return false;
    directories_[wd].insert(dir);
    watched_[dir] = wd;
    return true;
}

bool FileWatcher::refresh() {
    files_.clear();
    needed_.clear();
    for (const std::string& file : requested_) {
        files_.insert(file);
        const std::string target = resolved_path(file);
        if (!target.empty()) files_.insert(target);
    }
    for (const std::string& file : files_) needed_.insert(fs::path(file).parent_path().string());
    bool appeared = false;
    std::set<std::string> missing;
    for (const std::string& dir : needed_) {
        if (add_watch(dir)) {
            appeared = appeared || missing_.count(dir) > 0;
            continue;
        }
        missing.insert(dir);
        for (fs::path up = fs::path(dir).parent_path(); !add_watch(up.string()); up = up.parent_path())
            if (up == up.parent_path()) break;
    }
    missing_ = std::move(missing);
    return appeared;
}

bool FileWatcher::read_events() {
    alignas(inotify_event) char buffer[16384];
    bool matched = false, moved = false;
    for (;;) {
        const ssize_t n = ::read(fd_, buffer, sizeof buffer);
        if (n <= 0) break;  // EAGAIN: drained
        for (ssize_t at = 0; at < n;) {
            const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
            at += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
            auto it = directories_.find(event->wd);
            if (it == directories_.end()) continue;
            if (event->mask & IN_IGNORED) {  // the directory is gone, or its watch removed
                for (const std::string& dir : it->second) {
                    watched_.erase(dir);
                    if (needed_.count(dir)) missing_.insert(dir);
                }
                directories_.erase(it);
                moved = true;
                continue;
            }
            if (event->mask & (IN_DELETE_SELF | IN_MOVE_SELF)) {
                for (const std::string& dir : it->second) matched = matched || needed_.count(dir) > 0;
                if (event->mask & IN_MOVE_SELF) inotify_rm_watch(fd_, event->wd);  // its path is stale
                moved = true;
                continue;
            }
            if (event->len == 0) continue;
            if (event->mask & IN_ISDIR) moved = true;  // a path may lead elsewhere now
            for (const std::string& dir : it->second) {
                const std::string path = (fs::path(dir) / event->name).string();
                if (files_.count(path) || (whole_directories_ && needed_.count(dir))) matched = true;
            }
        }
    }
    // A save may have replaced a link (or a directory): resolve and watch again.
    if ((matched || moved) && refresh()) matched = true;
    return matched;
}

bool FileWatcher::wait(int timeout_ms) {
    if (fd_ < 0) {
        ::poll(nullptr, 0, timeout_ms);
        return false;
    }
    pollfd p{fd_, POLLIN, 0};
    if (pending_) {
        pending_ = false;
        return true;
    }
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
    if (!read_events()) return false;
    // Take the rest of the save's events with it (for at most a few settling periods).
    for (int i = 0; i < 8 && ::poll(&p, 1, kSettleMs) > 0; ++i) read_events();
    return true;
}

}  // namespace wsd::app
