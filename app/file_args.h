// File arguments of `wsd fmt` and `wsd check`: a directory stands for its .wsd and .wsdi files.
#pragma once

#include <string>
#include <vector>

namespace wsd::app {

// `args` with each directory replaced by the .wsd and .wsdi files under it, recursively, in
// sorted order; other arguments (files, "-", paths that do not exist) stay as given. A directory
// with no such file is a warning on stderr, unless `warn_empty` is false.
std::vector<std::string> expand_scene_paths(const std::vector<std::string>& args, bool warn_empty = true);

}  // namespace wsd::app
