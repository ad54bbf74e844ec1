// The material frame's gather: n 32-bit words of a material's buffer (its relief, normals, albedo
// or precomputed data) into the frame's buffer from word `at`. A kernel, not a buffer copy:
// Oclgrind 21.10 takes a copy into part of a buffer for a store of the whole buffer, of the
// copy's size, and then reads the rest as uninitialised; a kernel's stores it follows word by word.
__kernel void om_gather_words(__global const uint* src, const uint n, __global uint* dst,
                              const uint at) {
    const uint i = (uint)get_global_id(0);
    if (i < n) dst[at + i] = src[i];
}
