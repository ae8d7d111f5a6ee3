// The frame plan and the run over frames. Every usage error of --frames/--frame/--clock and of a
// name without '#' for several frames is found here, before the first frame renders.
#include "app/frames.h"

#include <charconv>
#include <cmath>
#include <iostream>

#include "app/exit_codes.h"
#include "app/io_util.h"

namespace wsd::app {

namespace {

bool parse_frame_number(std::string_view text, long long& value) {
    if (text.empty() || text.front() < '0' || text.front() > '9') return false;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && end == text.data() + text.size();
}

// A name that several frames share is a usage error: each frame would overwrite the last.
int needs_marker(const char* option, const std::string& name) {
    return fail(exit_code::usage, std::string(option) + " '" + name +
                                      "': several frames need a run of '#' in the name for the frame "
                                      "number (e.g. frame-####.png)");
}

}  // namespace

lang::AnimationTime FramePlan::time_of(long long n) const {
    if (!animated) return {still_clock, 0};
    const double clock =
        last == first ? 0.0 : static_cast<double>(n - first) / static_cast<double>(last - first);
    return {clock, n};
}

bool parse_frame_range(const std::string& text, long long& first, long long& last, std::string& error) {
    const size_t dash = text.find('-');
    if (dash == std::string::npos || !parse_frame_number(std::string_view(text).substr(0, dash), first) ||
        !parse_frame_number(std::string_view(text).substr(dash + 1), last)) {
        error = "--frames: expected A-B, two whole numbers from 0 (e.g. 1-48), got '" + text + "'";
        return false;
    }
    if (first > max_frame_number || last > max_frame_number) {
        error = "--frames " + text + ": frame numbers go up to " + std::to_string(max_frame_number);
        return false;
    }
    if (first > last) {
        error = "--frames " + text + ": the first frame is after the last (need A <= B)";
        return false;
    }
    return true;
}

int plan_frames(const RenderArgs& args, FramePlan& plan) {
    if (args.frames.empty()) {
        if (args.frame)
            return fail(exit_code::usage, "--frame " + std::to_string(*args.frame) +
                                              " needs --frames A-B: the range it is a frame of");
        if (args.clock && !std::isfinite(*args.clock))
            return fail(exit_code::usage, "--clock must be a finite number");
        plan.still_clock = args.clock.value_or(0.0);
        return exit_code::ok;
    }
    if (args.clock)
        return fail(exit_code::usage,
                    "--clock cannot be used with --frames: each frame's clock comes from the range");
    std::string error;
    if (!parse_frame_range(args.frames, plan.first, plan.last, error)) return fail(exit_code::usage, error);
    plan.animated = true;
    if (args.frame) {
        if (*args.frame < plan.first || *args.frame > plan.last)
            return fail(exit_code::usage,
                        "--frame " + std::to_string(*args.frame) + " is not in --frames " + args.frames);
        plan.from = plan.to = *args.frame;
    } else {
        plan.from = plan.first;
        plan.to = plan.last;
    }
    if (plan.count() > 1) {
        if (!args.output.empty() && !has_frame_marker(args.output)) return needs_marker("-o", args.output);
        if (!args.stats_json.empty() && !has_frame_marker(args.stats_json))
            return needs_marker("--stats-json", args.stats_json);
    }
    return exit_code::ok;
}

bool has_frame_marker(const std::string& pattern) {
    return pattern.find('#') != std::string::npos;
}

std::string frame_path(const std::string& pattern, long long frame) {
    const std::string number = std::to_string(frame);
    std::string out;
    for (size_t i = 0; i < pattern.size();) {
        if (pattern[i] != '#') {
            out += pattern[i++];
            continue;
        }
        size_t run = 0;
        while (i < pattern.size() && pattern[i] == '#') ++i, ++run;
        if (number.size() < run) out.append(run - number.size(), '0');
        out += number;
    }
    return out;
}

std::string FrameJob::progress_label() const {
    if (!animated) return "render";
    std::string label = "frame " + std::to_string(time.frame);
    if (count > 1) label += " (" + std::to_string(index + 1) + "/" + std::to_string(count) + ")";
    return label;
}

int run_frames(const FramePlan& plan, const std::function<int(const FrameJob&)>& render_frame) {
    FrameJob job;
    job.animated = plan.animated;
    job.count = plan.count();
    for (long long n = plan.from; n <= plan.to; ++n) {
        job.index = static_cast<size_t>(n - plan.from);
        job.time = plan.time_of(n);
        if (const int status = render_frame(job); status != exit_code::ok) {
            if (!plan.animated) return status;
            std::cerr << "wsd: stopped at frame " << n << "; ";
            if (n == plan.from)
                std::cerr << "no frame was written\n";
            else if (n - 1 == plan.from)
                std::cerr << "frame " << plan.from << " was written\n";
            else
                std::cerr << "frames " << plan.from << " to " << n - 1 << " were written\n";
            return status;
        }
    }
    return exit_code::ok;
}

}  // namespace wsd::app
