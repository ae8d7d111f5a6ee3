// Image files with auxiliary images: the `--aov` list, the sibling names, and writing and reading
// through render/image_io (PNG … PFM) or app/exr_io (OpenEXR).
#include "app/image_files.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "app/exr_io.h"
#include "app/io_util.h"
#include "lang/diagnostics.h"
#include "render/file_util.h"
#include "render/image_io.h"

namespace wsd::app {

namespace {

const std::vector<std::string>& aov_names() {
    static const std::vector<std::string> names{"albedo", "normal", "depth", "samples"};
    return names;
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// The EXR channels of a film and its selected auxiliary images.
std::vector<ExrChannel> exr_channels(const render::Film& film, const render::AovFilm& aovs,
                                     const AovSelection& selection) {
    std::vector<ExrChannel> channels;
    const char* rgb[3] = {"R", "G", "B"};
    const char* xyz[3] = {"X", "Y", "Z"};
    for (size_t k = 0; k < 3; ++k) channels.push_back({rgb[k], film.rgb.data() + k, 3});
    if (selection.albedo)
        for (size_t k = 0; k < 3; ++k)
            channels.push_back({std::string("albedo.") + rgb[k], aovs.albedo.data() + k, 3});
    if (selection.normal)
        for (size_t k = 0; k < 3; ++k)
            channels.push_back({std::string("normal.") + xyz[k], aovs.normal.data() + k, 3});
    if (selection.depth) channels.push_back({"depth.Z", aovs.depth.data(), 1});
    if (selection.samples) channels.push_back({"samples.Y", aovs.samples.data(), 1});
    return channels;
}

bool write_exr(const std::string& path, const render::Film& film, const render::AovFilm& aovs,
               const AovSelection& selection, std::string& error) {
    if (film.width < 1 || film.height < 1) {
        error = "cannot write '" + path + "': the image is empty";
        return false;
    }
    std::string bytes;
    if (!encode_exr(film.width, film.height, exr_channels(film, aovs, selection), bytes, error)) {
        error = "cannot write '" + path + "': " + error;
        return false;
    }
    return write_file_atomic(path, bytes, error);
}

// The bytes of the PFM file of one auxiliary image.
std::string aov_pfm(const render::Film& film, const render::AovFilm& aovs, const std::string& name) {
    if (name == "albedo") return render::encode_pfm(film.width, film.height, 3, aovs.albedo.data());
    if (name == "normal") return render::encode_pfm(film.width, film.height, 3, aovs.normal.data());
    if (name == "samples") return render::encode_pfm(film.width, film.height, 1, aovs.samples.data());
    return render::encode_pfm(film.width, film.height, 1, aovs.depth.data());
}

bool starts_like_exr(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    char head[4] = {};
    const size_t n = std::fread(head, 1, 4, f);
    std::fclose(f);
    return looks_like_exr(std::string_view(head, n));
}

}  // namespace

std::vector<std::string> AovSelection::names() const {
    std::vector<std::string> out;
    if (albedo) out.push_back("albedo");
    if (normal) out.push_back("normal");
    if (depth) out.push_back("depth");
    if (samples) out.push_back("samples");
    return out;
}

bool select_aov(const std::string& name, AovSelection& selection) {
    if (name == "albedo")
        selection.albedo = true;
    else if (name == "normal")
        selection.normal = true;
    else if (name == "depth")
        selection.depth = true;
    else if (name == "samples")
        selection.samples = true;
    else
        return false;
    return true;
}

bool parse_aov_list(const std::string& text, AovSelection& selection, std::string& error) {
    selection = {};
    size_t start = 0;
    while (true) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string name = text.substr(start, comma - start);
        if (name.empty()) {
            error =
                "expected names from albedo, normal, depth, samples separated by commas, got '" + text + "'";
            return false;
        }
        if (!select_aov(name, selection)) {
            const std::string match = lang::closest_match(name, aov_names());
            error = "unknown auxiliary image '" + name + "'" +
                    (match.empty() ? std::string() : "; did you mean '" + match + "'?") +
                    " (known: albedo, normal, depth, samples)";
            return false;
        }
        if (comma == text.size()) return true;
        start = comma + 1;
    }
}

bool known_image_format(const std::string& path) {
    return is_exr_path(path) || render::format_from_extension(path) != render::ImageFormat::Unknown;
}

bool is_exr_path(const std::string& path) {
    return lower_extension(path) == ".exr";
}

std::string unknown_format_message(const std::string& path) {
    if (path == "-")
        return "cannot write '-': images are written to files, not to stdout; name one, such as 'image.png'";
    // A directory (or a name ending in '/') gets told so, with the name of a file in it to use.
    std::error_code ec;
    if (!path.empty() && (path.back() == '/' || std::filesystem::is_directory(path, ec)))
        return "cannot write '" + path + "': it is a directory; name an image file in it, such as '" +
               (std::filesystem::path(path) / "image.png").lexically_normal().string() + "'";
    return "cannot write '" + path +
           "': unknown image format (use .png, .jpg, .jpeg, .bmp, .tga, .hdr, .pfm or .exr)";
}

std::string aov_sibling_path(const std::string& path, const std::string& aov) {
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + "." + aov + ".pfm")).string();
}

std::vector<std::string> output_paths(const std::string& path, const AovSelection& aovs) {
    std::vector<std::string> out;
    if (!is_exr_path(path))
        for (const std::string& name : aovs.names()) out.push_back(aov_sibling_path(path, name));
    out.push_back(path);
    return out;
}

bool write_image_with_aovs(const std::string& path, const render::Film& film, const render::AovFilm& aovs,
                           const AovSelection& selection, std::string& error) {
    if (selection.any() && aovs.empty()) {
        error = "cannot write '" + path + "': no auxiliary images were rendered";
        return false;
    }
    if (is_exr_path(path)) return write_exr(path, film, aovs, selection, error);
    // Each file is written whole or not at all; when one fails, those written before it go too,
    // so that a failed run leaves no part of its output.
    std::vector<std::string> written;
    const auto undo = [&] {
        std::error_code ec;
        for (const std::string& done : written) std::filesystem::remove(done, ec);
        return false;
    };
    for (const std::string& name : selection.names()) {
        const std::string sibling = aov_sibling_path(path, name);
        if (!write_file_atomic(sibling, aov_pfm(film, aovs, name), error)) return undo();
        written.push_back(sibling);
    }
    return render::write_image(path, film, error) || undo();
}

bool write_image_file(const std::string& path, const render::Film& film, std::string& error) {
    return write_image_with_aovs(path, film, render::AovFilm{}, AovSelection{}, error);
}

bool read_image_file(const std::string& path, render::Film& film, std::string& error, bool* eight_bit) {
    if (eight_bit) *eight_bit = false;
    if (!starts_like_exr(path)) return render::read_image(path, film, error, eight_bit);
    render::FileBytes file;
    if (!render::read_whole_file(path, file, error)) {
        error = "cannot read '" + path + "': " + error;
        return false;
    }
    if (!decode_exr_colour(std::string(file.view()), film, error)) {
        error = "cannot read '" + path + "': " + error;
        return false;
    }
    return true;
}

}  // namespace wsd::app
