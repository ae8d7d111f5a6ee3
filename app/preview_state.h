// What a live preview shows, shared between the render loop (which writes it) and the HTTP
// handlers (which read it and wait for changes): the last good image, the diagnostics of the
// last load, progress and statistics. Every change bumps a version that waiting readers see.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>

namespace wsd::app {

struct PreviewSnapshot {
    uint64_t version = 0;
    uint64_t generation = 0;  // counts loads: 1 for the first, +1 per save
    std::string phase;        // "loading", "rendering", "done", "error"
    std::string diagnostics;  // as `wsd check` prints them; empty when the scene loads
    // The image on show: the last good one, kept while the scene has errors.
    uint64_t image_id = 0;  // 0: none yet
    uint64_t image_generation = 0;
    int image_width = 0, image_height = 0;  // this stage's size
    int full_width = 0, full_height = 0;    // the scene's size
    int stage = 0, stages = 0;              // 1-based stage of the image
    double progress = 0;                    // of the whole generation's stages, 0 to 1
    std::string stats_json;                 // the last complete render's statistics (an object)
    std::string files_json;                 // the watched files (an array)
};

class PreviewState {
public:
    PreviewSnapshot snapshot() const;
    std::string image_png() const;

    // Waits until the version differs from `seen` or the preview stops, at most `timeout_ms`.
    // The current snapshot; `stopping` tells whether the preview is shutting down.
    PreviewSnapshot wait_change(uint64_t seen, int timeout_ms, bool& stopping) const;

    void begin_generation(uint64_t generation);
    void set_phase(const std::string& phase);
    void set_diagnostics(const std::string& text);  // with phase "error" when not empty
    void set_progress(double progress);
    void set_image(std::string png, int width, int height, int full_width, int full_height, int stage,
                   int stages);
    void set_stats(std::string stats_json);
    void set_files(std::string files_json);
    void stop();

private:
    void changed();  // with mutex_ held

    mutable std::mutex mutex_;
    mutable std::condition_variable cv_;
    PreviewSnapshot s_;
    std::string png_;
    bool stopping_ = false;
};

// The snapshot as the JSON object the page receives.
std::string snapshot_json(const PreviewSnapshot& s);

}  // namespace wsd::app
