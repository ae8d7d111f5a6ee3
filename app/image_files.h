// The image files the commands read and write: the formats known by extension (render's, plus
// OpenEXR), the auxiliary images a render is asked for (`--aov`), and writing an image together
// with them: layers of an `.exr`, or sibling `.pfm` files next to any other format.
#pragma once

#include <string>
#include <vector>

#include "render/renderer.h"

namespace wsd::app {

// Which auxiliary images to write, always in this order.
struct AovSelection {
    bool albedo = false, normal = false, depth = false;
    bool samples = false;  // samples per pixel (progressive rendering only)
    bool any() const { return albedo || normal || depth || samples; }
    bool traced() const { return albedo || normal || depth; }  // those the AOV walk computes
    std::vector<std::string> names() const;  // "albedo", "normal", "depth", "samples" as selected
    bool operator==(const AovSelection&) const = default;
};

// Parses `--aov` text: names from albedo, normal, depth, samples separated by commas (repeats allowed).
// False + what is wrong (with a did-you-mean for a misspelt name), for "--aov: " to precede.
bool parse_aov_list(const std::string& text, AovSelection& selection, std::string& error);

// Selects the AOV called `name`; false when there is none.
bool select_aov(const std::string& name, AovSelection& selection);

// True for .png .jpg .jpeg .bmp .tga .hdr .pfm .exr (case-insensitive).
bool known_image_format(const std::string& path);
bool is_exr_path(const std::string& path);
// "cannot write 'PATH': unknown image format (use .png, …, .pfm or .exr)", or, for a directory
// (or PATH ending in '/'), that it is one and a file in it to name instead; for '-', that images
// are not written to stdout.
std::string unknown_format_message(const std::string& path);

// The sibling file of an auxiliary image: "out/s.png" and "albedo" → "out/s.albedo.pfm".
std::string aov_sibling_path(const std::string& path, const std::string& aov);

// The files write_image_with_aovs writes, the image itself last.
std::vector<std::string> output_paths(const std::string& path, const AovSelection& aovs);

// Writes `film` to `path` in the format its extension names, with the selected auxiliary images
// (`aovs` holds them, same size): layers of the same file for .exr, else sibling PFM files
// written before the image. Each file is written atomically. False + error.
bool write_image_with_aovs(const std::string& path, const render::Film& film, const render::AovFilm& aovs,
                           const AovSelection& selection, std::string& error);

// Writes `film` alone (any format, .exr included). False + error.
bool write_image_file(const std::string& path, const render::Film& film, std::string& error);

// Reads any supported image into linear RGB (.exr by its magic number, the rest as
// render::read_image does; `eight_bit` as there). False + error naming the file.
bool read_image_file(const std::string& path, render::Film& film, std::string& error,
                     bool* eight_bit = nullptr);

}  // namespace wsd::app
