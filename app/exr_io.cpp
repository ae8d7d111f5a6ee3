// EXR encoding and decoding with the OpenEXR library, through in-memory streams so that writes
// stay atomic (the caller renames a complete file into place) and reads share the one file reader.
#include "app/exr_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include <algorithm>
#include <cstring>
#include <exception>

#include "render/limits.h"

namespace wsd::app {

namespace {

constexpr unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};

}  // namespace

bool encode_exr(int width, int height, const std::vector<ExrChannel>& channels, std::string& bytes,
                std::string& error) {
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (const ExrChannel& c : channels) {
            header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
            // The library reads through a non-const pointer but does not write when encoding.
            char* base = reinterpret_cast<char*>(const_cast<float*>(c.data));
            frame.insert(c.name, Imf::Slice(Imf::FLOAT, base, sizeof(float) * c.stride,
                                            sizeof(float) * c.stride * size_t(width)));
        }
        Imf::StdOSStream stream;
        {
            Imf::OutputFile file(stream, header);
            file.setFrameBuffer(frame);
            file.writePixels(height);
        }  // the file is complete once closed
        bytes = stream.str();
        return true;
    } catch (const std::exception& e) {
        error = std::string("OpenEXR: ") + e.what();
        return false;
    }
}

bool looks_like_exr(std::string_view bytes) {
    return bytes.size() >= 4 && std::memcmp(bytes.data(), exr_magic, 4) == 0;
}

bool decode_exr(const std::string& bytes, ExrImage& image, std::string& error,
                const std::vector<std::string>& wanted) {
    try {
        Imf::StdISStream stream;
        stream.str(bytes);
        Imf::InputFile file(stream);
        const Imath::Box2i window = file.header().dataWindow();
        const long long w = static_cast<long long>(window.max.x) - window.min.x + 1;
        const long long h = static_cast<long long>(window.max.y) - window.min.y + 1;
        if (w < 1 || h < 1 || w > render::kMaxImageSide || h > render::kMaxImageSide ||
            w * h > render::kMaxPixels) {
            error = "malformed or too large EXR file (data window " + std::to_string(w) + "x" +
                    std::to_string(h) + ")";
            return false;
        }
        image.width = static_cast<int>(w);
        image.height = static_cast<int>(h);
        image.channels.clear();
        Imf::FrameBuffer frame;
        const size_t pixels = static_cast<size_t>(w * h);
        for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
            const std::string name = it.name();
            if (it.channel().xSampling != 1 || it.channel().ySampling != 1) continue;
            if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), name) == wanted.end()) continue;
            std::vector<float>& data = image.channels[name];
            data.assign(pixels, 0.0f);
            // Make() places the buffer's first pixel at the data window's corner.
            frame.insert(name, Imf::Slice::Make(Imf::FLOAT, data.data(), window, sizeof(float),
                                                sizeof(float) * size_t(w)));
        }
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return true;
    } catch (const std::exception& e) {
        error = std::string("malformed EXR file (") + e.what() + ")";
        return false;
    }
}

bool decode_exr_colour(const std::string& bytes, render::Film& film, std::string& error) {
    ExrImage image;
    if (!decode_exr(bytes, image, error, {"R", "G", "B", "Y"})) return false;
    const auto& ch = image.channels;
    const bool rgb = ch.count("R") || ch.count("G") || ch.count("B");
    if (!rgb && !ch.count("Y")) {
        error = "the EXR file has no R, G, B or Y channel";
        return false;
    }
    film.width = image.width;
    film.height = image.height;
    const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    film.rgb.assign(pixels * 3, 0.0f);
    const char* names[3] = {"R", "G", "B"};
    for (size_t k = 0; k < 3; ++k) {
        const auto it = ch.find(rgb ? names[k] : "Y");
        if (it == ch.end()) continue;
        for (size_t i = 0; i < pixels; ++i) film.rgb[3 * i + k] = it->second[i];
    }
    return true;
}

}  // namespace wsd::app
