// The bundle's build only (see glibc_floor.h). GCC 12's static libstdc++ links std::random_device
// (its mt19937 instances share random.o with it) and so glibc 2.36's arc4random, which the check
// never calls: this definition satisfies the link without raising the glibc it needs.
#include <cstdint>
#include <cstdio>

extern "C" std::uint32_t arc4random(void) {
    std::uint32_t x = 0;
    if (std::FILE* f = std::fopen("/dev/urandom", "rb")) {
        if (std::fread(&x, sizeof x, 1, f) != 1) x = 0;
        std::fclose(f);
    }
    return x;
}
