// Animation on the command line (`wsd render --frames A-B [--frame N]`, `--clock X`): the plan of
// which frames to render with which `clock`, output names with their `#` runs replaced by the
// frame number, and the run over the frames that stops at the first one that fails.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "app/commands.h"
#include "lang/builtins.h"

namespace wsd::app {

// The largest frame number --frames and --frame accept.
constexpr long long max_frame_number = 999999999;

struct FramePlan {
    bool animated = false;          // --frames was given
    long long first = 0, last = 0;  // its range A-B
    long long from = 0, to = 0;     // the frames to render, in order: all of A-B, or --frame N
    double still_clock = 0;         // --clock X, for a still

    // How many frames the run renders.
    size_t count() const { return static_cast<size_t>(to - from + 1); }
    // `clock` and `frame` of frame n: n and (n − A)/(B − A), clock 0 when A = B.
    lang::AnimationTime time_of(long long n) const;
};

// Parses "A-B" (0 ≤ A ≤ B ≤ max_frame_number); false + a message.
bool parse_frame_range(const std::string& text, long long& first, long long& last, std::string& error);

// Checks --frames, --frame and --clock against each other and against -o/--stats-json: an exit
// status (2 with a message for every usage error), and `plan` when 0.
int plan_frames(const RenderArgs& args, FramePlan& plan);

// `pattern` with every run of '#' replaced by `frame`, zero-padded to the run's length (a wider
// number is written in full).
std::string frame_path(const std::string& pattern, long long frame);
bool has_frame_marker(const std::string& pattern);

// What one frame of a run is: its time, its number and where the run stands (for progress).
struct FrameJob {
    lang::AnimationTime time;
    bool animated = false;  // a frame of --frames (names get the number; tiles record it)
    size_t index = 0, count = 1;
    std::chrono::steady_clock::time_point run_start = std::chrono::steady_clock::now();

    // The fraction of the whole run done when this frame is `fraction` done.
    double run_fraction(double fraction) const {
        return (static_cast<double>(index) + fraction) / static_cast<double>(count);
    }
    // "frame 7 (3/48)" for a run of several frames, "frame 7" for one, "render" for a still.
    std::string progress_label() const;
};

// Renders every frame of `plan` in order with `render_frame`, stopping at the first that does not
// return 0 (that status is the run's; the frames before it stay written, and for frames wsd says
// where it stopped).
int run_frames(const FramePlan& plan, const std::function<int(const FrameJob&)>& render_frame);

}  // namespace wsd::app
