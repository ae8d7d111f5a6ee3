// The single translation unit that compiles stb_image and stb_image_write (Debian's libstb-dev
// ships them header-only). Everything else includes the headers for declarations only:
// image_texture.cpp reads textures, image_io.cpp writes renders.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
// Messages a scene author can act on ("Image not of any known type, or corrupt") rather than
// stb's terse internal codes; they end up in our "cannot decode image" errors.
#define STBI_FAILURE_USERMSG

#include <stb_image.h>
#include <stb_image_write.h>
