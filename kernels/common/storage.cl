// Inputs in the caller's memory, as engines store them: a buffer of values in one of the
// OM_STORAGE_* forms, or a 2D image read with read_imagef, whose format does the conversion.

// Pixel (x, y) of an image, unfiltered.
__constant sampler_t om_texel_sampler =
    CLK_NORMALIZED_COORDS_FALSE | CLK_ADDRESS_CLAMP_TO_EDGE | CLK_FILTER_NEAREST;

// Element i of a buffer of `storage` known at build time (a literal 0-4, OM_STORAGE_*): straight-
// line code, with no switch for a vectoriser to stop at. The unorm and snorm forms divide as the
// OpenCL specification converts images (c / 65535, max(c / 32767, -1), ...), so a buffer and an
// image of the same format agree to the conversion's rounding.
#define OM_STORED(p, storage, i) OM_STORED_(p, storage, i)
#define OM_STORED_(p, storage, i) OM_STORED_##storage(p, i)
#define OM_STORED_0(p, i) (((__global const float*)(p))[i])
#define OM_STORED_1(p, i) vload_half((i), (__global const half*)(p))
#define OM_STORED_2(p, i) fmax((float)(((__global const short*)(p))[i]) / 32767.0f, -1.0f)
#define OM_STORED_3(p, i) ((float)(((__global const ushort*)(p))[i]) / 65535.0f)
#define OM_STORED_4(p, i) ((float)(((__global const uchar*)(p))[i]) / 255.0f)

// The same, with the storage known only at run time.
OM_INLINE float om_stored(__global const uchar* p, int storage, size_t i) {
    switch (storage) {
        case OM_STORAGE_HALF:
            return OM_STORED_1(p, i);
        case OM_STORAGE_SNORM16:
            return OM_STORED_2(p, i);
        case OM_STORAGE_UNORM16:
            return OM_STORED_3(p, i);
        case OM_STORAGE_UNORM8:
            return OM_STORED_4(p, i);
        default:
            return OM_STORED_0(p, i);
    }
}
