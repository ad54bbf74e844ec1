// A check of an OpenEXR file's header before OpenEXR opens it: OpenEXR allocates what the header
// declares (an attribute's value, the chunk offset table) before it reads it, so a damaged header
// that declares gigabytes costs gigabytes before any of the readers' size checks can run.
#pragma once
#include <cstddef>
#include <string>

namespace offsetmap {

// When `path` holds an OpenEXR file: throws Error naming the file (`what 'path'`) when an
// attribute declares more bytes than the file holds after it, or the chunk offset table its data
// window implies (8 bytes a chunk) is larger than the file, or when decoding its data window (its
// channels at their stored sizes) would take more than `max_bytes` (OpenEXR's line buffers are
// sized by it when the file is opened). Files that are not OpenEXR pass.
void check_exr_header(const std::string& path, const std::string& what, size_t max_bytes);

}  // namespace offsetmap
