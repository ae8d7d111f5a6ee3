// OpenEXR output and auxiliary images through the real binary: `.exr` files read back with the
// OpenEXR library (and `exrheader` where installed) equal the PFM render bit for bit, AOV layers
// and sibling files carry the right names and values, tiles carry them and merge into the single
// render, `wsd diff` reads `.exr`, and bad `--aov` lists are usage errors.
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <bit>
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>

#include "app/tile_file.h"
#include "app_test_util.h"

using namespace wsd::test;

namespace {

struct Exr {
    int width = 0, height = 0;
    Imf::Compression compression = Imf::NO_COMPRESSION;
    std::map<std::string, Imf::PixelType> types;
    std::map<std::string, std::vector<float>> channels;  // top row first
};

Exr read_exr(const std::string& path) {
    Imf::InputFile file(path.c_str());
    Exr out;
    const Imath::Box2i dw = file.header().dataWindow();
    out.width = dw.max.x - dw.min.x + 1;
    out.height = dw.max.y - dw.min.y + 1;
    out.compression = file.header().compression();
    Imf::FrameBuffer frame;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
        out.types[it.name()] = it.channel().type;
        std::vector<float>& data = out.channels[it.name()];
        data.resize(size_t(out.width) * size_t(out.height));
        frame.insert(it.name(), Imf::Slice::Make(Imf::FLOAT, data.data(), dw, sizeof(float),
                                                 sizeof(float) * size_t(out.width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
    return out;
}

// A PFM file (little-endian, as wsd writes it) as top-row-first floats and its channel count.
std::vector<float> read_pfm(const std::string& path, int& channels, int& width, int& height) {
    const std::string bytes = read_file(path);
    std::istringstream in(bytes);
    std::string magic;
    double scale = 0;
    in >> magic >> width >> height >> scale;
    REQUIRE((magic == "PF" || magic == "Pf"));
    REQUIRE(scale < 0);
    channels = magic == "PF" ? 3 : 1;
    const size_t row = size_t(width) * size_t(channels);
    const size_t start = bytes.size() - row * size_t(height) * 4;
    std::vector<float> out(row * size_t(height));
    for (size_t y = 0; y < size_t(height); ++y)
        std::memcpy(out.data() + y * row, bytes.data() + start + (size_t(height) - 1 - y) * row * 4, row * 4);
    return out;
}

// Channel k of interleaved data with `n` channels.
std::vector<float> channel(const std::vector<float>& data, int n, int k) {
    std::vector<float> out;
    for (size_t i = size_t(k); i < data.size(); i += size_t(n)) out.push_back(data[i]);
    return out;
}

// Same floats, bit for bit (+∞ and −0 included).
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::bit_cast<uint32_t>(a[i]) != std::bit_cast<uint32_t>(b[i])) return false;
    return true;
}

// A red wall filling the view of a camera at −4 z, and a sphere in front of it (7×5 pixels).
const char* const kWallScene =
    "settings { width 7  height 5  supersamples 1 }\n"
    "camera { position <0, 0, -4>  look_at <0, 0, 0>  fov 30 }\n"
    "light point { position <0, 2, -3> }\n"
    "plane { normal <0, 0, -1>  distance 0  material { color <0.75, 0.125, 0.0625> } }\n";

}  // namespace

TEST_CASE("-o scene.exr writes ZIP-compressed float RGB equal to the PFM render", "[exr]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene());
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.pfm").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.exr").status == 0);
    const Exr exr = read_exr(dir / "s.exr");
    CHECK(exr.compression == Imf::ZIP_COMPRESSION);
    CHECK(exr.channels.size() == 3);
    for (const auto& [name, type] : exr.types) CHECK(type == Imf::FLOAT);
    int n = 0, w = 0, h = 0;
    const std::vector<float> pfm = read_pfm(dir / "s.pfm", n, w, h);
    CHECK(exr.width == w);
    CHECK(exr.height == h);
    CHECK(same_bits(exr.channels.at("R"), channel(pfm, 3, 0)));
    CHECK(same_bits(exr.channels.at("G"), channel(pfm, 3, 1)));
    CHECK(same_bits(exr.channels.at("B"), channel(pfm, 3, 2)));

    // `wsd diff` reads .exr: the two files are the same image.
    const RunResult diff = run_wsd(dir, "diff s.exr s.pfm");
    REQUIRE(diff.status == 0);
    CHECK(field(diff.out, "RMSE") == "0");
    CHECK(run_wsd(dir, "diff s.exr s.exr -o heat.exr").status == 0);
    CHECK(read_exr(dir / "heat.exr").width == w);
    write_file(dir / "bad.exr", read_file(dir / "s.exr").substr(0, 100));
    const RunResult bad = run_wsd(dir, "diff bad.exr s.pfm");
    CHECK(bad.status == 1);
    CHECK(bad.err.find("bad.exr") != std::string::npos);
}

TEST_CASE("the OpenEXR tools read the EXR file wsd writes", "[exr]") {
    if (std::system("command -v exrheader >/dev/null 2>&1") != 0) {
        WARN("exrheader is not installed (Debian package openexr); skipped");
        return;
    }
    TempDir dir;
    write_file(dir / "s.wsd", kWallScene);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.exr --aov albedo,normal,depth").status == 0);
    const std::string out = dir / "header.txt";
    REQUIRE(std::system(("exrheader " + shell_quote(dir / "s.exr") + " > " + shell_quote(out)).c_str()) == 0);
    const std::string header = read_file(out);
    for (const char* name :
         {"albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z", "depth.Z"})
        CHECK(header.find(std::string(name) + ", 32-bit floating-point") != std::string::npos);
    CHECK(header.find("    R, 32-bit floating-point") != std::string::npos);
    CHECK(header.find("zip") != std::string::npos);
    CHECK(header.find("(0 0) - (6 4)") != std::string::npos);

    // The OpenEXR tools' tiled copy of the file reads back as the same image.
    if (std::system("command -v exrmaketiled >/dev/null 2>&1") != 0) return;
    REQUIRE(std::system(("exrmaketiled " + shell_quote(dir / "s.exr") + " " + shell_quote(dir / "tiled.exr") +
                         " >/dev/null")
                            .c_str()) == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.pfm").status == 0);
    const RunResult diff = run_wsd(dir, "diff tiled.exr s.pfm");
    REQUIRE(diff.status == 0);
    CHECK(field(diff.out, "RMSE") == "0");
}

TEST_CASE("AOV layers of an .exr: albedo of a red wall, normal towards the camera, analytic depth",
          "[exr][aov]") {
    TempDir dir;
    write_file(dir / "s.wsd", kWallScene);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.exr --aov albedo,normal,depth").status == 0);
    const Exr exr = read_exr(dir / "s.exr");
    std::vector<std::string> names;
    for (const auto& [name, data] : exr.channels) names.push_back(name);
    CHECK(names == std::vector<std::string>{"B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth.Z",
                                            "normal.X", "normal.Y", "normal.Z"});
    for (size_t i = 0; i < 35; ++i) {
        CHECK(exr.channels.at("albedo.R")[i] == 0.75f);
        CHECK(exr.channels.at("albedo.G")[i] == 0.125f);
        CHECK(exr.channels.at("albedo.B")[i] == 0.0625f);
        CHECK(exr.channels.at("normal.X")[i] == 0.0f);
        CHECK(exr.channels.at("normal.Y")[i] == 0.0f);
        CHECK(exr.channels.at("normal.Z")[i] == -1.0f);
    }
    CHECK(exr.channels.at("depth.Z")[2 * 7 + 3] == 4.0f);  // the centre pixel looks straight ahead
    CHECK(exr.channels.at("depth.Z")[0] > 4.0f);
    CHECK(exr.channels.at("depth.Z")[0] < 4.5f);
}

TEST_CASE("AOVs with another format are sibling PFM files equal to the EXR layers", "[exr][aov]") {
    TempDir dir;
    write_file(dir / "s.wsd", std::string(kWallScene) +
                                  "sphere { center <0, 0, -2>  radius 0.3  material { color <0, 1, 0> } }\n");
    RunResult r = run_wsd(dir, "render s.wsd -o out.png --aov depth,albedo");
    REQUIRE(r.status == 0);
    CHECK(r.err.find("out.albedo.pfm, out.depth.pfm") != std::string::npos);
    CHECK(fs::exists(dir / "out.png"));
    CHECK(fs::exists(dir / "out.albedo.pfm"));
    CHECK(fs::exists(dir / "out.depth.pfm"));
    CHECK_FALSE(fs::exists(dir / "out.normal.pfm"));

    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.pfm --aov albedo,normal,depth").status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.exr --aov albedo,normal,depth").status == 0);
    const Exr exr = read_exr(dir / "s.exr");
    int n = 0, w = 0, h = 0;
    const auto albedo = read_pfm(dir / "s.albedo.pfm", n, w, h);
    CHECK(n == 3);
    CHECK(same_bits(exr.channels.at("albedo.R"), channel(albedo, 3, 0)));
    CHECK(same_bits(exr.channels.at("albedo.G"), channel(albedo, 3, 1)));
    CHECK(same_bits(exr.channels.at("albedo.B"), channel(albedo, 3, 2)));
    const auto normal = read_pfm(dir / "s.normal.pfm", n, w, h);
    CHECK(n == 3);
    CHECK(same_bits(exr.channels.at("normal.X"), channel(normal, 3, 0)));
    CHECK(same_bits(exr.channels.at("normal.Y"), channel(normal, 3, 1)));
    CHECK(same_bits(exr.channels.at("normal.Z"), channel(normal, 3, 2)));
    const auto depth = read_pfm(dir / "s.depth.pfm", n, w, h);
    CHECK(n == 1);
    CHECK(same_bits(exr.channels.at("depth.Z"), depth));
    // The sphere at the centre: green albedo, nearer depth (|eye − centre| − r = 1.7).
    CHECK(albedo[3 * (2 * 7 + 3) + 1] == 1.0f);
    CHECK(depth[2 * 7 + 3] == Approx(1.7).epsilon(1e-6));
    // Asking for AOVs leaves the colour as it was.
    REQUIRE(run_wsd(dir, "render s.wsd -q -o plain.pfm").status == 0);
    CHECK(read_file(dir / "plain.pfm") == read_file(dir / "s.pfm"));
}

TEST_CASE("when one AOV file cannot be written, the run leaves none of its files", "[exr][aov]") {
    TempDir dir;
    write_file(dir / "s.wsd", kWallScene);
    fs::create_directory(dir / "out.normal.pfm");  // in the way of the second sibling
    const RunResult r = run_wsd(dir, "render s.wsd -q -o out.png --aov albedo,normal");
    CHECK(r.status == 3);
    CHECK(r.err.find("out.normal.pfm") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out.albedo.pfm"));  // written first, then removed
    CHECK_FALSE(fs::exists(dir / "out.png"));
}

TEST_CASE("misses give albedo and normal 0 and depth +inf", "[exr][aov]") {
    TempDir dir;
    write_file(dir / "s.wsd",
               "settings { width 4  height 4  supersamples 4  background <0.5, 0.5, 0.5> }\n"
               "camera { position <0, 0, -4>  look_at <0, 0, 0> }\n");
    REQUIRE(run_wsd(dir, "render s.wsd -q -o s.exr --aov albedo,normal,depth").status == 0);
    const Exr exr = read_exr(dir / "s.exr");
    for (const char* name : {"albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z"})
        for (const float v : exr.channels.at(name)) CHECK(v == 0.0f);
    for (const float v : exr.channels.at("depth.Z")) CHECK(v == std::numeric_limits<float>::infinity());
}

TEST_CASE("AOVs are the same for any thread count, and tiles carry them and merge them",
          "[exr][aov][tiles]") {
    TempDir dir;
    write_file(dir / "s.wsd", tiny_scene(5, 18));
    const std::string aov = " --aov albedo,normal,depth";
    REQUIRE(run_wsd(dir, "render s.wsd -q -o one.exr --threads 1" + aov).status == 0);
    REQUIRE(run_wsd(dir, "render s.wsd -q -o two.exr --threads 2" + aov).status == 0);
    CHECK(read_file(dir / "one.exr") == read_file(dir / "two.exr"));
    REQUIRE(run_wsd(dir, "render s.wsd -q -o whole.pfm" + aov).status == 0);
    for (int i = 1; i <= 3; ++i)
        REQUIRE(run_wsd(dir, "render s.wsd -q --tile " + std::to_string(i) + "/3 -o t" + std::to_string(i) +
                                 ".pfm" + aov)
                    .status == 0);
    // A tile file is still a PFM of the colour: its first image is the region's pixels.
    CHECK(read_file(dir / "t1.pfm").rfind("PF\n18 6\n", 0) == 0);
    REQUIRE(run_wsd(dir, "merge t2.pfm t3.pfm t1.pfm -o merged.pfm").status == 0);
    for (const char* name : {"merged.pfm", "merged.albedo.pfm", "merged.normal.pfm", "merged.depth.pfm"}) {
        INFO(name);
        std::string whole = name;
        whole.replace(0, 6, "whole");
        CHECK(read_file(dir / name) == read_file(dir / whole));
    }
    REQUIRE(run_wsd(dir, "merge t1.pfm t2.pfm t3.pfm -o merged.exr").status == 0);
    CHECK(read_file(dir / "merged.exr") == read_file(dir / "one.exr"));

    // Tiles that carry different AOVs do not merge.
    REQUIRE(run_wsd(dir, "render s.wsd -q --tile 2/3 -o plain2.pfm").status == 0);
    const RunResult r = run_wsd(dir, "merge t1.pfm plain2.pfm t3.pfm -o bad.pfm");
    CHECK(r.status == 1);
    CHECK(r.err.find("plain2.pfm") != std::string::npos);
    CHECK(r.err.find("auxiliary images") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad.pfm"));
}

TEST_CASE("bad --aov lists and unknown output formats are usage errors", "[exr][aov][cli]") {
    TempDir dir;
    write_file(dir / "s.wsd", kWallScene);
    RunResult r = run_wsd(dir, "render s.wsd -o s.exr --aov albdo");
    CHECK(r.status == 2);
    CHECK(r.err.find("unknown auxiliary image 'albdo'; did you mean 'albedo'?") != std::string::npos);
    for (const char* list : {"''", "albedo,", ",depth", "albedo,,normal", "colour"}) {
        INFO(list);
        r = run_wsd(dir, std::string("render s.wsd -o s.exr --aov ") + list);
        CHECK(r.status == 2);
        CHECK(r.err.find("--aov") != std::string::npos);
    }
    CHECK_FALSE(fs::exists(dir / "s.exr"));
    r = run_wsd(dir, "render s.wsd -o s.xer");
    CHECK(r.status == 2);
    CHECK(r.err.find(".exr") != std::string::npos);
    // Repeating a name is harmless.
    CHECK(run_wsd(dir, "render s.wsd -q -o s.png --aov depth,depth").status == 0);
    CHECK(fs::exists(dir / "s.depth.pfm"));
}

TEST_CASE("tile files carry their AOVs and refuse missing or malformed ones", "[tiles][aov]") {
    wsd::render::Film film;
    film.width = 2;
    film.height = 3;
    film.rgb.assign(18, 0.5f);
    wsd::render::AovFilm aovs;
    for (int i = 0; i < 18; ++i) {
        aovs.albedo.push_back(0.01f * float(i));
        aovs.normal.push_back(-0.02f * float(i));
    }
    for (int i = 0; i < 6; ++i)
        aovs.depth.push_back(i == 4 ? std::numeric_limits<float>::infinity() : float(i));
    wsd::app::TileMeta meta;
    meta.full_width = 2;
    meta.full_height = 6;
    meta.region = {0, 3, 2, 6};
    meta.scene_hash = meta.settings_hash = "0";
    meta.aovs.albedo = meta.aovs.depth = true;
    const std::string bytes = wsd::app::encode_tile(film, aovs, meta);
    CHECK(bytes.find("\"aovs\":[\"albedo\",\"depth\"]") != std::string::npos);

    wsd::render::Film f;
    wsd::render::AovFilm a;
    wsd::app::TileMeta m;
    std::string error;
    REQUIRE(wsd::app::decode_tile(bytes, f, a, m, error));
    CHECK(m.aovs == meta.aovs);
    CHECK(f.rgb == film.rgb);
    CHECK(same_bits(a.albedo, aovs.albedo));
    CHECK(same_bits(a.depth, aovs.depth));
    CHECK(a.normal == std::vector<float>(18, 0.0f));  // not carried: zero-filled

    CHECK_FALSE(wsd::app::decode_tile(bytes.substr(0, bytes.size() - 8), f, a, m, error));
    CHECK(error.find("depth") != std::string::npos);
    const std::string no_aovs = bytes.substr(0, bytes.find('\n', bytes.find("WSDTILE")) + 1);
    CHECK_FALSE(wsd::app::decode_tile(no_aovs, f, a, m, error));
    CHECK(error.find("albedo") != std::string::npos);
    std::string unknown = bytes;
    unknown.replace(unknown.find("\"depth\"]"), 7, "\"dpeth\"");
    CHECK_FALSE(wsd::app::decode_tile(unknown, f, a, m, error));
    CHECK(error.find("'aovs'") != std::string::npos);
}

TEST_CASE("wsd diff reads an EXR whose data window does not start at the origin", "[exr]") {
    TempDir dir;
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(9, 9)), data(Imath::V2i(2, 3), Imath::V2i(4, 5));
    Imf::Header header(display, data);
    std::vector<float> grey(9);
    for (size_t i = 0; i < 9; ++i) grey[i] = 0.1f * float(i);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    {
        Imf::OutputFile file((dir / "grey.exr").c_str(), header);
        Imf::FrameBuffer frame;
        frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, grey.data(), data, sizeof(float), 3 * sizeof(float)));
        file.setFrameBuffer(frame);
        file.writePixels(3);
    }
    // The same pixels as a PFM: grey replicated in R, G, B, bottom row first.
    std::string pfm = "PF\n3 3\n-1.0\n";
    for (int y = 2; y >= 0; --y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c)
                pfm.append(reinterpret_cast<const char*>(&grey[size_t(y * 3 + x)]), 4);
    write_file(dir / "grey.pfm", pfm);
    const RunResult diff = run_wsd(dir, "diff grey.exr grey.pfm");
    REQUIRE(diff.status == 0);
    CHECK(field(diff.out, "RMSE") == "0");
}
