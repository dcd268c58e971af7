// stb_image's implementation, once for the whole test binary (PNG checks of GUI screenshots and
// rendered images).
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
