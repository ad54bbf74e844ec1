// The evaluation library from the package: a scene written as a G-buffer file and read back.
#include <cstdio>
#include <filesystem>

#include "offsetmap/evaluation.hpp"

int main() {
    using namespace offsetmap;
    try {
        const auto path = std::filesystem::temp_directory_path() / "om_package_gbuffer.exr";
        GBuffer gb = make_scene(RandomScene{8, 4, 3, 10.0, 90.0});
        save_gbuffer(path.string(), gb);
        GBuffer back = load_gbuffer(path.string());
        std::filesystem::remove(path);
        if (back.width != 8 || back.height != 4 || back.uv[5].s[0] != gb.uv[5].s[0]) {
            std::fprintf(stderr, "consumer_evaluation: the G-buffer did not round-trip\n");
            return 1;
        }
        std::printf("consumer_evaluation: a G-buffer file written and read back\n");
        return 0;
    } catch (const Error& e) {
        std::fprintf(stderr, "consumer_evaluation: %s\n", e.what());
        return 1;
    }
}
