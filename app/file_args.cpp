// Directory arguments: the scene files under them, in an order that does not depend on the
// file system.
#include "app/file_args.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "app/io_util.h"

namespace wsd::app {

namespace fs = std::filesystem;

std::vector<std::string> expand_scene_paths(const std::vector<std::string>& args, bool warn_empty) {
    std::vector<std::string> paths;
    for (const std::string& arg : args) {
        std::error_code ec;
        if (arg == "-" || !fs::is_directory(arg, ec)) {
            paths.push_back(arg);
            continue;
        }
        std::vector<std::string> found;
        for (fs::recursive_directory_iterator it(arg, ec), end; !ec && it != end; it.increment(ec)) {
            const fs::path& p = it->path();
            if ((p.extension() == ".wsd" || p.extension() == ".wsdi") && it->is_regular_file(ec))
                found.push_back(p.string());
        }
        // `wsd fmt --check scenes/` on a directory without scenes (or a mistyped one) checks
        // nothing: say so, not silently succeed.
        if (found.empty() && warn_empty) warn("no .wsd or .wsdi file under '" + arg + "'");
        std::sort(found.begin(), found.end());
        paths.insert(paths.end(), found.begin(), found.end());
    }
    return paths;
}

}  // namespace wsd::app
