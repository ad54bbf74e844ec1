#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/evaluate.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/scenes.hpp"

namespace offsetmap {

// Reading (OpenImageIO): height maps, albedo and normal maps, G-buffer files.

// Every reader checks, from the file's header and before allocating any pixel, that decoding it
// (the decoder's copy of every stored channel at its stored size, plus what the reader keeps)
// stays within this many bytes, and throws Error naming the file and the limit otherwise.
inline constexpr size_t kDefaultReadLimitBytes = size_t(2) << 30;

struct HeightLoadOptions {
    int channel = 0;         // which channel of the image holds the heights
    bool depth_map = false;  // the file stores depth (white = deep): H = 1 - value
    size_t max_bytes = kDefaultReadLimitBytes;
};

// Loads a PNG (8/16-bit), OpenEXR, TIFF, JPEG, PNM/PFM, Radiance HDR, BMP or Targa image (the
// format named by the file's first bytes, else a .tga name) through OpenImageIO as stored: alpha is
// never multiplied in (a grey+alpha PNG gives its grey values). Integer formats map to [0,1];
// float values outside [0,1] are clamped (counted in `clamped`). Throws Error naming the file for
// a missing, unreadable, truncated, empty or too large image, a missing channel, or non-finite
// heights.
HeightMap load_height_map(const std::string& path, const HeightLoadOptions& options = {});

// Loads an image as float4 (missing channels: 0, alpha 1; colour as stored, alpha not multiplied
// in). Throws Error naming the file.
Image4 load_image4(const std::string& path, size_t max_bytes = kDefaultReadLimitBytes);

// Tangent-space normals from a normal-map file: rgb in [0,1] -> [-1,1], optional green flip
// (DirectX-authored maps store -y), renormalised.
Image4 load_normal_map(const std::string& path, bool flip_green,
                       size_t max_bytes = kDefaultReadLimitBytes);

// Reads an OpenEXR G-buffer with channels u v Vx Vy Vz and optionally Lx Ly Lz (all three) and lod,
// each stored as half or float; or one in the engine form (channel depth; save_engine_gbuffer),
// which is reconstructed on `runtime` (a runtime of its own when null) as the reconstruct pass does
// it in a frame. Throws Error naming the file and the missing or mistyped channels or attributes,
// or the size limit (kMaxGBufferPixels, `max_bytes`) it exceeds.
GBuffer load_gbuffer(const std::string& path, size_t max_bytes = kDefaultReadLimitBytes,
                     std::shared_ptr<Runtime> runtime = nullptr);

// The engine form of a G-buffer file: float channels depth, Nx Ny Nz Tx Ty Tz Tw (or Qx Qy Qz Qw)
// and u v, and the camera and light as header attributes (offsetmap:inverseViewProjection, 16
// numbers column-major; offsetmap:eye, 3; offsetmap:depth, gl | zero-one | reversed;
// offsetmap:firstRow, top | bottom; offsetmap:light, "directional x y z" or "point x y z").
// Optional channels: material (ids), dudx dvdx dudy dvdy (uv derivatives) and kuu kuv kvv (the
// base surface's curvature in uv units, EngineScene::curvature; all three or none, finite) with
// stretch beside them (EngineScene::uv_stretch, finite).
void save_engine_gbuffer(const std::string& path, const EngineScene& scene);
EngineScene load_engine_gbuffer(const std::string& path, size_t max_bytes = kDefaultReadLimitBytes);

// While on, the readers send what image decoders write straight to the process's stderr (libpng
// prints its errors before OpenImageIO reports them) to /dev/null for the duration of each read, so
// that a bad file gives one message, the Error's. Off by default; the CLI turns it on.
void quiet_decoders(bool quiet);

// Writes the G-buffer as float OpenEXR with the channel names above.
void save_gbuffer(const std::string& path, const GBuffer& gbuffer);

// Writing.

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

// Labelled images in a grid of `columns`, each tile with its label above it; tiles narrower than
// 560 pixels are enlarged by a whole factor (nearest texel) so that their labels fit.
Rgb8 contact_sheet(const std::vector<std::pair<std::string, Rgb8>>& tiles, int columns);

// Writes PNG (or any format by extension); throws Error naming the file.
void write_image(const std::string& path, const Rgb8& image);

// Writes the offset pass outputs as float EXR with channels u v depth fetches flags.
void write_uv_exr(const std::string& path, const OffsetResult& result);
// Interleaved float channels, zip-compressed, with string attributes in the header (the writer
// the G-buffer and uv' files share); throws Error naming `what` and the file.
void write_float_exr(const std::string& path, const std::string& what, int width, int height,
                     const std::vector<std::string>& channels, const std::vector<float>& data,
                     const std::map<std::string, std::string>& attributes = {});

}  // namespace offsetmap
