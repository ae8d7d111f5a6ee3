// The files a live preview depends on, watched with inotify. Editors save by rewriting a file or
// by writing a new one and renaming it over the old, so the watches are on the directories and
// the events are matched against the files' names.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace wsd::app {

class FileWatcher {
public:
    FileWatcher();  // check ok() before use
    ~FileWatcher();
    FileWatcher(const FileWatcher&) = delete;
    FileWatcher& operator=(const FileWatcher&) = delete;

    bool ok() const { return fd_ >= 0; }
    const std::string& error() const { return error_; }

    // The files to watch from now on (any relative path is taken from the working directory).
    // With `whole_directories`, any file saved in their directories counts too: a scene that
    // names a missing file recovers when that file appears.
    void watch(const std::vector<std::string>& files, bool whole_directories);

    // Waits up to `timeout_ms` for a watched file to be saved, renamed into place or deleted;
    // true when one was (the burst of events one save makes is taken as one).
    bool wait(int timeout_ms);

private:
    bool read_events();  // true when an event concerned a watched file

    int fd_ = -1;
    std::string error_;
    std::map<int, std::string> directories_;  // watch descriptor → directory
    std::set<std::string> watched_dirs_;
    std::set<std::string> files_;  // absolute paths
    bool whole_directories_ = false;
};

}  // namespace wsd::app
