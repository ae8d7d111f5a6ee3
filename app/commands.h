// The arguments and entry points of every `wsd` command. cli.cpp fills the argument structs from
// the command line (CLI11); each run_* function returns an exit status (exit_codes.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "app/scene_setup.h"

namespace wsd::app {

// Parses argv and runs the chosen command; every error becomes an exit status (never exits).
int run_cli(int argc, char** argv);

struct CheckArgs {
    std::vector<std::string> files;  // a directory: its .wsd and .wsdi files
    bool effects = false;
    bool json = false;  // --format json
    SceneInputArgs input;
};
int run_check(const CheckArgs& args);

struct FmtArgs {
    std::vector<std::string> files;  // a directory: its .wsd and .wsdi files
    bool in_place = false;           // -i
    bool check = false;              // --check
};
int run_fmt(const FmtArgs& args);

struct AstArgs {
    std::string file;
};
int run_ast(const AstArgs& args);

struct RenderArgs {
    std::string scene;
    SceneInputArgs input;
    std::string output;  // empty: ./NAME.png (./NAME.tile-I-of-N.pfm for tiles; NAME-####… for frames)
    SceneOverrides overrides;
    int threads = 0;
    bool no_bvh = false;
    bool general = false;  // the unspecialised integrator (every effect enabled)
    bool stats = false;
    std::string stats_json;
    bool quiet = false;
    bool adaptive_lights = false;
    std::string tile;                // "I/N"
    std::string region;              // "x0,y0,x1,y1"
    std::string aov;                 // auxiliary images, "albedo,normal,depth" or any of them; empty: none
    std::string frames;              // "A-B": an animation (app/frames.h)
    std::optional<long long> frame;  // --frame N: only frame N of --frames
    std::optional<double> clock;     // --clock X: `clock` of a still
    std::optional<double> target_error;  // --target-error E: progressive, each pixel to E
    std::optional<double> time_limit;    // --time-limit T: progressive, passes until T seconds
};
int run_render(const RenderArgs& args);

struct DiffArgs {
    std::string a, b;
    std::string heatmap;
};
int run_diff(const DiffArgs& args);

struct MergeArgs {
    std::vector<std::string> tiles;
    std::string output;
};
int run_merge(const MergeArgs& args);

struct BenchArgs {
    std::string scene;
    SceneInputArgs input;
    std::string dir = ".";
    int repeat = 0;  // 0: 3, or 1 with --quick
    bool quick = false;
    int reference_supersamples = 0;   // 0: 256
    int reference_light_samples = 0;  // N: an N×N grid on every area light; 0: 16 (8 quick)
    int reference_depth = -1;         // -1: max(scene's max_depth, 10)
    int threads = 0;
    int width = 0, height = 0;  // 0: the scene's (or the quick size)
    bool quiet = false;
};
int run_bench(const BenchArgs& args);

// A language server on stdin/stdout; 0 after `shutdown` and `exit`, 1 when input ends without them.
int run_lsp();

struct PreviewArgs {
    std::string scene;
    std::vector<std::string> defines;  // NAME=EXPR, from --define/-D, in order
    std::string host = "127.0.0.1";
    int port = 8642;  // 0: any free port
    int threads = 0;
};
int run_preview(const PreviewArgs& args);

}  // namespace wsd::app
