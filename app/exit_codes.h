// The exit statuses of the `wsd` command (wsd-cli.md, "Exit status"). Every command returns one of
// these from its run function; only main() turns them into the process status.
#pragma once

namespace wsd::app::exit_code {

constexpr int ok = 0;
constexpr int input_error = 1;  // scene errors, malformed image or tile, size mismatch
constexpr int usage = 2;        // unknown option, missing argument, bad value
constexpr int io = 3;           // a command-line file cannot be read or the output cannot be written
constexpr int internal = 4;     // a bug
constexpr int sigint = 130;
constexpr int sigterm = 143;

}  // namespace wsd::app::exit_code
