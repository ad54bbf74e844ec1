// The float OpenEXR writer the G-buffer and uv' files share (evaluation/src/image_io.cpp).
#pragma once
#include <map>
#include <string>
#include <vector>

namespace offsetmap {

// Interleaved float channels, zip-compressed, with string attributes in the header; throws Error
// naming `what` and the file.
void write_float_exr(const std::string& path, const std::string& what, int width, int height,
                     const std::vector<std::string>& channels, const std::vector<float>& data,
                     const std::map<std::string, std::string>& attributes = {});

}  // namespace offsetmap
