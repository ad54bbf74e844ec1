// The height field on the device: heights with their box-filtered mip pyramid, and normals.
#include "offsetmap/height_field.hpp"

#include <algorithm>

#include "launch.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {
namespace {

void build_mips(Runtime& rt, DeviceHeightField& f) {
    if (f.mip_levels < 2) return;
    cl::Kernel k(rt.program({"prep/mips.cl"}), "om_mip_level");
    int w = f.width, h = f.height, offset = 0;
    cl::Event done;
    for (int level = 1; level < f.mip_levels; ++level) {
        int cw = std::max(1, w / 2), ch = std::max(1, h / 2), child = offset + w * h;
        set_args(k, f.heights, offset, w, h, child, cw, ch);
        // Each level reads the one before it: chained by events (the queue may be out of order).
        std::vector<cl::Event> after;
        if (level > 1) after.push_back(done);
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(cw, ch), cl::NullRange,
                                        &after, &done);
        offset = child;
        w = cw;
        h = ch;
    }
    done.wait();
}

}  // namespace

int mip_level_count(int width, int height) {
    int levels = 1;
    while ((width > 1 || height > 1) && levels < OM_MAX_MIP_LEVELS) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        ++levels;
    }
    return levels;
}

size_t mip_pyramid_floats(int width, int height, int levels) {
    size_t total = 0;
    for (int k = 0; k < levels; ++k) {
        total += static_cast<size_t>(width) * height;
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
    }
    return total;
}

DeviceHeightField upload(Runtime& rt, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map) {
    validate_height_map(map, "height map");
    validate(settings);
    DeviceHeightField f;
    f.width = map.width;
    f.height = map.height;
    const size_t n = map.h.size();
    f.mip_levels = mip_level_count(map.width, map.height);
    const std::string size = std::to_string(map.width) + "x" + std::to_string(map.height);
    f.heights =
        device_buffer(rt.context(), CL_MEM_READ_WRITE,
                      mip_pyramid_floats(map.width, map.height, f.mip_levels) * sizeof(float),
                      "the " + size + " height pyramid");
    rt.queue().enqueueWriteBuffer(f.heights, CL_TRUE, 0, n * sizeof(float), map.h.data());
    build_mips(rt, f);
    if (normal_map) {
        if (normal_map->width != map.width || normal_map->height != map.height)
            throw Error("normal map is " + std::to_string(normal_map->width) + "x" +
                        std::to_string(normal_map->height) + " but the height map is " +
                        std::to_string(map.width) + "x" + std::to_string(map.height));
        f.normals = device_buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                  n * sizeof(cl_float4), "the " + size + " normal map",
                                  normal_map->texels.data());
        return f;
    }
    f.normals = device_buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4),
                              "the " + size + " normals");
    cl::Kernel k(rt.program(sampling_program_files("prep/normals.cl")), "om_normals");
    set_args(k, offset_params(settings, 0, map.width, map.height), f.heights, f.normals);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(map.width, map.height));
    rt.queue().finish();
    return f;
}

}  // namespace offsetmap
