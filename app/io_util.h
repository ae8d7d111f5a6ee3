// Small file helpers shared by the commands: reading a command-line input (or stdin for "-"),
// writing an output atomically (temporary file in the same directory, then rename), checking
// early that an output can be written, and printing `wsd: error: ...` lines.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace wsd::app {

// Reads the whole file ("-" = stdin). False + a message naming the path on failure.
bool read_input_file(const std::string& path, std::string& text, std::string& error);

// True when `path` names an existing regular file we can open for reading; else false + message.
bool can_open_for_reading(const std::string& path, std::string& error);

// False + message when the directory that would hold `path` does not exist (it is never created),
// is not writable, or `path` itself is a directory. True for an existing device, FIFO or socket.
bool output_directory_exists(const std::string& path, std::string& error);

// Whether two paths name the same file: the same once made absolute and normal, or, when both
// exist, the same file (links).
bool same_path(const std::string& a, const std::string& b);

// How write_file_atomic writes: the permission bits of the file (exactly these, whatever the
// umask; by default 0644 less the umask, as for any new file), and a flag that, once set (by a
// signal), stops the write.
struct AtomicWrite {
    std::optional<unsigned> mode;
    const std::atomic<bool>* cancel = nullptr;
};

// Writes `data` to a temporary file next to `path`, then renames it over `path`. On failure, and
// when `how.cancel` is set before the rename (error "interrupted"), nothing is left behind. An
// existing `path` that is a device, FIFO or socket (/dev/null, /dev/stdout) is written in place.
bool write_file_atomic(const std::string& path, std::string_view data, std::string& error,
                       const AtomicWrite& how = {});

// Removes an output that write_file_atomic wrote, when a later part of the same output failed. A
// device, FIFO or socket written in place (/dev/stdout) is left as it is.
void remove_output(const std::string& path);

// Flushes stdout. When something written to it was lost (a full disk, /dev/full), says so and
// returns exit_code::io in place of a `status` of success or input errors; else `status`.
int flush_stdout(int status);

// `wsd: error: message` on stderr; returns `status` so callers can `return fail(...)`.
int fail(int status, const std::string& message);
void warn(const std::string& message);

// FNV-1a, 64 bits: the scene/settings hash of tiles. `seed` chains several pieces.
uint64_t fnv1a64(std::string_view data, uint64_t seed = 0xcbf29ce484222325ull);
std::string hex64(uint64_t value);

// The stem of a scene path for default outputs ("a/b/NAME.wsd" → "NAME"; "-" → "stdin").
std::string scene_stem(const std::string& path);

// "1 light", "3 lights": a count with its noun, plural unless the count is one. `plural` defaults
// to `singular` + "s".
std::string counted(uint64_t count, std::string_view singular, std::string_view plural = {});

// Process memory high-water mark (VmHWM) in bytes, 0 if unknown.
uint64_t peak_memory_bytes();

}  // namespace wsd::app
