// offsetmap's one header that is both C++17 and OpenCL C 1.2: the structs, flags and enums the host
// and the kernels share, the launch geometry both compute, and the layout both must agree on. The
// runtime puts the library's own copy at the top of every kernel program (never a kernel folder's:
// the host was compiled against this one). Method-internal layouts live beside their methods
// (kernels/methods/*.h).
// Every member is a 4-byte scalar (or a struct of them) so the layout is identical on both sides
// without packing pragmas.
#ifndef OFFSETMAP_SHARED_H
#define OFFSETMAP_SHARED_H

// OpenCL C defines __OPENCL_C_VERSION__ (1.2 and later); __OPENCL_VERSION__ is the platform's,
// which an offline compiler (clang for SPIR-V) leaves undefined.
#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)
#define OM_OPENCL_C 1
#endif

#ifdef OM_OPENCL_C
typedef float om_float;
typedef int om_int;
typedef uint om_uint;
#else
#include <cstddef>
#include <cstdint>
typedef float om_float;
typedef std::int32_t om_int;
typedef std::uint32_t om_uint;
#endif

#define OM_MAX_METHOD_PARAMS 8
// A method parameter by name: the host defines OM_SLOT_<name> from the method's registry row
// (param_slot_defines), so no kernel indexes a parameter by position.
#define OM_PARAM(P, name) ((P)->p[OM_SLOT_##name])

// Per-pixel flags written by the offset pass (bit set).
#define OM_FLAG_EMPTY 1u          // u or v is NaN: no surface at this pixel; uv passed through
#define OM_FLAG_INVALID 2u        // non-finite V, zero V or infinite uv; uv passed through
#define OM_FLAG_BACKFACING 4u     // V.z <= 0 after normalisation; uv passed through
#define OM_FLAG_GRAZING 8u        // V.z was raised to min_vz (the grazing rule)
#define OM_FLAG_RENORMALIZED 16u  // |V| differed from 1 by more than 1e-3 and was normalised
#define OM_FLAG_CAPPED 32u        // a marching loop reached its iteration cap
#define OM_FLAG_LOD_FADED 64u     // past the LOD threshold: normal mapping only (uv' = uv)
#define OM_FLAG_OUT_OF_TILE 128u  // tile mask on and uv' outside [0,1]^2: discard (a silhouette)
// Over a curved base (the curvature plane), the ray left the relief's slab through its top before
// meeting the relief: nothing of this surface is seen here (a silhouette); uv' is where it left.
#define OM_FLAG_SILHOUETTE 256u
// The flags under which the pixel shows nothing of its G-buffer surface: the shade pass gives it
// the background, an engine fills it (or a second G-buffer layer does).
#define OM_FLAGS_NOT_SHOWN (OM_FLAG_EMPTY | OM_FLAG_OUT_OF_TILE | OM_FLAG_SILHOUETTE)
// Where the relief dropped its own surface (not where there is none), a second G-buffer layer
// shows what lies behind; a pixel that took the second layer's surface and result is BEHIND.
#define OM_FLAGS_SEE_BEHIND (OM_FLAG_OUT_OF_TILE | OM_FLAG_SILHOUETTE)
#define OM_FLAG_BEHIND 512u

// Enums, one definition each for host and device: the kernels and the shared structs use the OM_*
// constants (as om_int), the host's enum classes take their values from them.
enum { OM_ADDRESS_WRAP = 0, OM_ADDRESS_CLAMP = 1 };  // height addressing: tiling, or edge texels
// The grazing rule (core/src/grazing.cpp): views below min_vz raised to it (clamp); Welsh's offset
// limiting, rays along normalize(V.xy, 1) (limit); min_vz raised so that no footprint passes
// max_offset_texels (cap).
enum { OM_GRAZING_CLAMP = 0, OM_GRAZING_LIMIT = 1, OM_GRAZING_CAP = 2 };
enum { OM_SHADOW_NONE = 0, OM_SHADOW_HARD = 1, OM_SHADOW_SOFT = 2 };  // the relief's self-shadows

// The offset entry's lane groups are blocks of the G-buffer image: 4 x 4 pixels for 16 lanes, 4 x 2
// for 8, one pixel for 1; blocks are numbered row by row, ceil(width / w) to a row.
#define OM_BLOCK_W(lanes) ((lanes) == 1 ? 1 : 4)
#define OM_BLOCK_H(lanes) ((lanes) / OM_BLOCK_W(lanes))
// Blocks covering a width x height image.
static inline int om_image_blocks(int width, int height, int lanes) {
    return ((width + OM_BLOCK_W(lanes) - 1) / OM_BLOCK_W(lanes)) *
           ((height + OM_BLOCK_H(lanes) - 1) / OM_BLOCK_H(lanes));
}

typedef struct {
    om_int gb_width;  // G-buffer width and height in pixels (0 x 0 outside the offset pass)
    om_int gb_height;
    om_int hf_width;          // height-field texels along u
    om_int hf_height;         // height-field texels along v
    om_int address_mode;      // OM_ADDRESS_*
    om_float scale;           // depth scale s, in uv units
    om_float ref_plane;       // reference plane r in [0,1]: the polygon sits at height r
    om_float min_vz;          // grazing rule: V.z is raised to at least this (sin of min elevation)
    om_int max_cells;         // hard cap on cells or steps any marching loop may visit
    om_int mip_levels;        // levels in the height buffer: level 0, then each half the size
    om_float lod_threshold;   // mip level at and past which the pass is plain normal mapping
    om_float lod_fade;        // levels below the threshold over which the effect fades out
    om_float lod_min_detail;  // step-count factor at the threshold (1 at level 0)
    om_int grazing;           // OM_GRAZING_*: the policy (min_vz already holds cap's raise)
    om_int tile_mask;         // flag OM_FLAG_OUT_OF_TILE where uv' leaves the tile:
    om_float tile_u0;         // u in [tile_u0, tile_u1], v in [tile_v0, tile_v1] (+-FLT_MAX: open)
    om_float tile_v0;
    om_float tile_u1;
    om_float tile_v1;
    om_int lod_footprint;  // LOD mode: steps from the texels crossed, fade over a texel range
    om_float lod_fade_lo;  // footprint mode: texels crossed at which the effect is gone
    om_float lod_fade_hi;  // footprint mode: texels crossed from which it is whole
    // 0, or where the heights' packed unorm16 words start (in words after the height pointer):
    // one per texel of every level, texel (i, j) low and (i, j + 1) high (HeightStorage::Unorm16).
    om_int packed_heights;
    om_float p[OM_MAX_METHOD_PARAMS];  // method parameters: read with OM_PARAM(P, name)
} OmOffsetParams;

// The engine-shaped G-buffer (offsetmap/engine_gbuffer.hpp) and heights in the caller's memory:
// how a buffer stores its values (images carry their own format), the depth buffer's convention,
// the tangent frame's form and the light.
enum {
    OM_STORAGE_FLOAT = 0,
    OM_STORAGE_HALF = 1,
    OM_STORAGE_SNORM16 = 2,  // max(c / 32767, -1)
    OM_STORAGE_UNORM16 = 3,  // c / 65535
    OM_STORAGE_UNORM8 = 4    // c / 255
};
// Window depth d: GL, NDC z = 2d - 1 and the far plane at d = 1; zero-one (D3D, Vulkan, GL with
// glClipControl), NDC z = d, far at 1; reversed (zero-one with near and far swapped), far at 0.
enum { OM_DEPTH_GL = 0, OM_DEPTH_ZERO_ONE = 1, OM_DEPTH_REVERSED = 2 };
enum { OM_FRAME_NORMAL_TANGENT = 0, OM_FRAME_QUATERNION = 1 };
enum { OM_LIGHT_NONE = 0, OM_LIGHT_DIRECTIONAL = 1, OM_LIGHT_POINT = 2, OM_LIGHT_SPOT = 3 };

typedef struct {
    om_int width, height;
    om_float inv_view_proj[16];  // NDC -> world, column-major: row r, column c at [4 c + r]
    om_float eye[3];             // world position of the eye
    om_float depth_scale;        // NDC z = depth_scale d + depth_offset: 2, -1 (GL); 1, 0
    om_float depth_offset;
    om_float far_depth;     // d at the far plane: 1, or 0 (reversed)
    om_float far_sign;      // sky where far_sign (d - far_depth) >= 0: +1, or -1 (reversed)
    om_float row0_ndc_y;    // NDC y of pixel row 0's edge: +1 (D3D) or -1 (GL, Vulkan)
    om_float light_vec[3];  // world direction toward the light (unit), or its position
    // 1: eye is a position (a perspective view); 0: an orthographic view (a directional light's),
    // eye the direction toward the viewer. V = eye - eye_w p, normalized.
    om_float eye_w;
    // A spot light (OM_SPOT_LIGHT): the unit world direction it shines along, and the cosines of
    // its cone's half-angles, where it fades out and where it is whole.
    om_float light_axis[3];
    om_float cone_cos_outer, cone_cos_inner;
} OmReconstructParams;

// A frame's pixels as a kernel that unprojects them (kernels/common/unproject.cl) or projects
// into them reads them: the size and the engine camera's conventions (EngineCamera's depth and
// first row), from the host's pixel_grid.
typedef struct {
    om_int width, height;
    om_float depth_scale, depth_offset;  // NDC z = depth_scale d + depth_offset: 2, -1 (GL); 1, 0
    om_float ndc_depth_scale, ndc_depth_offset;  // and back: d = ndc_depth_scale z + ..._offset
    om_float far_depth;   // d at the far plane: 1, or 0 (reversed)
    om_float far_sign;    // sky where far_sign (d - far_depth) >= 0: +1, or -1 (reversed)
    om_float row0_ndc_y;  // NDC y of pixel row 0's edge: +1 (top first) or -1 (bottom first)
} OmPixelGrid;

// The rendered frame's pixel depth offset (kernels/frame/depth_offset.cl), in the camera's
// conventions; a work-item takes OM_DEPTH_RUN pixels of a row.
#define OM_DEPTH_RUN 16
typedef struct {
    OmPixelGrid grid;
    om_float view_proj[16];      // world -> clip, column-major: row r, column c at [4 c + r]
    om_float inv_view_proj[16];  // NDC -> world, the same layout
    om_float eye[3];             // world position of the eye, or (eye_w 0) direction toward it
    om_float eye_w;              // as OmReconstructParams's: 1 a position, 0 orthographic
} OmDepthOffsetParams;

// The receivers' shadow test (kernels/frame/shadow_mask.cl): each pixel's point after the depth
// offset against the light's displaced shadow map (its view orthographic or perspective), each in
// its own camera's conventions. The receiver's plane through the point and its neighbours in the
// frame gives its depth at each tap's texel centre, so a lit plane compares with itself at any
// light angle; the slack allows for what is not planar over a texel.
typedef struct {
    OmPixelGrid frame;             // the camera's frame
    OmPixelGrid map;               // the light's shadow map
    om_float inv_view_proj[16];    // the camera's NDC -> world, column-major
    om_float light_view_proj[16];  // world -> the light's clip space, column-major
    om_float slack_texels;         // lit within the plane's depth change over this many texels
    om_float slack_depth;          // and this much window depth (the float rounding of points)
    om_int pcf_radius;             // (2 r + 1)^2 taps around the point's texel
} OmShadowMaskParams;

// A unorm16 height's value, as OpenImageIO converts 16-bit files (a product, not c / 65535: the
// two differ in the last bit for 512 of the 65536 values), so a 16-bit map rounds to itself.
#define OM_UNORM16_STEP (1.0f / 65535.0f)

// Dimensions of mip level k of a W x H map: each level halves (rounding down, at least 1).
#define OM_MAX_MIP_LEVELS 16

typedef struct {
    om_int gb_width, gb_height;  // the G-buffer's pixels, shaded in blocks (om_image_blocks)
    om_int hf_width;
    om_int hf_height;
    om_int address_mode;
    om_float light_x, light_y, light_z;  // global tangent-space light (used without per-pixel L)
    om_int has_light;                    // 1: read light_ts per pixel from the G-buffer
    om_float ambient, diffuse, specular, shininess;
    om_int has_albedo;  // 0: neutral procedural checker
    om_int albedo_width, albedo_height;
    om_int shadow_mode;                 // OM_SHADOW_*
    om_int shadow_steps;                // samples along the light ray
    om_float light_size;                // soft shadows: the light's angular diameter (radians)
    om_float scale, ref_plane, min_vz;  // the relief and the grazing rule, as in OmOffsetParams
    om_int grazing;                     // OM_GRAZING_*: the light's march obeys the view's rule
} OmShadeParams;

// The material frame (offsetmap/material_frame.hpp): the screen in tiles of OM_TILE_W x tile_h
// pixels (OM_TILE_W a multiple of every block's width, so a tile holds whole blocks), each
// classified by the materials it holds into one entry (tile, material slot) per material present,
// appended to the list of that material's method. Slots index the frame's material table (at most
// OM_MAX_MATERIALS: a tile's materials fit one 32-bit mask).
#define OM_TILE_W 16
#define OM_MAX_MATERIALS 32

// A tile's lane groups are blocks as in the offset entry, but no taller than the tile: the tallest
// power of two up to OM_BLOCK_H rows, so a block row stays a multiple of 4 pixels and divides
// OM_TILE_W. Blocks are numbered row by row within the tile; the last row of blocks may be cut.
static inline int om_tile_block_h(int lanes, int tile_h) {
    int h = OM_BLOCK_H(lanes);
    while (h > 1 && h > tile_h) h /= 2;
    return h;
}
static inline int om_tile_blocks(int lanes, int tile_h) {
    const int h = om_tile_block_h(lanes, tile_h);
    return OM_TILE_W / (lanes / h) * ((tile_h + h - 1) / h);
}

typedef struct {
    om_int width, height;  // the G-buffer
    om_int tile_h;         // tile rows
    om_int tiles_x;        // tiles per row of tiles
    om_int tile_count;
    om_int slot_count;    // materials in the table
    om_int method_count;  // method dispatches (distinct methods in the table)
    om_int id_limit;      // the id -> slot table's length (largest id + 1)
    om_int entry_base;    // tile entry: the dispatched method's first entry
    om_int entry_count;   // and how many it has
    om_int pass_through;  // 1: id 0's pixels get uv' = uv (and depth 0, no fetches); 0: nothing
} OmTileParams;

typedef struct {
    OmOffsetParams P;       // the material's pass parameters, its method's included
    om_int id;              // its material id (>= 1)
    om_int heights_offset;  // its pyramid's first float in the frame's heights buffer
    om_int aux_offset;      // its precomputed data's first float in its method's aux buffer
    om_int method;          // its method's dispatch
    OmShadeParams shade;    // its shading (the G-buffer's size unused)
    om_int normals_offset;  // its normals' first float4 in the frame's normals buffer
    om_int albedo_offset;   // its albedo's first float4 in the frame's albedo buffer
} OmMaterialSlot;

// The layout host and device must agree on: the host uploads these structs as raw bytes (kernel
// arguments, the material frame's slot table). Every member is a 4-byte scalar (or a struct of
// them), so neither side pads; a member that breaks the rule (a vector, a double, a pointer, a
// bool) or a field added without updating this list fails the host's build (size and the last
// member's offset) and every kernel program's (size: C99 has no static assertion, and offsetof is
// not OpenCL C 1.2's), rather than uploading shifted fields. Sizes and offsets in bytes.
#define OM_LAYOUT_CHECKS(CHECK)                          \
    CHECK(OmOffsetParams, 124, p, 92)                    \
    CHECK(OmReconstructParams, 140, cone_cos_inner, 136) \
    CHECK(OmPixelGrid, 36, row0_ndc_y, 32)               \
    CHECK(OmDepthOffsetParams, 180, eye_w, 176)          \
    CHECK(OmShadowMaskParams, 212, pcf_radius, 208)      \
    CHECK(OmShadeParams, 92, grazing, 88)                \
    CHECK(OmTileParams, 44, pass_through, 40)            \
    CHECK(OmMaterialSlot, 240, albedo_offset, 236)
#ifdef OM_OPENCL_C
// An array of negative size does not compile.
#define OM_LAYOUT_CHECK(S, size, last, at) \
    typedef char om_layout_of_##S[sizeof(S) == (size) ? 1 : -1];
#else
#define OM_LAYOUT_CHECK(S, size, last, at)                          \
    static_assert(sizeof(S) == (size) && offsetof(S, last) == (at), \
                  #S "'s layout is not the one OM_LAYOUT_CHECKS records");
#endif
OM_LAYOUT_CHECKS(OM_LAYOUT_CHECK)

#endif
