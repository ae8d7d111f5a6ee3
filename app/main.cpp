// The `wsd` executable: runs the command line, makes a lost write to stdout exit status 3, and
// turns anything thrown into exit status 4 with a request for a bug report (wsd-cli.md, "Exit
// status").
#include <exception>
#include <iostream>

#include "app/commands.h"
#include "app/exit_codes.h"
#include "app/io_util.h"

int main(int argc, char** argv) {
    try {
        return wsd::app::flush_stdout(wsd::app::run_cli(argc, argv));
    } catch (const std::exception& e) {
        std::cerr << "wsd: internal error: " << e.what()
                  << "\nThis is a bug in wsd; please report it with the command line and the "
                     "scene that caused it.\n";
    } catch (...) {
        std::cerr << "wsd: internal error: unknown exception\nThis is a bug in wsd; please "
                     "report it with the command line and the scene that caused it.\n";
    }
    return wsd::app::exit_code::internal;
}
