// Whether an image file holds all the pixel data its header promises, for the formats whose
// decoder (stb_image) does not say so itself: a Radiance HDR cut short (or with a zero-length
// run) makes it loop forever, and a BMP or TGA cut short decodes with its missing pixels black.
// Checked before decoding, in image_io.cpp (read_image) and image_texture.cpp (textures).
#pragma once

#include <cstddef>
#include <string>

namespace wsd::render {

// Empty when the data is complete, or is not an HDR, BMP or TGA file this check understands
// (the decoder then judges it); otherwise what is wrong, in lower case.
std::string incomplete_image_data(const unsigned char* data, size_t size);

}  // namespace wsd::render
