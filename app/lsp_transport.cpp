// Content-Length framing over file descriptors. Anything that is not a header line is skipped up
// to the next `Content-Length:` (so garbage bytes cost nothing but a parse error), and a body is
// read in full however it arrives.
#include "app/lsp_transport.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>

namespace wsd::app::lsp {

namespace {

constexpr std::string_view kLengthHeader = "content-length:";

// The position of `Content-Length:` in `line`, case-insensitively, or npos.
size_t find_length_header(std::string_view line) {
    for (size_t i = 0; i + kLengthHeader.size() <= line.size(); ++i) {
        size_t k = 0;
        while (k < kLengthHeader.size() &&
               std::tolower(static_cast<unsigned char>(line[i + k])) == kLengthHeader[k])
            ++k;
        if (k == kLengthHeader.size()) return i;
    }
    return std::string_view::npos;
}

}  // namespace

bool Reader::fill() {
    if (pos_ > 0 && pos_ == buffer_.size()) {
        buffer_.clear();
        pos_ = 0;
    } else if (pos_ > (size_t(1) << 20)) {
        buffer_.erase(0, pos_);
        pos_ = 0;
    }
    char chunk[65536];
    for (;;) {
        const ssize_t n = ::read(fd_, chunk, sizeof chunk);
        if (n > 0) {
            buffer_.append(chunk, static_cast<size_t>(n));
            return true;
        }
        if (n < 0 && errno == EINTR) continue;
        return false;
    }
}

bool Reader::read_line(std::string& line) {
    for (;;) {
        const size_t nl = buffer_.find('\n', pos_);
        if (nl != std::string::npos) {
            line.assign(buffer_, pos_, nl - pos_);
            pos_ = nl + 1;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            return true;
        }
        // A line longer than any header is garbage: keep only its tail, where a header may start.
        if (buffer_.size() - pos_ > 4096) pos_ = buffer_.size() - 64;
        if (!fill()) return false;
    }
}

bool Reader::input_pending() {
    if (pos_ < buffer_.size()) return true;
    pollfd p{fd_, POLLIN, 0};
    return ::poll(&p, 1, 0) > 0;
}

bool Reader::wait_input(int timeout_ms, int wake_fd) const {
    if (pos_ < buffer_.size()) return true;
    pollfd p[2] = {{fd_, POLLIN, 0}, {wake_fd, POLLIN, 0}};
    return ::poll(p, wake_fd < 0 ? 1 : 2, timeout_ms) > 0 && p[0].revents != 0;
}

Reader::Result Reader::read(std::string& body) {
    std::string line;
    bool have_length = false, bad = false, in_header = false;
    size_t length = 0;
    for (;;) {
        if (!read_line(line)) return Result::End;
        if (line.empty()) {
            if (!in_header) continue;  // blank lines between messages
            break;
        }
        const size_t at = find_length_header(line);
        if (at != std::string_view::npos) {
            // A new header block starts here (garbage before it on the line is dropped).
            in_header = true;
            bad = false;
            std::string_view value = std::string_view(line).substr(at + kLengthHeader.size());
            while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
            while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.remove_suffix(1);
            const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), length);
            have_length = ec == std::errc() && end == value.data() + value.size();
            if (!have_length) bad = true;
        } else if (in_header && line.find(':') == std::string::npos) {
            bad = true;  // not a header line inside a header block
        }
    }
    if (!have_length || bad) {
        body = have_length ? "a malformed header line" : "a header block without a valid Content-Length";
        return Result::BadHeader;
    }
    if (length > max_body) {
        // Not read: what follows is scanned for the next header like any garbage.
        body = "a message of " + std::to_string(length) + " bytes, over the limit";
        return Result::BadHeader;
    }
    while (buffer_.size() - pos_ < length)
        if (!fill()) return Result::End;
    body.assign(buffer_, pos_, length);
    pos_ += length;
    return Result::Message;
}

bool write_message(int fd, std::string_view body) {
    std::string out = "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n";
    out.append(body);
    size_t done = 0;
    while (done < out.size()) {
        const ssize_t n = ::write(fd, out.data() + done, out.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += static_cast<size_t>(n);
    }
    return true;
}

}  // namespace wsd::app::lsp
