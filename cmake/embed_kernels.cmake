# Writes OUTPUT: a C++ file defining offsetmap::embedded_kernels() with the text of every file
# under KERNEL_DIR (relative path -> contents), so the library runs from any folder.
file(GLOB_RECURSE files RELATIVE "${KERNEL_DIR}" "${KERNEL_DIR}/*.cl" "${KERNEL_DIR}/*.h")
list(SORT files)
set(body "")
foreach(f IN LISTS files)
    file(READ "${KERNEL_DIR}/${f}" text)
    # Raw string literals are limited in length by some compilers; split every 8000 characters.
    string(LENGTH "${text}" n)
    set(pieces "")
    set(pos 0)
    while(pos LESS n)
        string(SUBSTRING "${text}" ${pos} 8000 piece)
        string(APPEND pieces "R\"OMKERNEL(${piece})OMKERNEL\"\n")
        math(EXPR pos "${pos} + 8000")
    endwhile()
    if(pieces STREQUAL "")
        set(pieces "\"\"")
    endif()
    string(APPEND body "        {\"${f}\", std::string(${pieces})},\n")
endforeach()
file(WRITE "${OUTPUT}.tmp" "// Generated from kernels/ by cmake/embed_kernels.cmake. Do not edit.
#include \"kernel_sources.hpp\"
namespace offsetmap {
const std::vector<std::pair<std::string, std::string>>& embedded_kernels() {
    static const std::vector<std::pair<std::string, std::string>> files = {
${body}    };
    return files;
}
}  // namespace offsetmap
")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
