#include "offsetmap/program_variants.hpp"

#include <algorithm>

#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/shadow_mask_pass.hpp"

namespace offsetmap {
namespace {

void add_offset_variants(std::vector<ProgramVariant>& out) {
    for (const MethodInfo& m : methods()) {
        for (int lanes : {1, 8, 16})
            for (bool images : {false, true})
                for (bool lod : {false, true})
                    for (bool outputs : {false, true}) {
                        OffsetVariant v;
                        v.lanes = lanes;
                        v.images = images;
                        v.lod = lod;
                        v.depth = v.fetches = v.flags = outputs;
                        std::string name = "offset/" + m.name + "/lanes" + std::to_string(lanes);
                        if (images) name += "-images";
                        if (lod) name += "-lod";
                        if (outputs) name += "-outputs";
                        const bool plain = lanes == 1 && !images && !lod && !outputs;
                        out.push_back(
                            {name, offset_program_files(m), offset_program_defines(m, v), plain});
                    }
        for (int lanes : {1, 8, 16})
            for (bool outputs : {false, true}) {
                OffsetVariant v;
                v.lanes = lanes;
                v.depth = v.fetches = v.flags = outputs;
                std::vector<std::string> files = offset_program_files(m);
                files.push_back("frame/tiles.cl");
                // frame/tiles.cl's sample: pom's entry (the room's materials' method).
                const bool sample = m.name == "pom" && lanes == 1 && !outputs;
                out.push_back({"tiles/" + m.name + "/lanes" + std::to_string(lanes) +
                                   (outputs ? "-outputs" : ""),
                               files, offset_program_defines(m, v, true), sample});
            }
        // Over a curved base (OM_CURVED), with every output: a GPU's path (one lane, images,
        // with the uv metric: OM_UV_METRIC) and PoCL's (16 lanes, buffers, the stretch alone),
        // per pixel and in the material frame's tiles.
        for (int lanes : {1, 16}) {
            OffsetVariant v;
            v.lanes = lanes;
            v.images = lanes == 1;
            v.curved = true;
            v.uv_metric = lanes == 1;
            v.depth = v.fetches = v.flags = true;
            const std::string at = "/lanes" + std::to_string(lanes);
            const std::string curved = v.uv_metric ? "-curved-metric-outputs" : "-curved-outputs";
            // common/curved.cl's sample: the exact walk over a curved base, a GPU's path.
            out.push_back({"offset/" + m.name + at + (v.images ? "-images" : "") + curved,
                           offset_program_files(m), offset_program_defines(m, v),
                           m.name == "exact" && lanes == 1});
            std::vector<std::string> files = offset_program_files(m);
            files.push_back("frame/tiles.cl");
            out.push_back(
                {"tiles/" + m.name + at + curved, files, offset_program_defines(m, v, true)});
        }
    }
}

void add_reconstruct_variants(std::vector<ProgramVariant>& out) {
    // Every input an image (kImageInput), or every input a buffer of one OM_STORAGE_* value.
    for (int lanes : {1, 8, 16})
        for (int storage = kImageInput; storage <= 4; ++storage)
            for (bool quaternion : {false, true})
                for (LightKind light :
                     {LightKind::None, LightKind::Directional, LightKind::Point}) {
                    // Every storage and form at one lane; at 8 and 16 the float and image forms.
                    if (lanes > 1 && storage > 0) continue;
                    const bool sample =
                        lanes == 1 && storage == 0 && !quaternion && light == LightKind::None;
                    out.push_back(
                        {"reconstruct/lanes" + std::to_string(lanes) +
                             (storage < 0 ? "-images" : "-storage" + std::to_string(storage)) +
                             (quaternion ? "-quaternion" : "") +
                             (light == LightKind::Directional ? "-lit"
                              : light == LightKind::Point     ? "-point"
                                                              : ""),
                         reconstruct_program_files(),
                         reconstruct_program_defines(lanes, {storage, storage, storage, storage},
                                                     quaternion, light),
                         sample});
                }
    // A spot light: float buffers, the normal and tangent form, at one lane and at 16.
    for (int lanes : {1, 16})
        out.push_back({"reconstruct/lanes" + std::to_string(lanes) + "-storage0-spot",
                       reconstruct_program_files(),
                       reconstruct_program_defines(lanes, {0, 0, 0, 0}, false, LightKind::Spot),
                       false});
    // The triplanar split: float buffers, each frame form, lit or not, with and without uv and
    // a tangent.
    for (int lanes : {1, 8, 16})
        for (bool quaternion : {false, true})
            for (bool lit : {false, true})
                for (bool bare : {false, true}) {
                    const int tangent = bare ? kNoInput : 0, uv = bare ? kNoInput : 0;
                    out.push_back({"reconstruct/triplanar/lanes" + std::to_string(lanes) +
                                       (quaternion ? "-quaternion" : "") + (lit ? "-lit" : "") +
                                       (bare ? "-no-uv" : ""),
                                   reconstruct_program_files(),
                                   reconstruct_program_defines(
                                       lanes, {0, 0, tangent, uv}, quaternion,
                                       lit ? LightKind::Directional : LightKind::None, true),
                                   lanes == 1 && !quaternion && !lit && !bare});
                }
}

}  // namespace

std::vector<ProgramVariant> program_variants() {
    std::vector<ProgramVariant> out;
    add_offset_variants(out);
    add_reconstruct_variants(out);
    out.push_back({"prep/mips", {"prep/mips.cl"}, "", true});
    out.push_back({"prep/unorm16", {"prep/unorm16.cl"}, "", true});
    out.push_back({"prep/normals", sampling_program_files("prep/normals.cl"), "", true});
    out.push_back({"prep/footprint", {"prep/footprint.cl"}, "", true});
    const std::vector<std::string> import = {"common/storage.cl", "prep/import.cl"};
    out.push_back({"prep/import", import, "", true});
    out.push_back({"prep/import-image", import, "#define OM_IMAGE_HEIGHTS\n"});
    std::vector<const PrecomputeSpec*> prep;  // each precompute's kernels, once
    for (const MethodInfo& m : methods())
        if (m.precompute && std::find(prep.begin(), prep.end(), m.precompute) == prep.end())
            prep.push_back(m.precompute);
    for (const PrecomputeSpec* spec : prep) {
        const std::string file = spec->prep_file;
        out.push_back({file.substr(0, file.rfind('.')), prep_program_files(*spec), "", true});
    }
    out.push_back({"frame/classify", classify_program_files(), "", true});
    out.push_back({"frame/gather", {"frame/gather.cl"}, "", true});
    out.push_back({"frame/behind", behind_program_files(), "", true});
    out.push_back({"frame/triplanar", {"frame/triplanar.cl"}, "", true});
    out.push_back(
        {"frame/depth_offset", {"common/unproject.cl", "frame/depth_offset.cl"}, "", true});
    for (int lanes : {1, 8, 16})
        out.push_back({"frame/shadow_mask/lanes" + std::to_string(lanes),
                       shadow_mask_program_files(), lanes_define(lanes), lanes == 1});
    for (int lanes : {1, 8, 16})
        for (bool materials : {false, true})
            out.push_back({std::string(materials ? "shade-materials" : "shade") + "/lanes" +
                               std::to_string(lanes),
                           shade_program_files(), shade_program_defines(lanes, materials),
                           lanes == 1});
    for (int lanes : {1, 8, 16})
        out.push_back({"bench/roofline/lanes" + std::to_string(lanes),
                       sampling_program_files("bench/roofline.cl"), lanes_define(lanes),
                       lanes == 1});
    return out;
}

}  // namespace offsetmap
