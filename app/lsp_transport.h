// The language server's framing: JSON-RPC messages on a byte stream, each a header block
// (`Content-Length: N`, other headers ignored, CRLF line ends, a blank line) and N bytes of body.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace wsd::app::lsp {

class Reader {
public:
    explicit Reader(int fd) : fd_(fd) {}

    enum class Result {
        Message,    // `body` holds a whole body
        BadHeader,  // a header block without a usable Content-Length (`body` says why); skipped
        End,        // end of input
    };
    // Reads the next message. Garbage before a header is skipped up to the next `Content-Length:`;
    // a body shorter than announced at the end of input is End; one longer than max_body is a
    // BadHeader, and its bytes are scanned as garbage.
    Result read(std::string& body);
    // Whether a byte is ready without blocking (in the buffer or on the descriptor).
    bool input_pending();
    // Whether a byte (or the end of input) is ready within `timeout_ms` (-1: no limit), without
    // reading it; false also once `wake_fd` (if not -1) is readable. Safe on another thread while
    // this one is not reading.
    bool wait_input(int timeout_ms, int wake_fd = -1) const;

    static constexpr size_t max_body = size_t(1) << 30;

private:
    bool fill();  // reads more input; false at the end
    bool read_line(std::string& line);
    int fd_;
    std::string buffer_;
    size_t pos_ = 0;
};

// Writes one message with its header; false if the output is gone.
bool write_message(int fd, std::string_view body);

}  // namespace wsd::app::lsp
