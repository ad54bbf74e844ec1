#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/evaluate.hpp"

namespace offsetmap {

// 8-bit sRGB RGB image, row 0 at the top.
struct Rgb8 {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;
};

// Linear RGB (alpha ignored) to 8-bit sRGB.
Rgb8 to_srgb8(int width, int height, const std::vector<cl_float4>& linear);

// Heat map of non-negative values: log scale from 0 to `vmax` (values above saturate), NaN drawn
// dark grey (no data). Colours run black - purple - orange - pale yellow.
Rgb8 heat_map(int width, int height, const std::vector<float>& values, float vmax);

// Labelled images in a grid of `columns`, each tile with its label above it.
Rgb8 contact_sheet(const std::vector<std::pair<std::string, Rgb8>>& tiles, int columns);

// Writes PNG (or any format by extension); throws Error naming the file.
void write_image(const std::string& path, const Rgb8& image);

// Writes the offset pass outputs as float EXR with channels u v depth fetches flags.
void write_uv_exr(const std::string& path, const OffsetResult& result);

}  // namespace offsetmap
