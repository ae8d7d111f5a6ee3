// The preview's shared state: one mutex, one condition variable, a version per change.
#include "app/preview_state.h"

#include <chrono>
#include <nlohmann/json.hpp>

namespace wsd::app {

PreviewSnapshot PreviewState::snapshot() const {
    std::lock_guard lock(mutex_);
    return s_;
}

std::string PreviewState::image_png() const {
    std::lock_guard lock(mutex_);
    return png_;
}

PreviewSnapshot PreviewState::wait_change(uint64_t seen, int timeout_ms, bool& stopping) const {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                 [&] { return stopping_ || s_.version != seen; });
    stopping = stopping_;
    return s_;
}

void PreviewState::changed() {
    ++s_.version;
    cv_.notify_all();
}

void PreviewState::begin_generation(uint64_t generation) {
    std::lock_guard lock(mutex_);
    s_.generation = generation;
    s_.phase = "loading";
    s_.progress = 0;
    changed();
}

void PreviewState::set_phase(const std::string& phase) {
    std::lock_guard lock(mutex_);
    s_.phase = phase;
    changed();
}

void PreviewState::set_diagnostics(const std::string& text) {
    std::lock_guard lock(mutex_);
    s_.diagnostics = text;
    if (!text.empty()) s_.phase = "error";
    changed();
}

void PreviewState::set_progress(double progress) {
    std::lock_guard lock(mutex_);
    s_.progress = progress;
    changed();
}

void PreviewState::set_image(std::string png, int width, int height, int full_width, int full_height,
                             int stage, int stages) {
    std::lock_guard lock(mutex_);
    png_ = std::move(png);
    ++s_.image_id;
    s_.image_generation = s_.generation;
    s_.image_width = width;
    s_.image_height = height;
    s_.full_width = full_width;
    s_.full_height = full_height;
    s_.stage = stage;
    s_.stages = stages;
    changed();
}

void PreviewState::set_stats(std::string stats_json) {
    std::lock_guard lock(mutex_);
    s_.stats_json = std::move(stats_json);
    changed();
}

void PreviewState::set_files(std::string files_json) {
    std::lock_guard lock(mutex_);
    s_.files_json = std::move(files_json);
    changed();
}

void PreviewState::stop() {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    changed();
}

std::string snapshot_json(const PreviewSnapshot& s) {
    nlohmann::ordered_json json = {{"version", s.version},
                                   {"generation", s.generation},
                                   {"phase", s.phase},
                                   {"diagnostics", s.diagnostics},
                                   {"image_id", s.image_id},
                                   {"image_generation", s.image_generation},
                                   {"image_width", s.image_width},
                                   {"image_height", s.image_height},
                                   {"width", s.full_width},
                                   {"height", s.full_height},
                                   {"stage", s.stage},
                                   {"stages", s.stages},
                                   {"progress", s.progress}};
    json["stats"] = s.stats_json.empty() ? nlohmann::ordered_json(nullptr)
                                         : nlohmann::ordered_json::parse(s.stats_json, nullptr, false);
    json["files"] = s.files_json.empty() ? nlohmann::ordered_json::array()
                                         : nlohmann::ordered_json::parse(s.files_json, nullptr, false);
    return json.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace wsd::app
