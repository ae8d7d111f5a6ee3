// The files a live preview depends on, watched with inotify. Editors save by rewriting a file or
// by writing a new one and renaming it over the old, so the watches are on the directories and
// the events are matched against the files' names. A file reached through a symbolic link is
// watched under its target's name too. A directory that does not exist (yet, or any more) is
// waited for on its nearest existing ancestor; once it appears it is watched, and that counts as
// a save (its files may have been written before the watch).
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
    // names a missing file recovers when that file appears (and since a directory watched only now
    // may have gained it after the load, the next wait() then counts as a save).
    void watch(const std::vector<std::string>& files, bool whole_directories);

    // Waits up to `timeout_ms` for a watched file to be saved, renamed into place or deleted (or
    // its directory to appear); true when one was (the burst of events one save makes is taken
    // as one).
    bool wait(int timeout_ms);

private:
    bool read_events();  // true when an event concerned a watched file
    // Resolves the files again and watches their directories (or the nearest existing ancestors
    // of those missing); true when a directory that was missing is now watched.
    bool refresh();
    bool add_watch(const std::string& dir);  // false when it is not a directory

    int fd_ = -1;
    std::string error_;
    std::vector<std::string> requested_;                // absolute paths, as given
    std::map<int, std::set<std::string>> directories_;  // watch descriptor → directories
    std::map<std::string, int> watched_;                // directory → watch descriptor
    std::set<std::string> files_;                       // absolute paths, links' targets included
    std::set<std::string> needed_;                      // the files' directories
    std::set<std::string> missing_;                     // those of them that were not watched
    bool whole_directories_ = false;
    bool pending_ = false;  // watch() found a change: the next wait() says so
};

}  // namespace wsd::app
