// The render loop of a live preview: each request (the first, then one per save) loads the scene
// afresh and renders it in stages, coarse to full size, publishing each stage's image into the
// PreviewState; a new request cancels the load or render in flight (a long evaluation and a
// photon map alike). A scene with errors publishes its diagnostics and keeps the last good image.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "app/preview_state.h"
#include "lang/params.h"

namespace wsd::app {

// One stage of the progressive render: the image size divided by `divisor`; coarse stages take
// one ray a pixel, at most `light_grid`×`light_grid` samples per area light (0: the scene's) and
// a small caustic photon map.
struct PreviewStage {
    int divisor = 1;
    bool coarse = false;
    int light_grid = 0;
};

// The stages for a `width`×`height` image: 1/8, 1/4 and 1/2 size while each is smaller than the
// next and at least 8 pixels a side, then the full size.
std::vector<PreviewStage> preview_stages(int width, int height);

// The image as PNG bytes (sRGB, 8 bits), as `wsd render` writes it.
std::string encode_png(int width, int height, const std::vector<float>& rgb);

class PreviewRenderer {
public:
    // `params`: the --define values (may be null; must outlive the renderer).
    PreviewRenderer(PreviewState& state, std::string scene_path, int threads,
                    const lang::ParamTable* params = nullptr);

    void request();  // renders again (cancelling a render in flight)
    void stop();     // ends run() soon; a render in flight is cancelled
    void run();      // the loop; returns after stop()

    // The files the last load read or named, when they changed since the last call (else false).
    // `whole_directories`: the last load failed, so any file in their directories may fix it.
    bool take_watch_list(std::vector<std::string>& files, bool& whole_directories);

private:
    void render_generation(uint64_t generation);
    void publish_files(const std::vector<std::string>& files, bool failed);
    bool superseded() const { return cancel_.load(); }

    PreviewState& state_;
    std::string scene_;
    int threads_ = 0;
    const lang::ParamTable* params_ = nullptr;

    std::mutex mutex_;
    std::condition_variable cv_;
    uint64_t requested_ = 0, started_ = 0;
    bool stopping_ = false;
    std::atomic<bool> cancel_{false};

    std::vector<std::string> files_;
    bool files_changed_ = false, files_failed_ = false;
};

}  // namespace wsd::app
