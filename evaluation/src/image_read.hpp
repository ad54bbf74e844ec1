// What every image reader shares (height maps, albedo, normal maps, G-buffers): opening with the
// stored (unassociated) values, a size limit checked from the header before any pixel is
// allocated, OpenImageIO's and the decoders' messages on one line, allocation failures as Errors.
#pragma once
#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>
#include <vector>

namespace offsetmap {

// "what 'path'", the way every message names a file.
std::string describe_file(const std::string& what, const std::string& path);

// Opens the file for reading with the one reader its first bytes (else its extension) name,
// after check_exr_header; throws Error naming it when it is missing, unreadable, not an image,
// empty, or (OpenEXR) damaged or declaring more than `max_bytes` to decode.
std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path, const std::string& what,
                                             size_t max_bytes);

// OpenImageIO's name of the reader for the file: from its magic bytes (png, openexr, tiff, jpeg,
// pnm, hdr, bmp), else targa for a .tga name, else "" (a format the readers do not take).
std::string image_format(const std::string& path);

// Throws Error naming the file when decoding it would take more than `max_bytes`: the decoder's
// copy of every stored channel at its stored size, plus `kept_bytes_per_pixel` for what the reader
// keeps. Called with the header alone, before any allocation.
void check_decode_size(const OIIO::ImageSpec& spec, const std::string& path,
                       const std::string& what, size_t kept_bytes_per_pixel, size_t max_bytes);

// Reads channels [chbegin, chend) of the first image as float; throws Error naming the file.
std::vector<float> read_float_pixels(OIIO::ImageInput& in, const std::string& path,
                                     const std::string& what, int chbegin, int chend);

// A vector of n elements, or an Error naming what it was for when memory runs out.
template <typename T>
std::vector<T> allocate(size_t n, const std::string& what);

// Several lines of library messages as one: "a; b" (repeats dropped, blank lines dropped).
std::string one_line(const std::string& text);

}  // namespace offsetmap
